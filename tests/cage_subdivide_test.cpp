// Tests for core/document/cage_subdivide.h: linear subdivision keeps the surface, Loop smooths and converges
// (counts V + E and 4F, boundary rules), red-green refinement leaves no T-junction and keeps the
// surface closed, manifold and oriented; quads; errors.
#include "core/document/cage_subdivide.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "core/document/cage_edit.h"
#include "core/cage/mesh_check.h"
#include "tests/cage_checks.h"
#include "tests/expect_error.h"
#include "tests/fixtures.h"

namespace cagewrap {
namespace {

using V = std::vector<uint32_t>;
using test::boundary_edges;
using test::distance_to_cage;
using test::manifold_and_oriented;
using test::no_t_junctions;
using test::rows_reproduce;
using test::signed_volume;

Cage subdivided_cage_of(PolyMesh m) {
  return std::move(make_cage(std::move(m), "test cage")).value();
}

// n x n vertices on z = 0, quads split into triangles: an open disc-like sheet.
Cage triangle_grid(int n) {
  PolyMesh m;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) m.positions.emplace_back(x, y, 0);
  for (uint32_t y = 0; y + 1 < uint32_t(n); ++y)
    for (uint32_t x = 0; x + 1 < uint32_t(n); ++x) {
      uint32_t a = y * n + x, b = a + 1, c = a + n + 1, d = a + n;
      m.add_face({a, b, c});
      m.add_face({a, c, d});
    }
  return subdivided_cage_of(std::move(m));
}

size_t count_edges(const PolyMesh& m) {
  return unique_edges(m).size();
}

double boundary_length(const PolyMesh& m) {
  double len = 0.0;
  for (auto [a, b] : boundary_edges(m))
    len += glm::length(glm::dvec3(m.positions[a]) - glm::dvec3(m.positions[b]));
  return len;
}

// The properties every conforming refinement of a closed cage must have.
void expect_conforming_on_surface(const Cage& before, const CageEdit& r) {
  EXPECT_TRUE(manifold_and_oriented(r.cage.polygons));
  EXPECT_TRUE(no_t_junctions(r.cage.polygons));
  EXPECT_EQ(boundary_edges(r.cage.polygons).size(), 0u);
  const MeshCheck mc = check_mesh(r.cage.polygons.positions, r.cage.elements, false);
  EXPECT_TRUE(mc.closed() && mc.manifold() && mc.oriented()) << mc.summary();
  EXPECT_NEAR(signed_volume(r.cage), signed_volume(before), 1e-5 * std::abs(signed_volume(before)));
  for (size_t v = 0; v < r.cage.num_vertices(); ++v)
    EXPECT_LT(distance_to_cage(glm::dvec3(r.cage.polygons.positions[v]), before), 1e-6) << "vertex " << v;
  EXPECT_TRUE(check_change(r.change, before, r.cage).ok());
  EXPECT_TRUE(rows_reproduce(r.change, before, r.cage));
}

// Every new element's centroid lies on one of its parent elements (planar polygons).
void expect_elements_inside_parents(const Cage& before, const CageEdit& r) {
  const auto& x = r.cage.polygons.positions;
  const auto& ox = before.polygons.positions;
  for (size_t e = 0; e < r.cage.num_elements(); ++e) {
    const Tri& t = r.cage.elements[e];
    glm::dvec3 c = (glm::dvec3(x[t[0]]) + glm::dvec3(x[t[1]]) + glm::dvec3(x[t[2]])) / 3.0;
    double best = 1e300;
    for (uint32_t k : r.change.parents_of_element(e)) {
      const Tri& o = before.elements[k];
      best = std::min(
          best, closest_point_on_triangle(c, glm::dvec3(ox[o[0]]), glm::dvec3(ox[o[1]]), glm::dvec3(ox[o[2]]))
                    .dist2);
    }
    EXPECT_LT(std::sqrt(best), 1e-6) << "element " << e;
  }
}

// ------------------------------------------------------------------------------------------ linear

TEST(SubdivideLinear, CubeQuadsBecomeFourQuadsOnTheSameSurface) {
  const Cage cube = fixtures::box_cage(1.0, 1);
  auto r = subdivide_linear(cube);
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r->cage.num_vertices(), 8u + 12u + 6u);  // V + E + F
  ASSERT_EQ(r->cage.polygons.num_faces(), 24u);
  for (size_t f = 0; f < 24; ++f) EXPECT_EQ(r->cage.polygons.face(f).size(), 4u);
  for (size_t f = 0; f < 24; ++f) EXPECT_EQ(r->change.face_parent[f], f / 4);
  expect_conforming_on_surface(cube, *r);
  expect_elements_inside_parents(cube, *r);
  EXPECT_TRUE(r->change.dropped_faces.empty());
}

TEST(SubdivideLinear, TrianglesQuadsAndOctagonsAtTwoLevels) {
  const Cage cyl = fixtures::cylinder_cage();  // 40 quads, 2 octagons
  auto one = subdivide_linear(cyl, 1);
  ASSERT_TRUE(one.ok());
  EXPECT_EQ(one->cage.polygons.num_faces(), 40u * 4 + 2u * 8);
  EXPECT_EQ(one->cage.num_vertices(), cyl.num_vertices() + count_edges(cyl.polygons) + 42u);
  expect_conforming_on_surface(cyl, *one);
  expect_elements_inside_parents(cyl, *one);

  auto two = subdivide_linear(cyl, 2);
  ASSERT_TRUE(two.ok());
  EXPECT_EQ(two->cage.polygons.num_faces(), one->cage.polygons.num_faces() * 4);
  expect_conforming_on_surface(cyl, *two);
  expect_elements_inside_parents(cyl, *two);

  const Cage oct = test::octahedron_cage();
  auto tri = subdivide_linear(oct);
  ASSERT_TRUE(tri.ok());
  EXPECT_EQ(tri->cage.num_vertices(), 6u + 12u);
  EXPECT_EQ(tri->cage.polygons.num_faces(), 32u);
  EXPECT_TRUE(tri->cage.polygons.all_triangles());
  expect_conforming_on_surface(oct, *tri);
  for (size_t e = 0; e < tri->cage.num_elements(); ++e)
    EXPECT_EQ(V(tri->change.parents_of_element(e).begin(), tri->change.parents_of_element(e).end()),
              (V{uint32_t(e / 4)}));
}

// ------------------------------------------------------------------------------------------ Loop

TEST(SubdivideLoop, CubeCountsAndEveryVertexMovesInside) {
  const Cage cube = fixtures::box_cage(1.0, 1);
  auto r = subdivide_loop(cube);  // the 6 quads are triangulated first: V 8, E 18, F 12
  ASSERT_TRUE(r.ok()) << r.error().message;
  ASSERT_EQ(r->warnings.size(), 1u);
  EXPECT_NE(r->warnings[0].find("6 faces that are not triangles"), std::string::npos) << r->warnings[0];
  EXPECT_EQ(r->cage.num_vertices(), 8u + 18u);
  EXPECT_EQ(r->cage.polygons.num_faces(), 4u * 12u);
  EXPECT_TRUE(r->cage.polygons.all_triangles());
  EXPECT_TRUE(manifold_and_oriented(r->cage.polygons));
  EXPECT_TRUE(boundary_edges(r->cage.polygons).empty());
  // convex combinations of the corners: inside the closed cube; the old corners strictly inside
  for (size_t v = 0; v < r->cage.num_vertices(); ++v) {
    const glm::vec3& p = r->cage.polygons.positions[v];
    EXPECT_LE(std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}), 1.0 + 1e-6) << "vertex " << v;
    if (v < 8) {
      EXPECT_LT(std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}), 0.9) << "corner " << v;
    }
  }
  EXPECT_LT(signed_volume(r->cage), signed_volume(cube));
  EXPECT_GT(signed_volume(r->cage), 0.0);
  EXPECT_TRUE(check_change(r->change, cube, r->cage).ok());
  EXPECT_TRUE(rows_reproduce(r->change, cube, r->cage));
  for (size_t v = 0; v < r->cage.num_vertices(); ++v)
    for (double w : r->change.weights_of_vertex(v)) EXPECT_GT(w, 0.0);
  // every element of the result comes from one element of the cube (the triangulation is one to one)
  for (size_t e = 0; e < r->cage.num_elements(); ++e) {
    EXPECT_EQ(r->change.parents_of_element(e).size(), 1u);
    EXPECT_EQ(r->change.parents_of_element(e)[0], e / 4);
  }
}

TEST(SubdivideLoop, ConvergesAndShrinksTowardTheLimit) {
  const Cage cube = fixtures::box_cage(1.0, 1);
  std::vector<glm::dvec3> corner_path[8];
  double volume_before = signed_volume(cube);
  for (uint32_t levels = 1; levels <= 4; ++levels) {
    auto r = subdivide_loop(cube, levels);
    ASSERT_TRUE(r.ok());
    for (int c = 0; c < 8; ++c)
      corner_path[c].emplace_back(r->cage.polygons.positions[c]);  // even vertices keep ids
    const double volume = signed_volume(r->cage);
    EXPECT_LT(volume, volume_before);  // smoothing a convex shape only removes volume
    volume_before = volume;
  }
  for (int c = 0; c < 8; ++c) {
    double previous = 1e300;
    for (size_t l = 1; l < corner_path[c].size(); ++l) {
      const double step = glm::length(corner_path[c][l] - corner_path[c][l - 1]);
      EXPECT_LT(step, 0.75 * previous) << "corner " << c << " level " << l;  // geometric convergence
      previous = step;
    }
  }
}

TEST(SubdivideLoop, BoundaryFollowsTheBoundaryRules) {
  Cage grid = triangle_grid(4);  // 12 boundary edges, 4 interior vertices
  auto r = subdivide_loop(grid);
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(r->warnings.empty());
  EXPECT_EQ(r->cage.num_vertices(), grid.num_vertices() + count_edges(grid.polygons));
  EXPECT_EQ(boundary_edges(r->cage.polygons).size(), 2 * boundary_edges(grid.polygons).size());
  EXPECT_TRUE(manifold_and_oriented(r->cage.polygons));
  // a boundary edge's new vertex is its midpoint; a boundary vertex moves to 3/4 v + 1/8 (a + b)
  for (size_t v = 0; v < r->cage.num_vertices(); ++v) EXPECT_EQ(r->cage.polygons.positions[v].z, 0.f);
  EXPECT_NEAR(r->cage.polygons.positions[1].x, 1.0f, 1e-6);  // (1, 0): 3/4 (1,0) + 1/8 (0,0) + 1/8 (2,0)
  EXPECT_NEAR(r->cage.polygons.positions[1].y, 0.0f, 1e-6);
  EXPECT_NEAR(r->cage.polygons.positions[0].x, 0.125f, 1e-6);  // the corner (0, 0) with (1, 0) and (0, 1)
  // boundary vertices depend on boundary vertices only: lifting an interior vertex leaves them alone
  Cage lifted = grid;
  lifted.polygons.positions[5].z = 1.0f;
  auto l = subdivide_loop(lifted);
  ASSERT_TRUE(l.ok());
  std::set<uint32_t> on_boundary;
  for (auto [a, b] : boundary_edges(r->cage.polygons)) on_boundary.insert({a, b});
  for (uint32_t v : on_boundary) EXPECT_EQ(l->cage.polygons.positions[v], r->cage.polygons.positions[v]) << v;
  EXPECT_GT(l->cage.polygons.positions[5].z, 0.5f);
}

TEST(SubdivideLoop, RejectsPolygonsWhenAsked) {
  EXPECT_TRUE(Fails(subdivide_loop(fixtures::box_cage(1.0, 1), 1, LoopNonTriangles::kReject),
                    ErrorCode::kInvalidArgument, {"face 0 is not a triangle", "4 corners"}));
  EXPECT_TRUE(subdivide_loop(test::octahedron_cage(), 1, LoopNonTriangles::kReject).ok());
}

// ------------------------------------------------------------------------------------------ red-green

TEST(RefineFaces, TwoTrianglesRedAndGreen) {
  PolyMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  m.add_face({0, 1, 2});
  m.add_face({0, 2, 3});
  const Cage square = subdivided_cage_of(m);
  auto r = refine_faces(square, V{0});
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r->cage.num_vertices(), 7u);
  EXPECT_EQ(r->cage.polygons.num_faces(), 6u);  // 4 red + 2 green
  EXPECT_EQ(r->change.face_parent, (V{0, 0, 0, 0, 1, 1}));
  EXPECT_TRUE(manifold_and_oriented(r->cage.polygons));
  EXPECT_TRUE(no_t_junctions(r->cage.polygons));
  // the same boundary: as long, and every boundary vertex on the old boundary
  EXPECT_NEAR(boundary_length(r->cage.polygons), boundary_length(square.polygons), 1e-6);
  EXPECT_EQ(boundary_edges(r->cage.polygons).size(), 6u);
  for (auto [a, b] : boundary_edges(r->cage.polygons))
    for (uint32_t v : {a, b}) {
      const glm::vec3& p = r->cage.polygons.positions[v];
      EXPECT_TRUE(p.x == 0 || p.x == 1 || p.y == 0 || p.y == 1) << v;
    }
}

TEST(RefineFaces, ClosureTurnsTwiceSplitTrianglesRed) {
  const Cage oct = test::octahedron_cage();
  // faces 0 (0 2 4) and 2 (1 3 4): faces 1 and 3 share an edge with each, so they turn red; the lower
  // four have one split edge each and are bisected
  auto r = refine_faces(oct, V{2, 0});
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r->cage.num_vertices(), 6u + 8u);
  EXPECT_EQ(r->cage.polygons.num_faces(), 4u * 4u + 4u * 2u);
  expect_conforming_on_surface(oct, *r);
  expect_elements_inside_parents(oct, *r);
}

TEST(RefineFaces, TriangleMeshStaysClosedAndUntouchedFacesStay) {
  const Cage tube = subdivided_cage_of(fixtures::cylinder_skin(0.5, 4.0, 8, 4));
  const V selected{3, 10, 11, 40};
  auto r = refine_faces(tube, selected);
  ASSERT_TRUE(r.ok()) << r.error().message;
  expect_conforming_on_surface(tube, *r);
  expect_elements_inside_parents(tube, *r);
  std::vector<int> children(tube.polygons.num_faces(), 0);
  for (uint32_t f : r->change.face_parent) ++children[f];
  for (uint32_t f : selected) EXPECT_EQ(children[f], 4);
  // a face with one child is copied unchanged
  for (size_t f = 0, at = 0; f < children.size(); at += children[f], ++f)
    if (children[f] == 1) {
      auto a = tube.polygons.face(f), b = r->cage.polygons.face(at);
      EXPECT_TRUE(std::equal(a.begin(), a.end(), b.begin(), b.end())) << "face " << f;
    }
  EXPECT_GT(std::count(children.begin(), children.end(), 1), 20);  // the refinement stays local
}

TEST(RefineFaces, QuadsSplitIntoQuadsAndNeighboursConform) {
  const Cage cyl = fixtures::cylinder_cage();
  // face 17 is a quad in the middle of the tube (ring segment 2, side 1)
  auto r = refine_faces(cyl, V{17});
  ASSERT_TRUE(r.ok()) << r.error().message;
  expect_conforming_on_surface(cyl, *r);
  expect_elements_inside_parents(cyl, *r);
  std::vector<V> kids(cyl.polygons.num_faces());
  for (uint32_t f = 0; f < r->change.face_parent.size(); ++f) kids[r->change.face_parent[f]].push_back(f);
  ASSERT_EQ(kids[17].size(), 4u);
  for (uint32_t f : kids[17]) EXPECT_EQ(r->cage.polygons.face(f).size(), 4u);
  for (uint32_t n : {16u, 18u, 9u, 25u}) {  // the four edge neighbours: 3 triangles each
    ASSERT_EQ(kids[n].size(), 3u) << "face " << n;
    for (uint32_t f : kids[n]) EXPECT_EQ(r->cage.polygons.face(f).size(), 3u);
  }
  EXPECT_EQ(r->cage.polygons.num_faces(), cyl.polygons.num_faces() + 3 + 4 * 2);

  // a quad next to the octagon cap: the cap turns red, and the closure runs around the ring
  auto cap = refine_faces(cyl, V{1});
  ASSERT_TRUE(cap.ok());
  expect_conforming_on_surface(cyl, *cap);
  expect_elements_inside_parents(cyl, *cap);
}

TEST(RefineFaces, QuadWithTwoOppositeSplitEdgesBecomesTwoQuads) {
  PolyMesh m;  // a strip of three unit quads along x
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x) m.positions.emplace_back(x, y, 0);
  for (uint32_t x = 0; x < 3; ++x) m.add_face({x, x + 1, x + 5, x + 4});
  const Cage strip = subdivided_cage_of(m);
  auto r = refine_faces(strip, V{0, 2});
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->cage.polygons.num_faces(), 4u + 2u + 4u);
  for (size_t f = 0; f < r->cage.polygons.num_faces(); ++f) EXPECT_EQ(r->cage.polygons.face(f).size(), 4u);
  EXPECT_TRUE(manifold_and_oriented(r->cage.polygons));
  EXPECT_TRUE(no_t_junctions(r->cage.polygons));
  EXPECT_NEAR(boundary_length(r->cage.polygons), boundary_length(strip.polygons), 1e-6);
}

TEST(RefineFaces, SelectingEveryFaceIsLinearSubdivision) {
  const Cage cyl = fixtures::cylinder_cage();
  V all(cyl.polygons.num_faces());
  for (uint32_t f = 0; f < all.size(); ++f) all[f] = f;
  auto a = refine_faces(cyl, all);
  auto b = subdivide_linear(cyl);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ(a->cage.polygons.face_vertices, b->cage.polygons.face_vertices);
  EXPECT_EQ(a->cage.polygons.positions, b->cage.polygons.positions);
  EXPECT_EQ(a->change.element_parents, b->change.element_parents);
}

TEST(SubdivideErrors, NameTheFaceAndTheLevels) {
  const Cage oct = test::octahedron_cage();
  EXPECT_TRUE(
      Fails(refine_faces(oct, V{1, 12}), ErrorCode::kIndexOutOfRange, {"face 12 out of range", "8 faces"}));
  EXPECT_TRUE(Fails(refine_faces(oct, V{}), ErrorCode::kInvalidArgument, {"no faces"}));
  EXPECT_TRUE(
      Fails(subdivide_linear(oct, 0), ErrorCode::kInvalidArgument, {"levels must be 1 to 6", "not 0"}));
  EXPECT_TRUE(Fails(subdivide_loop(oct, 7), ErrorCode::kInvalidArgument, {"levels must be 1 to 6", "not 7"}));
  Cage bad = oct;
  bad.polygons.face_vertices[4] = 99;  // face 1 uses a vertex that does not exist
  EXPECT_TRUE(Fails(subdivide_linear(bad), ErrorCode::kIndexOutOfRange, {"face 1", "vertex 99"}));
}

}  // namespace
}  // namespace cagewrap
