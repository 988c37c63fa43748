// Smooth vertex normals of a deforming triangle mesh, recomputed every frame for display.
#pragma once

#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "core/geometry/mesh.h"

namespace cagewrap {

// Area-weighted vertex normals (#V x 3, unit; zero where no triangle touches a vertex).
// Uses a vertex -> triangles table built once, so the per-frame pass is parallel and allocation-free.
class NormalComputer {
 public:
  NormalComputer() = default;
  NormalComputer(size_t num_vertices, std::span<const Tri> triangles);
  void compute(std::span<const glm::vec3> positions, std::span<glm::vec3> normals);

  // The vertex -> triangles table (CSR): vertex v's triangles are incident()[starts()[v] ..
  // starts()[v + 1]), in increasing order; compute() sums their normals in that order.
  std::span<const uint32_t> starts() const { return start_; }      // #V + 1
  std::span<const uint32_t> incident() const { return incident_; }  // 3 #T (fewer if indices are out of range)
  std::span<const Tri> triangles() const { return triangles_; }

 private:
  std::vector<Tri> triangles_;
  std::vector<uint32_t> start_, incident_;  // CSR: triangles around each vertex
  std::vector<glm::vec3> face_normals_;     // scratch, #T
};

// Largest angle (radians) between corresponding normals of two sets (#V each): 0 where both are
// zero, pi where only one is (a vertex one side finds no triangle for). For comparing two ways of
// computing the same normals (the GPU path against this one).
double max_normal_angle(std::span<const glm::vec3> a, std::span<const glm::vec3> b);

}  // namespace cagewrap
