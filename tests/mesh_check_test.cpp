// Welding, mesh checks and signed distance: exact answers on hand-built meshes.
#include "core/cage/mesh_check.h"

#include <cmath>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "core/geometry/surface_distance.h"
#include "core/geometry/weld.h"
#include "tests/fixtures.h"

namespace cagewrap {
namespace {

// Unit cube [0, 1]^3, 12 outward triangles.
struct TriMesh {
  std::vector<glm::vec3> p;
  std::vector<Tri> t;
};
TriMesh unit_cube(glm::vec3 offset = glm::vec3(0.0f)) {
  TriMesh m;
  for (int i = 0; i < 8; ++i)
    m.p.push_back(offset + glm::vec3((i & 1) ? 1.f : 0.f, (i & 2) ? 1.f : 0.f, (i & 4) ? 1.f : 0.f));
  const uint32_t quads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (const auto& q : quads) {
    m.t.push_back({q[0], q[1], q[2]});
    m.t.push_back({q[0], q[2], q[3]});
  }
  return m;
}

TEST(Weld, SeamCopiesMergeAndFarPointsStay) {
  // two triangles sharing an edge, written with separate copies of the shared vertices (a UV seam)
  std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0},          {0, 1, 0},           {1, 0, 0},
                              {1, 1, 0}, {0, 1.0000001f, 0}, {0.5f, 0.5f, 0.001f}};
  const Weld w = weld_vertices(p, 1e-5);
  ASSERT_EQ(w.positions.size(), 5u);
  EXPECT_EQ(w.remap, (std::vector<uint32_t>{0, 1, 2, 1, 3, 2, 4}));  // the lowest index represents a cluster
  std::vector<Tri> tris = {{0, 1, 2}, {3, 4, 5}, {1, 2, 0}, {0, 3, 1}};
  uint32_t dropped = 0;
  const auto out = weld_triangles(tris, w.remap, &dropped);
  // {1,2,0} repeats the first triangle; {0,3,1} collapses (3 and 1 weld together)
  EXPECT_EQ(dropped, 2u);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[1], (Tri{1, 3, 2}));
  // zero tolerance turns welding off
  EXPECT_EQ(weld_vertices(p, 0.0).positions.size(), 7u);
}

TEST(Weld, ClustersAreTransitive) {
  // a chain of points each 0.8 tolerance apart collapses to one vertex
  std::vector<glm::vec3> p;
  for (int i = 0; i < 10; ++i) p.emplace_back(0.8f * i, 0, 0);
  p.emplace_back(100, 0, 0);
  const Weld w = weld_vertices(p, 1.0);
  EXPECT_EQ(w.positions.size(), 2u);
  EXPECT_EQ(w.remap[9], 0u);
  EXPECT_EQ(w.remap[10], 1u);
}

TEST(MeshCheck, ClosedCubeIsClean) {
  const TriMesh c = unit_cube();
  const MeshCheck m = check_mesh(c.p, c.t);
  EXPECT_EQ(m.triangles, 12u);
  EXPECT_EQ(m.edges, 18u);
  EXPECT_TRUE(m.closed());
  EXPECT_TRUE(m.manifold());
  EXPECT_TRUE(m.oriented());
  EXPECT_FALSE(m.self_intersecting());
  EXPECT_EQ(m.components, 1u);
  EXPECT_EQ(m.degenerate_triangles, 0u);
  EXPECT_EQ(m.needle_triangles, 0u);
  EXPECT_NEAR(m.signed_volume, 1.0, 1e-12);
  EXPECT_NEAR(m.worst_aspect, 2.0, 1e-12);  // right isosceles: hypotenuse sqrt 2 over altitude sqrt 2 / 2
}

TEST(MeshCheck, CountsEveryDefect) {
  TriMesh c = unit_cube();
  {
    auto t = c.t;
    t.pop_back();  // a hole: 3 boundary edges
    const MeshCheck m = check_mesh(c.p, t);
    EXPECT_EQ(m.boundary_edges, 3u);
    EXPECT_FALSE(m.closed());
  }
  {
    auto t = c.t;
    std::swap(t[0][1], t[0][2]);  // one triangle flipped: its 3 edges are traversed twice the same way
    EXPECT_EQ(check_mesh(c.p, t).misoriented_edges, 3u);
  }
  {
    auto p = c.p;
    auto t = c.t;
    p.emplace_back(0.5f, 0.5f, 3.0f);
    t.push_back({0, 4, 8});  // a fin on edge 0-4: used by three triangles
    const MeshCheck m = check_mesh(p, t);
    EXPECT_EQ(m.non_manifold_edges, 1u);
    EXPECT_EQ(m.boundary_edges, 2u);
  }
  {
    std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0}, {0.5f, 0.05f, 0}, {2, 0, 0}, {3, 0, 0}, {2.5f, 0, 0}};
    std::vector<Tri> t = {{0, 1, 2}, {3, 4, 5}};  // a needle (aspect 20) and a zero-area triangle
    const MeshCheck m = check_mesh(p, t);
    EXPECT_EQ(m.needle_triangles, 1u);
    EXPECT_EQ(m.degenerate_triangles, 1u);
    EXPECT_NEAR(m.worst_aspect, 20.0, 1e-5);
    EXPECT_EQ(m.components, 2u);
  }
}

TEST(MeshCheck, FindsSelfCrossingsBetweenPieces) {
  TriMesh a = unit_cube(), b = unit_cube({0.5f, 0.5f, 0.5f});
  for (Tri t : b.t) a.t.push_back({t[0] + 8, t[1] + 8, t[2] + 8});
  a.p.insert(a.p.end(), b.p.begin(), b.p.end());
  const auto x = self_crossings(a.p, a.t);
  EXPECT_GT(x.size(), 0u);
  for (const SelfCrossing& c : x) {
    EXPECT_LT(c.a, c.b);
    EXPECT_NE(c.a < 8, a.t[c.triangle][0] < 8) << "crossings are between the two cubes";
  }
  // check_mesh counts them as crossings between pieces, not as a piece folding over itself
  const MeshCheck overlapping = check_mesh(a.p, a.t);
  EXPECT_EQ(overlapping.piece_crossings, x.size());
  EXPECT_EQ(overlapping.self_intersections, 0u);
  EXPECT_FALSE(overlapping.self_intersecting());
  TriMesh far = unit_cube(), d = unit_cube({1.5f, 0, 0});
  for (Tri t : d.t) far.t.push_back({t[0] + 8, t[1] + 8, t[2] + 8});
  far.p.insert(far.p.end(), d.p.begin(), d.p.end());
  EXPECT_TRUE(self_crossings(far.p, far.t).empty());
  EXPECT_EQ(check_mesh(far.p, far.t).components, 2u);
}

TEST(MeshCheck, AFoldIsASelfIntersection) {
  // a cube with its faces split 2 x 2, the top face's centre pushed down through the bottom face:
  // one piece passing through itself
  const Cage box = fixtures::box_cage(1.0, 2);
  TriMesh c{box.polygons.positions, box.elements};
  for (glm::vec3& v : c.p)
    if (glm::length(v - glm::vec3(0, 0, 1)) < 1e-6f) v = {0, 0, -2};
  const MeshCheck m = check_mesh(c.p, c.t);
  EXPECT_EQ(m.components, 1u);
  EXPECT_GT(m.self_intersections, 0u);
  EXPECT_EQ(m.piece_crossings, 0u);
  EXPECT_EQ(m.self_intersections, self_crossings(c.p, c.t).size());
}

TEST(SurfaceDistance, SignsAndDistancesOnACube) {
  const TriMesh c = unit_cube();
  const SurfaceDistance sd(c.p, c.t);
  struct Case {
    glm::dvec3 p;
    double d;
  } cases[] = {
      {{0.5, 0.5, 0.5}, -0.5},              // centre
      {{0.5, 0.2, 0.5}, -0.2},              // nearest the bottom face
      {{0.5, 0.5, 1.3}, 0.3},               // above the front face
      {{1.2, 0.5, 1.2}, std::sqrt(0.08)},   // in an edge's region
      {{1.1, -0.1, 1.1}, std::sqrt(0.03)},  // in a corner's region
      {{0.95, 0.97, 0.99}, -0.01},          // inside near a corner
  };
  for (const Case& k : cases) {
    const SurfacePoint q = sd.query(k.p);
    EXPECT_NEAR(q.distance, k.d, 1e-6) << k.p.x << " " << k.p.y << " " << k.p.z;
    EXPECT_NEAR(glm::length(q.point - k.p), std::abs(k.d), 1e-6);
    EXPECT_NEAR(sd.winding_number(k.p), k.d < 0 ? 1.0 : 0.0, 1e-9);
  }
  // turning the cube inside-out turns the signs
  auto flipped = c.t;
  for (Tri& t : flipped) std::swap(t[1], t[2]);
  EXPECT_NEAR(SurfaceDistance(c.p, flipped).query({0.5, 0.5, 0.5}).distance, 0.5, 1e-9);
}

TEST(SurfaceDistance, WindingNumberCountsOverlappingPieces) {
  TriMesh a = unit_cube(), b = unit_cube({0.5f, 0.5f, 0.5f});
  for (Tri t : b.t) a.t.push_back({t[0] + 8, t[1] + 8, t[2] + 8});
  a.p.insert(a.p.end(), b.p.begin(), b.p.end());
  const SurfaceDistance sd(a.p, a.t);
  EXPECT_NEAR(sd.winding_number({0.75, 0.75, 0.75}), 2.0, 1e-9);
  EXPECT_NEAR(sd.winding_number({0.25, 0.25, 0.25}), 1.0, 1e-9);
  EXPECT_NEAR(sd.winding_number({1.25, 1.25, 1.25}), 1.0, 1e-9);
  EXPECT_NEAR(sd.winding_number({3, 3, 3}), 0.0, 1e-9);
}

}  // namespace
}  // namespace cagewrap
