#include "app/workspace/soft_selection.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

#include <glm/geometric.hpp>

namespace cagewrap {

const char* falloff_name(Falloff f) {
  switch (f) {
    case Falloff::kSmooth: return "smooth";
    case Falloff::kLinear: return "linear";
    case Falloff::kSharp: return "sharp";
    case Falloff::kConstant: return "constant";
  }
  return "?";
}

double falloff_weight(Falloff f, double t) {
  if (!(t < 1.0)) return 0.0;  // also NaN
  t = std::max(t, 0.0);
  switch (f) {
    case Falloff::kSmooth: return 1.0 - t * t * (3.0 - 2.0 * t);
    case Falloff::kLinear: return 1.0 - t;
    case Falloff::kSharp: return (1.0 - t) * (1.0 - t);
    case Falloff::kConstant: return 1.0;
  }
  return 0.0;
}

glm::dvec3 MoveWeights::displacement(size_t i, const glm::dvec3& d) const {
  const double a = direct[i], b = mirrored[i];
  const glm::dvec3 m(-d.x, d.y, d.z);
  return (a * d + b * m) / std::max(1.0, a + b);
}

std::vector<float> MoveWeights::dense(size_t count) const {
  std::vector<float> out(count, 0.f);
  for (size_t i = 0; i < vertices.size(); ++i)
    if (vertices[i] < count) out[vertices[i]] = std::max(direct[i], mirrored[i]);
  return out;
}

IndexSet face_vertices(const IndexSet& faces, const PolyMesh& mesh) {
  std::vector<uint32_t> v;
  for (uint32_t f : faces)
    if (f < mesh.num_faces())
      for (uint32_t c : mesh.face(f)) v.push_back(c);
  return IndexSet(std::move(v));
}

namespace {

// Distance from every vertex to the nearest seed, up to `radius` (infinity beyond).
std::vector<double> distances(std::span<const uint32_t> seeds, std::span<const glm::vec3> positions,
                              const PolyMesh& mesh, const SoftSelectionParams& soft) {
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> dist(positions.size(), inf);
  for (uint32_t s : seeds) dist[s] = 0.0;
  if (!soft.enabled) return dist;
  if (soft.distance == FalloffDistance::kVolume) {
    for (size_t v = 0; v < positions.size(); ++v) {
      if (dist[v] == 0.0) continue;
      const glm::dvec3 p(positions[v]);
      for (uint32_t s : seeds) {
        const double d = glm::length(p - glm::dvec3(positions[s]));
        if (d < dist[v]) dist[v] = d;
      }
      if (dist[v] >= soft.radius) dist[v] = inf;
    }
    return dist;
  }
  // surface: multi-source Dijkstra along polygon edges, stopped at the radius
  std::vector<std::vector<uint32_t>> adjacency(positions.size());
  for (auto [a, b] : unique_edges(mesh)) {
    if (a >= positions.size() || b >= positions.size()) continue;
    adjacency[a].push_back(b);
    adjacency[b].push_back(a);
  }
  using Item = std::pair<double, uint32_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
  for (uint32_t s : seeds) queue.push({0.0, s});
  while (!queue.empty()) {
    auto [d, v] = queue.top();
    queue.pop();
    if (d > dist[v]) continue;
    for (uint32_t n : adjacency[v]) {
      const double nd = d + glm::length(glm::dvec3(positions[n]) - glm::dvec3(positions[v]));
      if (nd < dist[n] && nd < soft.radius) {
        dist[n] = nd;
        queue.push({nd, n});
      }
    }
  }
  return dist;
}

}  // namespace

Result<MoveWeights> move_weights(const IndexSet& selected, std::span<const glm::vec3> positions,
                                 const PolyMesh& mesh, const SoftSelectionParams& soft,
                                 const MirrorParams& mirror) {
  for (uint32_t v : selected)
    if (v >= positions.size())
      return Error{ErrorCode::kIndexOutOfRange, "selected vertex " + std::to_string(v) + " is out of range (the cage has " +
                                                    std::to_string(positions.size()) + " vertices)"};
  if (soft.enabled && !(soft.radius > 0.0 && std::isfinite(soft.radius)))
    return Error{ErrorCode::kInvalidArgument, "soft selection radius must be a positive number, got " + std::to_string(soft.radius)};
  if (soft.enabled && soft.distance == FalloffDistance::kSurface && mesh.num_faces() == 0)
    return Error{ErrorCode::kInvalidArgument, "surface soft selection needs the cage's faces, and it has none"};
  if (mirror.enabled && !(mirror.tolerance > 0.0 && std::isfinite(mirror.tolerance)))
    return Error{ErrorCode::kInvalidArgument, "mirror tolerance must be a positive number, got " + std::to_string(mirror.tolerance)};

  MoveWeights out;
  const std::vector<double> direct = distances(selected.indices(), positions, mesh, soft);
  std::vector<double> mirrored(positions.size(), std::numeric_limits<double>::infinity());
  if (mirror.enabled) {
    MirrorResult m = mirror_x(selected, positions, mirror.tolerance);
    out.unmatched = std::move(m.unmatched);
    mirrored = distances(m.mirrored.indices(), positions, mesh, soft);
  }
  const double radius = soft.enabled ? soft.radius : 1.0;
  for (size_t v = 0; v < positions.size(); ++v) {
    const double a = direct[v] == 0.0 ? 1.0 : falloff_weight(soft.falloff, direct[v] / radius);
    const double b = mirrored[v] == 0.0 ? 1.0 : falloff_weight(soft.falloff, mirrored[v] / radius);
    if (a <= 0.0 && b <= 0.0) continue;
    out.vertices.push_back(static_cast<uint32_t>(v));
    out.direct.push_back(static_cast<float>(a));
    out.mirrored.push_back(static_cast<float>(b));
  }
  return out;
}

}  // namespace cagewrap
