// Checks shared by the cage edit and subdivision tests: polygon-level manifoldness and orientation,
// T-junctions, boundaries, distances to a cage's surface.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <glm/geometric.hpp>
#include <map>
#include <utility>
#include <vector>

#include "core/cage/cage.h"
#include "core/geometry/geometry.h"
#include "core/document/topology_change.h"

namespace cagewrap::test {

// Regular octahedron of radius 1 (vertices +x -x +y -y +z -z), 8 outward triangles.
inline Cage octahedron_cage() {
  PolyMesh m;
  m.positions = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (auto f : std::vector<Tri>{
           {0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}})
    m.add_face(f);
  return std::move(make_cage(std::move(m), "octahedron")).value();
}

struct PolygonEdges {
  std::map<std::pair<uint32_t, uint32_t>, int> directed;    // a -> b: how many faces traverse it
  std::map<std::pair<uint32_t, uint32_t>, int> undirected;  // (min, max): how many faces use it
};

inline PolygonEdges polygon_edges(const PolyMesh& m) {
  PolygonEdges e;
  for (size_t f = 0; f < m.num_faces(); ++f) {
    auto c = m.face(f);
    for (size_t i = 0; i < c.size(); ++i) {
      uint32_t a = c[i], b = c[(i + 1) % c.size()];
      ++e.directed[{a, b}];
      ++e.undirected[{std::min(a, b), std::max(a, b)}];
    }
  }
  return e;
}

// Every edge has at most two faces, and two faces sharing an edge traverse it in opposite directions.
inline ::testing::AssertionResult manifold_and_oriented(const PolyMesh& m) {
  PolygonEdges e = polygon_edges(m);
  for (auto [edge, n] : e.undirected)
    if (n > 2)
      return ::testing::AssertionFailure()
             << "edge " << edge.first << "-" << edge.second << " has " << n << " faces";
  for (auto [edge, n] : e.directed)
    if (n > 1)
      return ::testing::AssertionFailure()
             << "edge " << edge.first << "->" << edge.second << " traversed " << n << " times (misoriented)";
  return ::testing::AssertionSuccess();
}

// Undirected edges with one face.
inline std::vector<std::pair<uint32_t, uint32_t>> boundary_edges(const PolyMesh& m) {
  std::vector<std::pair<uint32_t, uint32_t>> out;
  for (auto [edge, n] : polygon_edges(m).undirected)
    if (n == 1) out.push_back(edge);
  return out;
}

// No vertex lies strictly inside a polygon edge it is not an end of (a hanging vertex).
inline ::testing::AssertionResult no_t_junctions(const PolyMesh& m, double tol = 1e-6) {
  for (auto [edge, n] : polygon_edges(m).undirected) {
    glm::dvec3 a(m.positions[edge.first]), b(m.positions[edge.second]);
    const double len2 = glm::dot(b - a, b - a);
    for (uint32_t v = 0; v < m.num_vertices(); ++v) {
      if (v == edge.first || v == edge.second) continue;
      glm::dvec3 p(m.positions[v]);
      const double t = glm::dot(p - a, b - a) / len2;
      if (t <= 1e-6 || t >= 1 - 1e-6) continue;
      if (glm::length(a + t * (b - a) - p) < tol * std::sqrt(len2))
        return ::testing::AssertionFailure()
               << "vertex " << v << " hangs on edge " << edge.first << "-" << edge.second;
    }
  }
  return ::testing::AssertionSuccess();
}

// Distance from p to the nearest control element of `cage` at `positions`.
inline double distance_to_cage(const glm::dvec3& p, const Cage& cage) {
  double best = 1e300;
  for (const Tri& t : cage.elements) {
    const auto& x = cage.polygons.positions;
    ClosestPoint cp =
        closest_point_on_triangle(p, glm::dvec3(x[t[0]]), glm::dvec3(x[t[1]]), glm::dvec3(x[t[2]]));
    best = std::min(best, std::sqrt(cp.dist2));
  }
  return best;
}

// Sum of signed tetrahedron volumes of the elements (> 0 for a closed surface oriented outward).
inline double signed_volume(const Cage& cage) {
  double v = 0.0;
  for (const Tri& t : cage.elements) {
    const auto& x = cage.polygons.positions;
    v += glm::dot(glm::dvec3(x[t[0]]), glm::cross(glm::dvec3(x[t[1]]), glm::dvec3(x[t[2]]))) / 6.0;
  }
  return v;
}

// A change's vertex rows reproduce the new positions from the old ones (to tol).
inline ::testing::AssertionResult rows_reproduce(const CageTopologyChange& c, const Cage& before,
                                                 const Cage& after, double tol = 1e-5) {
  auto p = interpolate_vertex_attribute(c, before.polygons.positions);
  for (size_t v = 0; v < p.size(); ++v)
    if (glm::length(glm::dvec3(p[v]) - glm::dvec3(after.polygons.positions[v])) > tol)
      return ::testing::AssertionFailure() << "vertex " << v << " is not its parents' combination";
  return ::testing::AssertionSuccess();
}

}  // namespace cagewrap::test
