// A generated test case for parametric drivers (the `cagewrap patch demo` files and the patch bench):
// a slab of skin around a wavy B-spline sheet, and the analytic twist about the sheet's long axis
// (core/deform/twist.h) that the bench holds the deformed skin to.
#pragma once

#include <cstdint>

#include "core/geometry/mesh.h"
#include "core/deform/patch_surface.h"
#include "core/deform/twist.h"

namespace cagewrap {

struct PatchDemo {
  PolyMesh skin;        // two triangulated sheets, 0.3 above and below the driver (open at the rim)
  PatchSurface driver;  // one 6 x 12 clamped bicubic B-spline grid, x in [0, 11], z in [0, 5]
  Twist twist;          // 90 degrees about the x axis through the sheet's middle, smoothstep along x
};

// `resolution`: skin vertices per unit length (the skin has about 2 * 55 * resolution^2 vertices).
PatchDemo make_patch_demo(uint32_t resolution);

// The driver with the twist applied to its control points.
PatchSurface twisted(const PatchSurface& driver, const Twist& twist);

}  // namespace cagewrap
