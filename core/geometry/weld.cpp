#include "core/geometry/weld.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>
#include <unordered_set>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

namespace cagewrap {

namespace {
struct CellHash {
  size_t operator()(const glm::ivec3& c) const {
    return (static_cast<size_t>(c.x) * 73856093u) ^ (static_cast<size_t>(c.y) * 19349663u) ^
           (static_cast<size_t>(c.z) * 83492791u);
  }
};

uint32_t find(std::vector<uint32_t>& parent, uint32_t x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}
}  // namespace

Weld weld_vertices(std::span<const glm::vec3> positions, double tolerance) {
  const size_t n = positions.size();
  std::vector<uint32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0u);
  if (tolerance > 0) {
    // cells of size tolerance: a partner lies in the same or an adjacent cell
    const double inv = 1.0 / tolerance, tol2 = tolerance * tolerance;
    std::unordered_map<glm::ivec3, std::vector<uint32_t>, CellHash> grid;
    grid.reserve(n);
    auto cell_of = [&](const glm::vec3& p) { return glm::ivec3(glm::floor(glm::dvec3(p) * inv)); };
    for (uint32_t i = 0; i < n; ++i) grid[cell_of(positions[i])].push_back(i);
    for (uint32_t i = 0; i < n; ++i) {
      const glm::ivec3 c = cell_of(positions[i]);
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            auto it = grid.find(c + glm::ivec3(dx, dy, dz));
            if (it == grid.end()) continue;
            for (uint32_t j : it->second) {
              if (j <= i) continue;
              const glm::dvec3 d = glm::dvec3(positions[i]) - glm::dvec3(positions[j]);
              if (glm::dot(d, d) > tol2) continue;
              const uint32_t a = find(parent, i), b = find(parent, j);
              if (a != b) parent[std::max(a, b)] = std::min(a, b);  // root = lowest index
            }
          }
    }
  }
  Weld w;
  w.remap.resize(n);
  std::vector<uint32_t> index_of_root(n, UINT32_MAX);
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t r = find(parent, i);
    if (index_of_root[r] == UINT32_MAX) {
      index_of_root[r] = static_cast<uint32_t>(w.positions.size());
      w.positions.push_back(positions[r]);
    }
    w.remap[i] = index_of_root[r];
  }
  return w;
}

std::vector<Tri> weld_triangles(std::span<const Tri> triangles, std::span<const uint32_t> remap,
                                uint32_t* dropped) {
  std::vector<Tri> out;
  out.reserve(triangles.size());
  struct KeyHash {
    size_t operator()(const Tri& t) const {
      return (size_t(t[0]) * 2654435761u) ^ (size_t(t[1]) * 40503u) ^ t[2];
    }
  };
  std::unordered_set<Tri, KeyHash> seen;
  seen.reserve(triangles.size());
  uint32_t count = 0;
  for (const Tri& t : triangles) {
    const Tri w{remap[t[0]], remap[t[1]], remap[t[2]]};
    Tri key = w;
    std::sort(key.begin(), key.end());
    if (key[0] == key[1] || key[1] == key[2] || !seen.insert(key).second) {
      ++count;
      continue;
    }
    out.push_back(w);
  }
  if (dropped) *dropped = count;
  return out;
}

}  // namespace cagewrap
