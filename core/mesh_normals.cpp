#include "core/mesh_normals.h"

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

}  // namespace cagewrap
