#include "core/geometry/mesh_normals.h"

#include "core/base/check.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

namespace cagewrap {

NormalComputer::NormalComputer(size_t num_vertices, std::span<const Tri> triangles)
    : triangles_(triangles.begin(), triangles.end()), start_(num_vertices + 1, 0), face_normals_(triangles.size()) {
  for (const Tri& t : triangles_)
    for (uint32_t v : t)
      if (v < num_vertices) start_[v + 1]++;
  for (size_t v = 0; v < num_vertices; ++v) start_[v + 1] += start_[v];
  incident_.resize(start_.back());
  std::vector<uint32_t> fill(start_.begin(), start_.end() - 1);
  for (uint32_t f = 0; f < triangles_.size(); ++f)
    for (uint32_t v : triangles_[f])
      if (v < num_vertices) incident_[fill[v]++] = f;
}

void NormalComputer::compute(std::span<const glm::vec3> p, std::span<glm::vec3> normals) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, triangles_.size(), 8192), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t f = r.begin(); f != r.end(); ++f) {
      const Tri& t = triangles_[f];
      face_normals_[f] = glm::cross(p[t[1]] - p[t[0]], p[t[2]] - p[t[0]]);  // length = 2 x area
    }
  });
  const size_t nv = start_.size() - 1;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, nv, 8192), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t v = r.begin(); v != r.end(); ++v) {
      glm::vec3 n(0.f);
      for (uint32_t k = start_[v]; k < start_[v + 1]; ++k) n += face_normals_[incident_[k]];
      float len = glm::length(n);
      normals[v] = len > 0 ? n / len : glm::vec3(0.f);
    }
  });
}

double max_normal_angle(std::span<const glm::vec3> a, std::span<const glm::vec3> b) {
  CAGEWRAP_CHECK(a.size() == b.size(), "one normal per vertex in both sets");
  double worst = 0.0;
  for (size_t i = 0; i < a.size(); ++i) {
    const glm::dvec3 p(a[i]), q(b[i]);
    const double lp = glm::length(p), lq = glm::length(q);
    if (lp == 0.0 && lq == 0.0) continue;
    // atan2 of |p x q| and p . q stays accurate for tiny angles, where acos does not
    const double angle = lp == 0.0 || lq == 0.0 ? M_PI : std::atan2(glm::length(glm::cross(p, q)), glm::dot(p, q));
    worst = std::max(worst, std::isnan(angle) ? M_PI : angle);  // a NaN normal is as wrong as can be
  }
  return worst;
}

}  // namespace cagewrap
