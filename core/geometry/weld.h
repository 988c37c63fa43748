// Welding: merges vertices closer than a tolerance (coincident copies at UV and normal seams,
// pieces modelled to touch) so separate primitives become one connected surface.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "core/geometry/mesh.h"

namespace cagewrap {

struct Weld {
  std::vector<uint32_t> remap;       // #V input vertex -> welded vertex
  std::vector<glm::vec3> positions;  // #W welded positions (the first input vertex of each cluster)
};

// Clusters points within `tolerance` of each other (transitively, through a hash grid), keeping
// the lowest input index of each cluster as its representative. Deterministic. Tolerance 0 turns
// welding off (every vertex stays its own).
Weld weld_vertices(std::span<const glm::vec3> positions, double tolerance);

// Applies a weld to triangles and drops those that collapse (two corners welded together) or repeat
// an earlier triangle's vertex set. #T' triangles; `dropped` counts the removed ones.
std::vector<Tri> weld_triangles(std::span<const Tri> triangles, std::span<const uint32_t> remap,
                                uint32_t* dropped);

}  // namespace cagewrap
