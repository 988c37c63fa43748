// Vertex frames of the extended variant (section 4.2): the linear part L_v of the manipulation at each
// cage vertex. Supplied by whoever moves the cage (a bone) or, here, estimated from the one-ring.
#pragma once

#include <span>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include "core/geometry/mesh.h"

namespace cagewrap {

class OneRingFit {
 public:
  // Adjacency from the given (valid) triangles of the cage, normals from the rest positions.
  OneRingFit(std::span<const glm::vec3> rest, std::span<const Tri> triangles);

  // L_v = least-squares linear map taking rest one-ring edge vectors to posed ones. Exact for every
  // affine map where the one-ring spans 3-D with a relief of about a sixth of its edges or more; where it
  // is (numerically) flat the free direction is fixed by mapping the rest vertex normal to the posed one,
  // and where it is nearly flat the fit leans toward that (no amplification of out-of-plane motion). #Vc maps written to `out`.
  // Uses preallocated scratch: no allocation per call, one call at a time.
  void fit(std::span<const glm::vec3> posed, std::span<glm::dmat3> out);

 private:
  std::vector<glm::dvec3> rest_;
  std::vector<uint32_t> ring_start_, ring_;  // CSR adjacency
  std::vector<Tri> triangles_;
  std::vector<glm::dvec3> rest_normal_;
  std::vector<double> ring_scale2_;  // squared mean edge length per vertex
  std::vector<uint8_t> flat_;        // one-ring spans less than 3-D
  std::vector<double> relief_;       // nearly flat one-ring: weight of the normal's regularisation (0: none)
  bool any_flat_ = false;
  // posed vertex normals (flat and nearly flat rings), leaning toward the ring's where they collapse
  void posed_normals();
  std::vector<glm::dvec3> posed_, posed_normal_, posed_cross_;  // scratch
};

// Below this relative size, |n| < kCollapseRatio * longest edge^2, a normal taken from cross products of
// float corners (an element's, or a vertex's sum) counts as nearly collapsed. The corners put a few 1e-7 of
// longest^2 of rounding into a cross product: above 1e-4 the normal's direction is good to 0.1 degree.
inline constexpr double kCollapseRatio = 1e-4;

// `n` normalised where |n| >= kCollapseRatio * scale2 (scale2: the longest edge squared); below, leaning
// continuously toward the unit vector `toward`, all of it at n = 0. So a normal that shrinks to nothing as
// the cage moves (a triangle collapsing) turns to `toward` instead of jumping to a fixed fallback.
glm::dvec3 lean_normal(const glm::dvec3& n, double scale2, const glm::dvec3& toward);

// Area-weighted vertex normals (unit, or zero where no valid triangle touches the vertex).
void vertex_normals(std::span<const glm::dvec3> positions, std::span<const Tri> triangles,
                    std::span<glm::dvec3> out);

}  // namespace cagewrap
