#include "core/document/skin_brush.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <limits>
#include <queue>
#include <string>

namespace cagewrap {

SkinBrush::SkinBrush(std::span<const glm::vec3> positions, std::span<const Tri> triangles)
    : positions_(positions.begin(), positions.end()) {
  const size_t nv = positions.size();
  std::vector<std::pair<uint32_t, uint32_t>> edges;  // (a, b) both ways
  edges.reserve(triangles.size() * 6);
  for (const Tri& t : triangles) {
    if (t[0] >= nv || t[1] >= nv || t[2] >= nv) continue;
    triangles_.push_back(t);
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = t[static_cast<size_t>(k)], b = t[static_cast<size_t>((k + 1) % 3)];
      if (a == b) continue;
      edges.emplace_back(a, b);
      edges.emplace_back(b, a);
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  start_.assign(nv + 1, 0);
  for (const auto& [a, b] : edges) ++start_[a + 1];
  for (size_t v = 0; v < nv; ++v) start_[v + 1] += start_[v];
  neighbour_.reserve(edges.size());
  length_.reserve(edges.size());
  for (const auto& [a, b] : edges) {
    neighbour_.push_back(b);
    length_.push_back(static_cast<float>(glm::length(glm::dvec3(positions[a]) - glm::dvec3(positions[b]))));
  }
  dist_.assign(nv, std::numeric_limits<double>::infinity());
}

Result<BrushPoints> SkinBrush::points_within(uint32_t triangle, const glm::dvec3& hit, double radius) {
  if (triangle >= triangles_.size())
    return make_error(ErrorCode::kIndexOutOfRange, "brush hit triangle " + std::to_string(triangle) +
                                                       " is out of range: the skin has " +
                                                       std::to_string(triangles_.size()) + " triangles");
  if (!(radius >= 0.0) || !std::isfinite(radius))
    return make_error(ErrorCode::kInvalidArgument,
                      "brush radius must be a finite number >= 0, not " + std::to_string(radius));
  if (!std::isfinite(hit.x) || !std::isfinite(hit.y) || !std::isfinite(hit.z))
    return make_error(ErrorCode::kNonFinite, "the brush hit point is not finite");
  using Item = std::pair<double, uint32_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
  auto relax = [&](uint32_t v, double d) {
    if (d > radius || d >= dist_[v]) return;
    if (dist_[v] == std::numeric_limits<double>::infinity()) reached_.push_back(v);
    dist_[v] = d;
    queue.push({d, v});
  };
  for (uint32_t v : triangles_[triangle]) relax(v, glm::length(glm::dvec3(positions_[v]) - hit));
  while (!queue.empty()) {
    auto [d, v] = queue.top();
    queue.pop();
    if (d > dist_[v]) continue;
    for (uint32_t i = start_[v]; i < start_[v + 1]; ++i) relax(neighbour_[i], d + length_[i]);
  }
  BrushPoints out;
  std::sort(reached_.begin(), reached_.end());
  out.points = reached_;
  out.distance.reserve(reached_.size());
  for (uint32_t v : reached_) {
    out.distance.push_back(static_cast<float>(dist_[v]));
    dist_[v] = std::numeric_limits<double>::infinity();
  }
  reached_.clear();
  return out;
}

}  // namespace cagewrap
