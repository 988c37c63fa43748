// Parametric drivers: a driver surface made of bicubic patches instead of a polygon cage.
//
// This work is based on:
//   K. Singh and E. Kokkevis, "Skinning Characters using Surface-Oriented Free-Form Deformations",
//   Graphics Interface 2000, section 3.3 (last paragraph): for a parametric driver the control
//   elements are samples of the surface at its knot values, each with the frame
//   e1 = dS/du, e2 = dS/dv, e3 = the unit normal (../shared/docs/algorithm.md, docs/parametric-drivers.md).
//   Basis functions: L. Piegl and W. Tiller, "The NURBS Book", chapter 2 (uniform cubic B-splines,
//   clamped knot vectors) and chapter 1 (cubic Bernstein polynomials).
//
// A PatchGrid is a rows x cols grid of control points of one bicubic surface:
// - kBSpline: a uniform cubic B-spline, clamped (open) at both ends in both directions, so it starts
//   and ends at the corner control points. n control points along a direction give n - 3 spans and
//   the knot values 0, 1, ..., n - 3 (the parameter domain [0, n - 3]). n >= 4.
// - kBezier: piecewise bicubic Bezier patches sharing their boundary rows: n = 3 m + 1 control
//   points give m patches along a direction and the knot values 0, 1, ..., m. n >= 4.
// u runs along a row (the column index c), v down the columns (the row index r).
#pragma once

#include <array>
#include <cstdint>
#include <glm/vec3.hpp>
#include <span>
#include <string>
#include <vector>

#include "core/base/result.h"

namespace cagewrap {

enum class PatchBasis : uint8_t { kBSpline = 0, kBezier = 1 };
const char* patch_basis_name(PatchBasis b);
bool parse_patch_basis(const std::string& s, PatchBasis& out);

struct PatchGrid {
  PatchBasis basis = PatchBasis::kBSpline;
  uint32_t rows = 0;               // control points along v
  uint32_t cols = 0;               // control points along u
  std::vector<glm::dvec3> points;  // rows x cols, row-major: points[r * cols + c]

  const glm::dvec3& at(uint32_t r, uint32_t c) const { return points[size_t(r) * cols + c]; }
  bool operator==(const PatchGrid&) const = default;
};

// The driver: one or more grids. Their control points are numbered grid by grid (global index =
// the sum of the earlier grids' sizes + the index inside the grid).
struct PatchSurface {
  std::vector<PatchGrid> grids;
  size_t num_control_points() const;
  // All control points, grid by grid (#C x 3), and the inverse.
  std::vector<glm::dvec3> control_points() const;
  void set_control_points(std::span<const glm::dvec3> points);  // #C; checked
  bool operator==(const PatchSurface&) const = default;
};

// A driver as a document holds it (core/document/document.h, saved in projects as "patch_driver"): the rest
// grids the skin is bound to, the sampling density, the posed control points (the same grids, moved)
// and whether it drives the skin in place of the cage.
struct PatchDriver {
  PatchSurface rest;
  PatchSurface posed;
  uint32_t density = 2;
  bool drive_skin = true;
  bool operator==(const PatchDriver&) const = default;
};

// The control net's edges as pairs of global control point indices (rows, then columns, grid by
// grid), for display.
std::vector<std::array<uint32_t, 2>> control_net_edges(const PatchSurface& surface);

// Spans along a direction with n control points (B-spline: n - 3; Bezier: (n - 1) / 3).
uint32_t patch_spans(PatchBasis basis, uint32_t n);

// Checks the grid sizes (>= 4 each; Bezier: 3 m + 1) and that every control point is finite. Messages
// name `what` (a file), the grid and the control point (row and column).
Status validate_patch_surface(const PatchSurface& surface, const std::string& what);

// One cubic basis along a direction at parameter t in [0, spans]: the first control point index and
// the four basis values and first derivatives (d/dt).
struct CubicBasis {
  uint32_t first = 0;
  double value[4]{};
  double deriv[4]{};
};
CubicBasis cubic_basis(PatchBasis basis, uint32_t n, double t);

// A point of the surface and its tangents dS/du, dS/dv.
struct SampleFrame {
  glm::dvec3 position{0.0};
  glm::dvec3 du{0.0}, dv{0.0};
};
using PatchPoint = SampleFrame;
// S(u, v) and its tangents; u in [0, spans along u], v in [0, spans along v] (clamped to the domain).
PatchPoint evaluate(const PatchGrid& grid, double u, double v);

// Control elements (section 3.3): samples at the knot values, each span cut into `density` equal
// steps, so a grid with su x sv spans gives (su * density + 1) x (sv * density + 1) samples. Density 1
// samples the knot values themselves. Samples are numbered grid by grid, row (v) by row, u fastest.
struct PatchSample {
  uint32_t grid = 0;
  double u = 0.0, v = 0.0;
  // sparse stencil of the sample on the grid's control points: S = sum w P, S_u = sum wu P, S_v = sum wv P
  uint32_t first_row = 0, first_col = 0;
  double w[16]{}, wu[16]{}, wv[16]{};  // 4 x 4, row-major (row offset, column offset)
};
// The most samples a driver may have (all grids): 150,000 control elements, far more than any skin needs,
// and at 412 bytes each under 64 MB (issue 19: a small file must not ask for more).
inline constexpr uint64_t kMaxPatchSamples = 150000;
// Errors: density 0 (or above 1024), more than kMaxPatchSamples samples, a surface validate_patch_surface
// refuses.
Result<std::vector<PatchSample>> sample_patch_surface(const PatchSurface& surface, uint32_t density);
// Samples a surface with the given control points (grid by grid, #C) would have: a sample and its frame.
SampleFrame sample_frame(const PatchSurface& surface, const PatchSample& sample);

}  // namespace cagewrap
