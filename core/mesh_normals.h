// Smooth vertex normals of a deforming triangle mesh, recomputed every frame for display.
#pragma once

#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "core/mesh.h"

namespace cagewrap {

// Area-weighted vertex normals (#V x 3, unit; zero where no triangle touches a vertex).
// Uses a vertex -> triangles table built once, so the per-frame pass is parallel and allocation-free.
class NormalComputer {
 public:
  NormalComputer() = default;
  NormalComputer(size_t num_vertices, std::span<const Tri> triangles);
  void compute(std::span<const glm::vec3> positions, std::span<glm::vec3> normals);

 private:
  std::vector<Tri> triangles_;
  std::vector<uint32_t> start_, incident_;  // CSR: triangles around each vertex
  std::vector<glm::vec3> face_normals_;     // scratch, #T
};

}  // namespace cagewrap
