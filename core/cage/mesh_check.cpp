#include "core/cage/mesh_check.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

#include <glm/geometric.hpp>

#include "core/cage/cage.h"
#include "core/geometry/triangle_bvh.h"

namespace cagewrap {

double triangle_aspect(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  const double l2 = std::max({glm::dot(b - a, b - a), glm::dot(c - b, c - b), glm::dot(a - c, a - c)});
  const double twice_area = glm::length(glm::cross(b - a, c - a));
  return twice_area > 0 ? l2 / twice_area : INFINITY;
}

std::string MeshCheck::summary() const {
  auto n = [](uint32_t x) { return std::to_string(x); };
  return n(triangles) + " triangles, " + n(degenerate_triangles) + " degenerate, " + n(needle_triangles) +
         " needles, " + n(non_manifold_edges) + " non-manifold edges, " + n(boundary_edges) +
         " boundary edges, " + n(misoriented_edges) + " misoriented edges, " + n(components) +
         " components, " + n(self_intersections) + " self-intersections, " + n(piece_crossings) +
         " crossings between pieces";
}

MeshCheck check_mesh(std::span<const glm::vec3> positions, std::span<const Tri> triangles,
                     bool find_self_crossings) {
  MeshCheck m;
  m.triangles = static_cast<uint32_t>(triangles.size());
  struct EdgeUse {
    uint32_t count = 0;
    uint32_t forward = 0;  // traversals a -> b with a < b
    uint32_t first_triangle = 0;
  };
  std::unordered_map<uint64_t, EdgeUse> edges;
  edges.reserve(triangles.size() * 2);
  std::vector<uint32_t> parent(triangles.size());
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (uint32_t t = 0; t < triangles.size(); ++t) {
    const Tri& tri = triangles[t];
    const glm::dvec3 a(positions[tri[0]]), b(positions[tri[1]]), c(positions[tri[2]]);
    const double l2 = std::max({glm::dot(b - a, b - a), glm::dot(c - b, c - b), glm::dot(a - c, a - c)});
    const double twice_area = glm::length(glm::cross(b - a, c - a));
    if (!(twice_area > kDegenerateRatio * l2)) {
      ++m.degenerate_triangles;
    } else {
      const double aspect = l2 / twice_area;
      m.worst_aspect = std::max(m.worst_aspect, aspect);
      if (aspect > kNeedleAspect) ++m.needle_triangles;
    }
    m.signed_volume += glm::dot(a, glm::cross(b, c)) / 6.0;
    for (int k = 0; k < 3; ++k) {
      const uint32_t u = tri[k], v = tri[(k + 1) % 3];
      const uint64_t key = (uint64_t(std::min(u, v)) << 32) | std::max(u, v);
      EdgeUse& e = edges[key];
      if (e.count == 0)
        e.first_triangle = t;
      else {
        const uint32_t x = find(t), y = find(e.first_triangle);
        if (x != y) parent[std::max(x, y)] = std::min(x, y);
      }
      ++e.count;
      e.forward += u < v ? 1 : 0;
    }
  }
  m.edges = static_cast<uint32_t>(edges.size());
  for (const auto& [key, e] : edges) {
    if (e.count == 1)
      ++m.boundary_edges;
    else if (e.count > 2)
      ++m.non_manifold_edges;
    else if (e.forward != 1)
      ++m.misoriented_edges;
  }
  for (uint32_t t = 0; t < triangles.size(); ++t) m.components += find(t) == t ? 1 : 0;
  if (find_self_crossings)
    for (const SelfCrossing& x : self_crossings(positions, triangles)) {
      // the edge's piece: any triangle using vertex a, found through the edge table
      const uint32_t u = x.a, v = x.b;
      const uint32_t edge_tri = edges.at((uint64_t(std::min(u, v)) << 32) | std::max(u, v)).first_triangle;
      if (find(edge_tri) == find(x.triangle))
        ++m.self_intersections;
      else
        ++m.piece_crossings;
    }
  return m;
}

std::vector<SelfCrossing> self_crossings(std::span<const glm::vec3> positions,
                                         std::span<const Tri> triangles) {
  const TriangleBvh bvh(positions, triangles);
  std::vector<SelfCrossing> out;
  std::vector<TriangleHit> hits;
  for (const Tri& tri : triangles)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = tri[k], b = tri[(k + 1) % 3];
      if (a > b)
        continue;  // each interior edge once (its other face has it as b -> a); open edges twice at most
      const glm::dvec3 pa(positions[a]), pb(positions[b]);
      const double len = glm::length(pb - pa);
      if (!(len > 0)) continue;
      bvh.all_hits(Ray{pa, (pb - pa) / len}, 0.0, len, hits);
      for (const TriangleHit& h : hits) {
        const Tri& t = triangles[h.triangle];
        if (t[0] == a || t[1] == a || t[2] == a || t[0] == b || t[1] == b || t[2] == b) continue;
        out.push_back({a, b, h.triangle});
      }
    }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}
}  // namespace cagewrap
