#include "core/cage/quad_pairing.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <glm/geometric.hpp>
#include <tuple>
#include <unordered_map>
#include <vector>

namespace cagewrap {

namespace {
constexpr double kDegrees = 180.0 / 3.141592653589793;

double angle_between(const glm::dvec3& a, const glm::dvec3& b) {
  const double la = glm::length(a), lb = glm::length(b);
  if (!(la > 0 && lb > 0)) return 0.0;
  return std::acos(std::clamp(glm::dot(a, b) / (la * lb), -1.0, 1.0)) * kDegrees;
}
}  // namespace

QuadPairing pair_quads(std::span<const glm::vec3> positions, std::span<const Tri> triangles,
                       const QuadPairingParams& params) {
  // each edge with the triangles using it (a third use marks it non-manifold)
  struct EdgeUse {
    uint32_t t[2] = {UINT32_MAX, UINT32_MAX};
    uint32_t count = 0;
  };
  std::unordered_map<uint64_t, EdgeUse> edges;
  edges.reserve(triangles.size() * 2);
  for (uint32_t t = 0; t < triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = triangles[t][k], b = triangles[t][(k + 1) % 3];
      EdgeUse& e = edges[(uint64_t(std::min(a, b)) << 32) | std::max(a, b)];
      if (e.count < 2) e.t[e.count] = t;
      ++e.count;
    }
  auto p = [&](uint32_t v) { return glm::dvec3(positions[v]); };
  auto normal = [&](const Tri& t) { return glm::cross(p(t[1]) - p(t[0]), p(t[2]) - p(t[0])); };

  struct Candidate {
    double score;
    uint32_t t0, t1;
    std::array<uint32_t, 4> quad;
  };
  std::vector<Candidate> candidates;
  for (const auto& [key, e] : edges) {
    if (e.count != 2) continue;
    const uint32_t u = uint32_t(key >> 32), v = uint32_t(key & 0xffffffffu);
    const Tri &a = triangles[e.t[0]], &b = triangles[e.t[1]];
    // orient the edge as triangle a traverses it: a = (u, v, w1), b = (v, u, w2)
    uint32_t from = u, to = v;
    for (int k = 0; k < 3; ++k)
      if (a[k] == v && a[(k + 1) % 3] == u) std::swap(from, to);
    bool consistent = false;
    for (int k = 0; k < 3; ++k) consistent = consistent || (b[k] == to && b[(k + 1) % 3] == from);
    if (!consistent) continue;  // misoriented pair: leave it alone
    const uint32_t w1 = a[0] + a[1] + a[2] - from - to, w2 = b[0] + b[1] + b[2] - from - to;
    if (w1 == w2) continue;
    const double bend = angle_between(normal(a), normal(b));
    if (!(bend <= params.max_bend)) continue;
    const std::array<uint32_t, 4> quad = {w2, to, w1, from};
    double worst = 0.0;
    bool ok = true;
    const glm::dvec3 n = normal(a) + normal(b);
    for (int k = 0; k < 4 && ok; ++k) {
      const glm::dvec3 c = p(quad[k]), prev = p(quad[(k + 3) % 4]), next = p(quad[(k + 1) % 4]);
      const double angle = angle_between(prev - c, next - c);
      // convex: each corner turns the same way as the quad's normal
      ok = angle >= params.min_angle && angle <= params.max_angle &&
           glm::dot(glm::cross(next - c, prev - c), n) > 0;
      worst = std::max(worst, std::abs(angle - 90.0));
    }
    if (!ok) continue;
    candidates.push_back({worst + bend, e.t[0], e.t[1], quad});
  }
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& x, const Candidate& y) {
    return std::tie(x.score, x.t0, x.t1) < std::tie(y.score, y.t0, y.t1);
  });

  QuadPairing out;
  out.mesh.positions.assign(positions.begin(), positions.end());
  std::vector<int64_t> paired(triangles.size(), -1);  // candidate index of each paired triangle
  for (size_t c = 0; c < candidates.size(); ++c) {
    const Candidate& x = candidates[c];
    if (paired[x.t0] >= 0 || paired[x.t1] >= 0) continue;
    paired[x.t0] = paired[x.t1] = static_cast<int64_t>(c);
  }
  // faces in the order of the input triangles: a quad where its first triangle was
  for (uint32_t t = 0; t < triangles.size(); ++t) {
    if (paired[t] < 0) {
      out.mesh.add_face({triangles[t][0], triangles[t][1], triangles[t][2]});
      ++out.triangles;
    } else if (const Candidate& x = candidates[size_t(paired[t])]; t == std::min(x.t0, x.t1)) {
      out.mesh.add_face(x.quad);
      ++out.quads;
    }
  }
  return out;
}

}  // namespace cagewrap
