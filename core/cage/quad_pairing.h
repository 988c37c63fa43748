// Quads from a triangle mesh: adjacent triangle pairs that are nearly coplanar and together form a
// convex, well-shaped quadrilateral are merged, best pairs first (greedy matching), so the cage the
// artist sees and edits has fewer, more regular faces (the paper, section 5: the user keeps seeing
// polygons; the deformer triangulates them back into the same control elements).
//
// A quad is written starting at a corner off the shared edge, (w2, v, w1, u) for the triangles
// (u, v, w1) and (v, u, w2), so that triangulate() (mesh.h) splits it along the edge it was merged
// across and the control elements are exactly the input triangles.
#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <span>

#include "core/geometry/mesh.h"

namespace cagewrap {

struct QuadPairingParams {
  double max_bend = 20.0;    // degrees between the two triangles' normals
  double min_angle = 40.0;   // degrees: every corner of the quad at least this ...
  double max_angle = 140.0;  // ... and at most this (below 180: convex)
};

struct QuadPairing {
  PolyMesh mesh;  // the input vertices; quads and the triangles left unpaired
  uint32_t quads = 0;
  uint32_t triangles = 0;  // faces left as triangles
};

// positions #V x 3, triangles #T x 3 (consistently oriented; an edge shared by more than two
// triangles is never merged across). Pairs are ranked by their worst corner's distance from 90
// degrees plus the bend; deterministic.
QuadPairing pair_quads(std::span<const glm::vec3> positions, std::span<const Tri> triangles,
                       const QuadPairingParams& params = {});

}  // namespace cagewrap
