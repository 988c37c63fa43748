// Bounding volume hierarchy over the cage's valid control elements, for the registration's
// "every element within a radius that depends on the nearest distance" query.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "core/geometry/geometry.h"
#include "core/geometry/mesh.h"

namespace cagewrap {

struct Candidate {
  uint32_t element;
  double dist2;     // squared distance to the closest point of the element
  glm::dvec3 bary;  // barycentric coordinates of that closest point
};

class ElementBvh {
 public:
  // Indexes `elements[ids[i]]`; `positions` are the reference cage vertices.
  ElementBvh(std::span<const glm::vec3> positions, std::span<const Tri> elements, std::span<const uint32_t> ids);

  bool empty() const { return tris_.empty(); }

  // Collects every indexed element k (not rejected by `skip(k)`) whose distance to p is at most
  // radius(d_min), where d_min is the distance to the nearest such element and radius is a
  // non-decreasing function with radius(d) >= d. Sorted by distance. `out` is cleared first.
  template <class Radius, class Skip>
  void within_adaptive_radius(const glm::dvec3& p, Radius radius, Skip skip, std::vector<Candidate>& out) const;

  // Squared distance from p to a box.
  static double box_dist2(const glm::dvec3& p, const glm::dvec3& lo, const glm::dvec3& hi) {
    const double dx = std::max(std::max(lo.x - p.x, p.x - hi.x), 0.0);
    const double dy = std::max(std::max(lo.y - p.y, p.y - hi.y), 0.0);
    const double dz = std::max(std::max(lo.z - p.z, p.z - hi.z), 0.0);
    return dx * dx + dy * dy + dz * dz;
  }

  // An indexed element with its corners and bounding box, for tight per-point loops.
  struct Element {
    glm::dvec3 a, b, c;
    glm::dvec3 lo, hi;
    uint32_t id;
  };
  // Every element whose bounding box lies within distance r of p (a superset of those within r).
  void boxes_within(const glm::dvec3& p, double r, std::vector<Element>& out) const;
  // Distance from p to the nearest indexed element (infinite when empty).
  double nearest_distance(const glm::dvec3& p) const;

 private:
  struct Node {
    glm::dvec3 lo, hi;
    uint32_t first;  // leaf: first triangle; inner: left child (right = first + 1... stored explicitly)
    uint32_t count;  // 0 for inner nodes
    uint32_t right;  // inner: right child
  };
  struct TriData {
    glm::dvec3 a, b, c;
    uint32_t element;
  };
  uint32_t build(uint32_t begin, uint32_t end, std::vector<glm::dvec3>& centroids);

  std::vector<Node> nodes_;
  std::vector<TriData> tris_;
};

template <class Radius, class Skip>
void ElementBvh::within_adaptive_radius(const glm::dvec3& p, Radius radius, Skip skip,
                                        std::vector<Candidate>& out) const {
  out.clear();
  if (nodes_.empty()) return;
  double best2 = 1e300, bound2 = 1e300;
  uint32_t stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (box_dist2(p, node.lo, node.hi) > bound2) continue;
    if (node.count > 0) {
      for (uint32_t i = node.first; i < node.first + node.count; ++i) {
        const TriData& t = tris_[i];
        if (skip(t.element)) continue;
        ClosestPoint cp = closest_point_on_triangle(p, t.a, t.b, t.c);
        if (cp.dist2 > bound2) continue;
        out.push_back({t.element, cp.dist2, cp.bary});
        if (cp.dist2 < best2) {
          best2 = cp.dist2;
          double r = radius(std::sqrt(best2));
          bound2 = std::max(r * r, best2);  // rounding must never drop the nearest element
        }
      }
    } else {
      uint32_t l = static_cast<uint32_t>(&node - nodes_.data()) + 1, r = node.right;
      double dl = box_dist2(p, nodes_[l].lo, nodes_[l].hi), dr = box_dist2(p, nodes_[r].lo, nodes_[r].hi);
      // push the far child first so the near one is visited first
      if (dl <= dr) {
        if (dr <= bound2) stack[top++] = r;
        if (dl <= bound2) stack[top++] = l;
      } else {
        if (dl <= bound2) stack[top++] = l;
        if (dr <= bound2) stack[top++] = r;
      }
    }
  }
  std::erase_if(out, [&](const Candidate& c) { return c.dist2 > bound2; });
  std::sort(out.begin(), out.end(), [](const Candidate& x, const Candidate& y) {
    return x.dist2 < y.dist2 || (x.dist2 == y.dist2 && x.element < y.element);
  });
}

}  // namespace cagewrap
