// Subdividing the cage to add control elements (paper section 5, step 1: "subdivide triangles in
// problem regions"): uniformly, linear or Loop, and locally, red-green refinement of selected faces.
// Each returns the new cage and the CageTopologyChange that carries offsets, set edits and
// attachments across (core/document/topology_change.h).
//
// This work is based on:
//   C. Loop, "Smooth Subdivision Surfaces Based on Triangles", MSc thesis, University of Utah, 1987
//   (the stencils, with Loop's beta; boundary and crease rules as in H. Hoppe et al., "Piecewise
//   Smooth Surface Reconstruction", SIGGRAPH 1994).
//   R. E. Bank, A. H. Sherman, A. Weiser, "Refinement Algorithms and Data Structures for Regular Local
//   Mesh Refinement", Scientific Computing, 1983 (red-green refinement).
#pragma once

#include <cstdint>
#include <span>

#include "core/cage/cage.h"
#include "core/base/result.h"
#include "core/document/topology_change.h"

namespace cagewrap {

inline constexpr uint32_t kMaxSubdivisionLevels = 6;  // each level multiplies the faces by about 4

// Linear (midpoint) subdivision, `levels` times (1..kMaxSubdivisionLevels): a triangle becomes 4
// triangles through its edge midpoints, every other polygon becomes one quad per corner through its
// edge midpoints and its centroid (the mean of its corners). New vertices lie on the old polygons'
// edges and at their centroids, so the shape is kept (exactly for planar polygons). Errors: bad
// levels, an invalid cage (validate_mesh).
Result<CageEdit> subdivide_linear(const Cage& cage, uint32_t levels = 1);

// What Loop subdivision does with a polygon that is not a triangle.
enum class LoopNonTriangles : uint8_t {
  kTriangulate,  // split into the cage's control elements first (triangulate_cage), then subdivide
  kReject,       // error "face 12 is not a triangle"
};

// Loop subdivision, `levels` times: every triangle becomes 4; old vertices move to
// (1 - n beta) v + beta sum(neighbours), beta = (5/8 - (3/8 + cos(2 pi / n) / 4)^2) / n, new edge
// vertices to 3/8 (a + b) + 1/8 (c + d). Edges with one face or more than two are creases: a crease
// edge's vertex is its midpoint, a vertex on exactly two crease edges moves to 3/4 v + 1/8 (a + b),
// and one on one or more than two crease edges stays. All weights are positive, so every new vertex
// is a convex combination of old ones. Errors: bad levels, an invalid cage, a non-triangle with
// kReject.
Result<CageEdit> subdivide_loop(const Cage& cage, uint32_t levels = 1,
                                LoopNonTriangles non_triangles = LoopNonTriangles::kTriangulate);

// Red-green refinement of the selected polygons: each is split as in subdivide_linear ("red"), and
// neighbours are split so that no T-junction remains, repeated until every face conforms:
//   triangle with 1 split edge  -> 2 triangles, bisected from the midpoint to the opposite corner (green)
//   triangle with 2 or 3        -> red (4 triangles)
//   quad with 1 split edge      -> 3 triangles from the midpoint (green)
//   quad with 2 opposite ones   -> 2 quads
//   quad with 2 adjacent or 3   -> red (4 quads)
//   larger polygon with any     -> red (one quad per corner)
// So a quad in the selection becomes 4 quads and its neighbours conform. Untouched faces keep their
// corners (and their order among the output faces: every face's children follow in input order).
// Errors: no face given, an id out of range ("face 12 out of range: ..."), an invalid cage.
Result<CageEdit> refine_faces(const Cage& cage, std::span<const uint32_t> faces);

}  // namespace cagewrap
