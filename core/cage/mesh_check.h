// Checks a triangle surface for what makes a cage misbehave: zero-area and needle triangles, edges
// shared by more than two faces, open boundaries, inconsistent orientation, a piece folding over
// itself. Separate closed pieces that pass through each other (a cage made of one shell per body
// segment, which the deformer takes as it takes any polygon soup) are counted apart from folds.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include <glm/vec3.hpp>

#include "core/geometry/mesh.h"

namespace cagewrap {

// A needle or a cap: its longest edge is more than this many times its altitude onto that edge
// (the smallest angle is below about 6 degrees). An equilateral triangle scores 1.15.
inline constexpr double kNeedleAspect = 10.0;

struct MeshCheck {
  uint32_t triangles = 0;
  uint32_t degenerate_triangles = 0;  // zero area relative to the longest edge (cage.h kDegenerateRatio)
  uint32_t needle_triangles = 0;  // aspect (longest edge / its altitude) above kNeedleAspect, not degenerate
  uint32_t edges = 0;
  uint32_t boundary_edges = 0;      // used by one triangle
  uint32_t non_manifold_edges = 0;  // used by more than two triangles
  uint32_t misoriented_edges = 0;   // two triangles traverse it in the same direction
  uint32_t components = 0;          // connected through shared edges
  uint32_t self_intersections = 0;  // edge-triangle pairs of one piece that cross (a fold), when searched
  uint32_t piece_crossings = 0;     // edge-triangle pairs of two different pieces that cross, when searched
  double worst_aspect = 0.0;        // largest aspect among non-degenerate triangles
  double signed_volume = 0.0;       // > 0 for a closed surface oriented outward

  bool closed() const { return boundary_edges == 0; }
  bool manifold() const { return non_manifold_edges == 0; }
  bool oriented() const { return misoriented_edges == 0; }
  bool self_intersecting() const { return self_intersections > 0; }
  // One line: "2000 triangles, 0 degenerate, 0 needles, ..."
  std::string summary() const;
};

// positions #V x 3, triangles #T x 3. The self-intersection search (a hierarchy and a ray per edge)
// runs only when asked.
MeshCheck check_mesh(std::span<const glm::vec3> positions, std::span<const Tri> triangles,
                     bool find_self_crossings = true);

// An edge (a < b) passing through a triangle that shares no vertex with it.
struct SelfCrossing {
  uint32_t a = 0, b = 0, triangle = 0;
  auto operator<=>(const SelfCrossing&) const = default;
};
// Every crossing, sorted. Builds a TriangleBvh; O(#E log #T).
std::vector<SelfCrossing> self_crossings(std::span<const glm::vec3> positions,
                                         std::span<const Tri> triangles);

// Longest edge over its altitude: L^2 / (2 * area); infinite for zero area.
double triangle_aspect(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c);

}  // namespace cagewrap
