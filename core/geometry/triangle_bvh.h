// A bounding volume hierarchy over a triangle mesh for ray casts: picking in the editor and
// inside/outside tests. Build once per mesh; when the vertices move (the cage is dragged, the skin
// deforms), refit() recomputes the boxes bottom-up in O(#T) and keeps the tree; rebuild (construct
// again) after large changes, when the refitted boxes have grown loose.
//
// This work is based on: Moller and Trumbore, "Fast, Minimum Storage Ray/Triangle Intersection"
// (JGT 1997); Williams et al., "An Efficient and Robust Ray-Box Intersection Algorithm" (JGT 2005).
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "core/geometry/ray.h"
#include "core/geometry/mesh.h"

namespace cagewrap {

struct TriangleHit {
  uint32_t triangle = 0;  // index into the triangles the hierarchy was built from
  glm::dvec3 bary{0.0};   // barycentric coordinates of the hit in (corner 0, corner 1, corner 2)
  double t = 0.0;         // ray parameter of the hit
  glm::dvec3 point{0.0};  // ray.at(t)
};

class TriangleBvh {
 public:
  static constexpr double kInfinity = std::numeric_limits<double>::infinity();

  TriangleBvh() = default;
  // positions: #V x 3; triangles: #T x 3 corner indices (asserted in range).
  TriangleBvh(std::span<const glm::vec3> positions, std::span<const Tri> triangles);

  // Same triangles, moved vertices: `positions` has the #V of construction.
  void refit(std::span<const glm::vec3> positions);

  // Nearest hit with t in [t_min, t_max], either side of the triangle.
  std::optional<TriangleHit> intersect(const Ray& ray, double t_min = 0.0, double t_max = kInfinity) const;
  // Whether anything is hit with t in [t_min, t_max] (stops at the first hit).
  bool any_hit(const Ray& ray, double t_min, double t_max) const;
  // Every hit with t in [t_min, t_max], in no particular order; `out` is cleared first.
  void all_hits(const Ray& ray, double t_min, double t_max, std::vector<TriangleHit>& out) const;
  // Number of triangles the whole ray crosses (t >= 0): odd means the origin is inside a closed mesh.
  uint32_t count_hits(const Ray& ray) const;

  size_t num_triangles() const { return tris_.size(); }
  size_t num_vertices() const { return positions_.size(); }
  std::span<const glm::vec3> positions() const { return positions_; }
  Aabb bounds() const;

 private:
  struct Node {
    glm::vec3 lo;
    uint32_t first;  // leaf: first triangle slot; inner: 0
    glm::vec3 hi;
    uint32_t count;  // leaf: number of triangles; inner: 0
    uint32_t right;  // inner: right child (the left child is the next node)
  };
  uint32_t build(uint32_t begin, uint32_t end, std::vector<uint32_t>& order,
                 const std::vector<glm::vec3>& centroids);
  void leaf_bounds(Node& node) const;
  // Calls visit(slot, hit) for every triangle hit in [t_min, t_max]; visit returns the new t_max
  // (or a negative value to stop).
  template <class Visit>
  void traverse(const Ray& ray, double t_min, double t_max, Visit visit) const;

  std::vector<Node> nodes_;
  std::vector<Tri> tris_;             // #T corners, in leaf order
  std::vector<uint32_t> ids_;         // #T original triangle index of each slot
  std::vector<glm::vec3> positions_;  // #V x 3 copy, updated by refit()
};

}  // namespace cagewrap
