// Quad pairing: flat grids become quads, bent, concave or badly shaped pairs stay triangles, and
// the quads triangulate back into exactly the input triangles.
#include "core/cage/quad_pairing.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

namespace cagewrap {
namespace {

// A triangle with its corners rotated so the smallest index comes first (same orientation).
Tri canonical(Tri t) {
  std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
  return t;
}
std::vector<Tri> sorted_triangles(std::vector<Tri> tris) {
  for (Tri& t : tris) t = canonical(t);
  std::sort(tris.begin(), tris.end());
  return tris;
}

// An n x n grid of unit squares in the z = 0 plane, each split along one diagonal (alternating).
struct Grid {
  std::vector<glm::vec3> p;
  std::vector<Tri> t;
};
Grid flat_grid(int n) {
  Grid g;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) g.p.emplace_back(float(i), float(j), 0.f);
  auto at = [&](int i, int j) { return uint32_t(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const uint32_t a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
      if ((i + j) % 2 == 0) {
        g.t.push_back({a, b, c});
        g.t.push_back({a, c, d});
      } else {
        g.t.push_back({a, b, d});
        g.t.push_back({b, c, d});
      }
    }
  return g;
}

TEST(QuadPairing, FlatGridBecomesSquaresThatTriangulateBack) {
  const Grid g = flat_grid(4);
  const QuadPairing q = pair_quads(g.p, g.t);
  EXPECT_EQ(q.quads, 16u) << "each square's own diagonal is the best pair (90-degree corners)";
  EXPECT_EQ(q.triangles, 0u);
  EXPECT_EQ(q.mesh.num_faces(), 16u);
  EXPECT_EQ(q.mesh.positions, g.p);
  // the control elements are exactly the input triangles, with their orientation
  EXPECT_EQ(sorted_triangles(triangulate(q.mesh).triangles), sorted_triangles(g.t));
  for (size_t f = 0; f < q.mesh.num_faces(); ++f) {
    const auto c = q.mesh.face(f);
    ASSERT_EQ(c.size(), 4u);
    // outward (+z) like the triangles, and a unit square
    const glm::vec3 n = glm::cross(g.p[c[1]] - g.p[c[0]], g.p[c[2]] - g.p[c[0]]);
    EXPECT_GT(n.z, 0.f);
    for (int k = 0; k < 4; ++k) EXPECT_FLOAT_EQ(glm::length(g.p[c[(k + 1) % 4]] - g.p[c[k]]), 1.f);
  }
}

TEST(QuadPairing, BentConcaveAndBadlyShapedPairsStayTriangles) {
  // two triangles sharing the edge (0, 1) on the x axis; the apex of the second is placed per case
  auto pair = [](glm::vec3 apex) {
    Grid g;
    g.p = {{0, 0, 0}, {1, 0, 0}, {0.5f, 1, 0}, apex};
    g.t = {{0, 1, 2}, {1, 0, 3}};
    return g;
  };
  auto quads = [](const Grid& g, QuadPairingParams p = {}) { return pair_quads(g.p, g.t, p).quads; };
  EXPECT_EQ(quads(pair({0.5f, -1, 0})), 1u) << "a flat rhombus: corners 53 and 127 degrees";
  // bent by 30 degrees about the shared edge: over the default 20, under a 40-degree limit
  const float c = std::cos(30.f * 3.14159265f / 180.f), s = std::sin(30.f * 3.14159265f / 180.f);
  const Grid bent = pair({0.5f, -c, s});
  EXPECT_EQ(quads(bent), 0u);
  QuadPairingParams loose;
  loose.max_bend = 40;
  EXPECT_EQ(quads(bent, loose), 1u);
  EXPECT_EQ(quads(pair({1.5f, -0.2f, 0})), 0u) << "a dart: the corner at vertex 1 is reflex";
  EXPECT_EQ(quads(pair({0.5f, -0.1f, 0})), 0u) << "a 157-degree corner at the apex";
  EXPECT_EQ(quads(pair({0.5f, 1, 0})), 0u) << "the second triangle folded onto the first";
  // a misoriented pair (the second triangle traverses the edge the same way) is left alone
  Grid mis = pair({0.5f, -1, 0});
  mis.t[1] = {0, 1, 3};
  EXPECT_EQ(quads(mis), 0u);
  // an edge shared by three triangles is never merged across
  Grid fan = pair({0.5f, -1, 0});
  fan.p.push_back({0.5f, 0, 1});
  fan.t.push_back({1, 0, 4});
  const QuadPairing f = pair_quads(fan.p, fan.t);
  EXPECT_EQ(f.quads, 0u);
  EXPECT_EQ(f.triangles, 3u);
}

TEST(QuadPairing, BestPairsWinAndTheResultIsDeterministic) {
  // a strip of three triangles: the middle one can pair left (a unit square) or right (a
  // parallelogram with 45/135-degree corners); the square wins, the last triangle stays alone
  Grid g;
  g.p = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  g.t = {{0, 1, 3}, {1, 4, 3}, {1, 2, 4}};
  const QuadPairing q = pair_quads(g.p, g.t);
  EXPECT_EQ(q.quads, 1u);
  EXPECT_EQ(q.triangles, 1u);
  ASSERT_EQ(q.mesh.num_faces(), 2u);
  EXPECT_EQ(q.mesh.face(0).size(), 4u);
  std::vector<uint32_t> corners(q.mesh.face(0).begin(), q.mesh.face(0).end());
  std::sort(corners.begin(), corners.end());
  EXPECT_EQ(corners, (std::vector<uint32_t>{0, 1, 3, 4}));
  // alone, the right pair is a quad too
  const std::vector<Tri> right = {g.t[1], g.t[2]};
  EXPECT_EQ(pair_quads(g.p, right).quads, 1u);
  EXPECT_EQ(sorted_triangles(triangulate(q.mesh).triangles), sorted_triangles(g.t));
  const QuadPairing again = pair_quads(g.p, g.t);
  EXPECT_EQ(again.mesh.face_vertices, q.mesh.face_vertices);
}

}  // namespace
}  // namespace cagewrap
