// Making a parametric driver from a cage: a bicubic B-spline grid fitted to selected cage faces.
//
// The selection must be a rectangle of quads (R x C faces meeting edge to edge, like a patch of a
// quad mesh). Its (R + 1) x (C + 1) vertices get the parameters (j / C, i / R) scaled to the
// B-spline's domain, and the control points are the least-squares fit to them: one direction after
// the other (exact tensor-product least squares), with a small second-difference smoothing term so
// that narrow selections (one or two faces across, fewer vertices than control points) still give
// a well-posed, even grid.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/geometry/mesh.h"
#include "core/deform/patch_surface.h"

namespace cagewrap {

// The selected quads as a grid: vertex (i, j) for i in [0, rows], j in [0, cols].
struct QuadGrid {
  uint32_t rows = 0, cols = 0;     // faces along v, along u
  std::vector<uint32_t> vertices;  // (rows + 1) x (cols + 1) cage vertex ids, row-major
  std::vector<uint32_t> faces;     // rows x cols cage face ids, row-major
};
// Errors (kInvalidArgument), naming the face: an empty selection, a face out of range, a face that
// is not a quad, faces that do not form one rectangle of quads (a hole, an L shape, a ring, a face
// not reached from the others).
Result<QuadGrid> quad_grid_of_faces(const PolyMesh& cage, std::span<const uint32_t> faces);

struct PatchFitOptions {
  uint32_t rows = 0, cols = 0;  // control points along v, u; 0 = one per vertex line, at least 4
  double smoothing = 1e-3;      // weight of the second differences of the control points
};

// A clamped uniform bicubic B-spline fitted to the grid's vertices (at positions `positions`, #V).
Result<PatchGrid> fit_patch_to_faces(const PolyMesh& cage, std::span<const glm::vec3> positions,
                                     std::span<const uint32_t> faces, const PatchFitOptions& options = {});

}  // namespace cagewrap
