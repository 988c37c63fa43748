#include "core/geometry/element_bvh.h"

#include <algorithm>

namespace cagewrap {

namespace {
constexpr uint32_t kLeafSize = 4;
}


ElementBvh::ElementBvh(std::span<const glm::vec3> positions, std::span<const Tri> elements,
                       std::span<const uint32_t> ids) {
  tris_.reserve(ids.size());
  std::vector<glm::dvec3> centroids;
  centroids.reserve(ids.size());
  for (uint32_t id : ids) {
    const Tri& t = elements[id];
    TriData d{glm::dvec3(positions[t[0]]), glm::dvec3(positions[t[1]]), glm::dvec3(positions[t[2]]), id};
    centroids.push_back((d.a + d.b + d.c) / 3.0);
    tris_.push_back(d);
  }
  if (!tris_.empty()) {
    nodes_.reserve(2 * tris_.size());
    build(0, static_cast<uint32_t>(tris_.size()), centroids);
  }
}

uint32_t ElementBvh::build(uint32_t begin, uint32_t end, std::vector<glm::dvec3>& centroids) {
  uint32_t index = static_cast<uint32_t>(nodes_.size());
  nodes_.push_back({});
  glm::dvec3 lo(1e300), hi(-1e300), clo(1e300), chi(-1e300);
  for (uint32_t i = begin; i < end; ++i) {
    const TriData& t = tris_[i];
    lo = glm::min(lo, glm::min(t.a, glm::min(t.b, t.c)));
    hi = glm::max(hi, glm::max(t.a, glm::max(t.b, t.c)));
    clo = glm::min(clo, centroids[i]);
    chi = glm::max(chi, centroids[i]);
  }
  nodes_[index].lo = lo;
  nodes_[index].hi = hi;
  if (end - begin <= kLeafSize) {
    nodes_[index].first = begin;
    nodes_[index].count = end - begin;
    return index;
  }
  glm::dvec3 extent = chi - clo;
  int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
  uint32_t mid = begin + (end - begin) / 2;
  // sort a permutation, then apply it to both arrays
  std::vector<uint32_t> order(end - begin);
  for (uint32_t i = 0; i < order.size(); ++i) order[i] = begin + i;
  std::nth_element(order.begin(), order.begin() + (mid - begin), order.end(),
                   [&](uint32_t x, uint32_t y) { return centroids[x][axis] < centroids[y][axis]; });
  std::vector<TriData> tris(order.size());
  std::vector<glm::dvec3> cents(order.size());
  for (size_t i = 0; i < order.size(); ++i) {
    tris[i] = tris_[order[i]];
    cents[i] = centroids[order[i]];
  }
  std::copy(tris.begin(), tris.end(), tris_.begin() + begin);
  std::copy(cents.begin(), cents.end(), centroids.begin() + begin);
  nodes_[index].count = 0;
  build(begin, mid, centroids);  // left child is index + 1
  uint32_t right = build(mid, end, centroids);
  nodes_[index].right = right;
  return index;
}

void ElementBvh::boxes_within(const glm::dvec3& p, double r, std::vector<Element>& out) const {
  out.clear();
  if (nodes_.empty()) return;
  const double r2 = r * r;
  uint32_t stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (box_dist2(p, node.lo, node.hi) > r2) continue;
    if (node.count > 0) {
      for (uint32_t i = node.first; i < node.first + node.count; ++i) {
        const TriData& t = tris_[i];
        glm::dvec3 lo = glm::min(t.a, glm::min(t.b, t.c)), hi = glm::max(t.a, glm::max(t.b, t.c));
        if (box_dist2(p, lo, hi) <= r2) out.push_back({t.a, t.b, t.c, lo, hi, t.element});
      }
    } else {
      stack[top++] = node.right;
      stack[top++] = static_cast<uint32_t>(&node - nodes_.data()) + 1;
    }
  }
}

double ElementBvh::nearest_distance(const glm::dvec3& p) const {
  std::vector<Candidate> c;
  within_adaptive_radius(p, [](double d) { return d; }, [](uint32_t) { return false; }, c);
  return c.empty() ? 1e300 : std::sqrt(c.front().dist2);
}

}  // namespace cagewrap
