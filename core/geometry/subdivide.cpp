#include "core/geometry/subdivide.h"

#include <unordered_map>

namespace cagewrap {

PolyMesh subdivide_edges_uniform(const PolyMesh& mesh, uint32_t n) {
  Triangulation tri = triangulate(mesh);
  PolyMesh out;
  out.positions = mesh.positions;
  const uint32_t s = n + 1;  // segments per edge
  // interior points of each undirected edge, stored from the smaller vertex to the larger
  std::unordered_map<uint64_t, uint32_t> edge_first;
  auto edge_point = [&](uint32_t a, uint32_t b, uint32_t k) -> uint32_t {  // k-th of n points from a
    if (k == 0) return a;
    if (k == s) return b;
    uint32_t lo = std::min(a, b), hi = std::max(a, b);
    uint64_t key = (uint64_t(lo) << 32) | hi;
    auto it = edge_first.find(key);
    if (it == edge_first.end()) {
      uint32_t first = static_cast<uint32_t>(out.positions.size());
      glm::dvec3 pl(mesh.positions[lo]), ph(mesh.positions[hi]);
      for (uint32_t j = 1; j <= n; ++j) out.positions.push_back(glm::vec3(pl + (ph - pl) * (double(j) / s)));
      it = edge_first.emplace(key, first).first;
    }
    uint32_t j = a == lo ? k : s - k;
    return it->second + j - 1;
  };
  std::vector<uint32_t> grid;
  for (const Tri& t : tri.triangles) {
    // grid(i, j): point A + (i/s)(B - A) + (j/s)(C - A), i + j <= s
    grid.assign(size_t(s + 1) * (s + 1), 0);
    auto at = [&](uint32_t i, uint32_t j) -> uint32_t& { return grid[size_t(i) * (s + 1) + j]; };
    glm::dvec3 a(mesh.positions[t[0]]), b(mesh.positions[t[1]]), c(mesh.positions[t[2]]);
    for (uint32_t i = 0; i <= s; ++i)
      for (uint32_t j = 0; i + j <= s; ++j) {
        if (j == 0) at(i, j) = edge_point(t[0], t[1], i);
        else if (i == 0) at(i, j) = edge_point(t[0], t[2], j);
        else if (i + j == s) at(i, j) = edge_point(t[1], t[2], j);
        else {
          at(i, j) = static_cast<uint32_t>(out.positions.size());
          out.positions.push_back(glm::vec3(a + (b - a) * (double(i) / s) + (c - a) * (double(j) / s)));
        }
      }
    for (uint32_t i = 0; i < s; ++i)
      for (uint32_t j = 0; i + j < s; ++j) {
        out.add_face({at(i, j), at(i + 1, j), at(i, j + 1)});
        if (i + j + 1 < s) out.add_face({at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
      }
  }
  return out;
}

}  // namespace cagewrap
