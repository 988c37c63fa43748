#include "core/geometry/surface_distance.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include <glm/geometric.hpp>

namespace cagewrap {

namespace {
std::vector<uint32_t> valid_triangles(std::span<const glm::vec3> positions, std::span<const Tri> triangles) {
  std::vector<uint32_t> ids;
  for (uint32_t t = 0; t < triangles.size(); ++t) {
    const glm::dvec3 a(positions[triangles[t][0]]), b(positions[triangles[t][1]]),
        c(positions[triangles[t][2]]);
    if (glm::length(glm::cross(b - a, c - a)) > 0.0) ids.push_back(t);
  }
  return ids;
}
}  // namespace

SurfaceDistance::SurfaceDistance(std::span<const glm::vec3> positions, std::span<const Tri> triangles)
    : positions_(positions.begin(), positions.end()),
      triangles_(triangles.begin(), triangles.end()),
      face_normal_(triangles.size(), glm::dvec3(0.0)),
      edge_normal_(triangles.size()),
      vertex_normal_(positions.size(), glm::dvec3(0.0)),
      bvh_(positions, triangles, valid_triangles(positions, triangles)) {
  std::unordered_map<uint64_t, glm::dvec3> edge_sum;
  edge_sum.reserve(triangles.size() * 2);
  auto key = [](uint32_t u, uint32_t v) { return (uint64_t(std::min(u, v)) << 32) | std::max(u, v); };
  for (size_t t = 0; t < triangles.size(); ++t) {
    const Tri& tri = triangles[t];
    glm::dvec3 p[3] = {glm::dvec3(positions[tri[0]]), glm::dvec3(positions[tri[1]]),
                       glm::dvec3(positions[tri[2]])};
    const glm::dvec3 n = glm::cross(p[1] - p[0], p[2] - p[0]);
    const double len = glm::length(n);
    if (!(len > 0.0)) continue;
    face_normal_[t] = n / len;
    for (int k = 0; k < 3; ++k) {
      const glm::dvec3 e1 = glm::normalize(p[(k + 1) % 3] - p[k]), e2 = glm::normalize(p[(k + 2) % 3] - p[k]);
      const double angle = std::acos(std::clamp(glm::dot(e1, e2), -1.0, 1.0));
      vertex_normal_[tri[k]] += angle * face_normal_[t];
      edge_sum[key(tri[k], tri[(k + 1) % 3])] += face_normal_[t];
    }
  }
  for (size_t t = 0; t < triangles.size(); ++t)
    for (int k = 0; k < 3; ++k)
      edge_normal_[t][k] = edge_sum[key(triangles[t][k], triangles[t][(k + 1) % 3])];
}

SurfacePoint SurfaceDistance::query(const glm::dvec3& p) const {
  std::vector<Candidate> found;
  bvh_.within_adaptive_radius(
      p, [](double d) { return d; }, [](uint32_t) { return false; }, found);
  SurfacePoint s;
  if (found.empty()) {
    s.distance = INFINITY;
    return s;
  }
  const Candidate& c = found.front();
  const Tri& tri = triangles_[c.element];
  s.triangle = c.element;
  s.bary = c.bary;
  s.point = c.bary.x * positions_[tri[0]] + c.bary.y * positions_[tri[1]] + c.bary.z * positions_[tri[2]];
  const int zeros = (c.bary.x == 0.0) + (c.bary.y == 0.0) + (c.bary.z == 0.0);
  glm::dvec3 normal = face_normal_[c.element];
  if (zeros == 2) {
    normal = vertex_normal_[tri[c.bary.x != 0.0 ? 0 : (c.bary.y != 0.0 ? 1 : 2)]];
  } else if (zeros == 1) {
    const int opposite = c.bary.x == 0.0 ? 0 : (c.bary.y == 0.0 ? 1 : 2);
    normal = edge_normal_[c.element][(opposite + 1) % 3];  // the edge not touching the zero corner
  }
  const double d = std::sqrt(c.dist2);
  s.distance = glm::dot(p - s.point, normal) >= 0.0 ? d : -d;
  return s;
}

double SurfaceDistance::winding_number(const glm::dvec3& p) const {
  double sum = 0.0;
  for (const Tri& t : triangles_) {
    const glm::dvec3 a = positions_[t[0]] - p, b = positions_[t[1]] - p, c = positions_[t[2]] - p;
    const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
    const double num = glm::dot(a, glm::cross(b, c));
    const double den = la * lb * lc + glm::dot(a, b) * lc + glm::dot(b, c) * la + glm::dot(c, a) * lb;
    sum += 2.0 * std::atan2(num, den);
  }
  return sum / (4.0 * 3.141592653589793);
}

}  // namespace cagewrap
