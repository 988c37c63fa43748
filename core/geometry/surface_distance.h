// Signed distance from points to a triangle surface: positive outside, negative inside. The sign
// comes from the angle-weighted pseudonormal of the closest feature (face, edge or vertex), which
// is exact for a closed, consistently oriented 2-manifold; on an open surface it tells the side
// of the nearest sheet.
//
// This work is based on: Baerentzen and Aanaes, "Signed Distance Computation Using the Angle
// Weighted Pseudonormal" (IEEE TVCG 2005); Jacobson et al., "Robust Inside-Outside Segmentation
// using Generalized Winding Numbers" (SIGGRAPH 2013); Van Oosterom and Strackee, "The Solid Angle of
// a Plane Triangle" (IEEE TBME 1983).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "core/geometry/element_bvh.h"
#include "core/geometry/mesh.h"

namespace cagewrap {

struct SurfacePoint {
  double distance = 0.0;  // signed: > 0 outside (the side the normals point to)
  uint32_t triangle = 0;  // the triangle holding the closest point
  glm::dvec3 bary{0.0};   // its barycentric coordinates in that triangle
  glm::dvec3 point{0.0};  // the closest point
};

class SurfaceDistance {
 public:
  // positions #V x 3, triangles #T x 3 (zero-area triangles are ignored).
  SurfaceDistance(std::span<const glm::vec3> positions, std::span<const Tri> triangles);
  bool empty() const { return bvh_.empty(); }
  SurfacePoint query(const glm::dvec3& p) const;
  // Generalized winding number (sum of signed solid angles / 4 pi): 1 inside a closed outward
  // surface, 0 outside, the count of covering pieces where closed pieces overlap; graceful on open
  // ones. Loops over every triangle: for confirming a few points, not for all of a dense skin.
  double winding_number(const glm::dvec3& p) const;

 private:
  std::vector<glm::dvec3> positions_;  // #V x 3
  std::vector<Tri> triangles_;
  std::vector<glm::dvec3> face_normal_;                 // #T unit normals
  std::vector<std::array<glm::dvec3, 3>> edge_normal_;  // #T x 3, edge k joins corners k and k+1
  std::vector<glm::dvec3> vertex_normal_;               // #V angle-weighted
  ElementBvh bvh_;
};

}  // namespace cagewrap
