// Tests for core/document/cage_edit.h: merging and welding vertices (collapsed faces dropped and reported),
// flipping faces, triangulating; the topology change each returns; every error.
#include "core/document/cage_edit.h"

#include <gtest/gtest.h>

#include <cmath>

#include "tests/cage_checks.h"
#include "tests/expect_error.h"
#include "tests/fixtures.h"

namespace cagewrap {
namespace {

using V = std::vector<uint32_t>;
using test::manifold_and_oriented;
using test::rows_reproduce;
using test::signed_volume;

V face_of(const PolyMesh& m, size_t f) {
  return V(m.face(f).begin(), m.face(f).end());
}

TEST(MergeVertices, MergesAtTheCentroidAndDropsCollapsedFaces) {
  const Cage oct = test::octahedron_cage();
  auto r = merge_vertices(oct, V{2, 0});
  ASSERT_TRUE(r.ok()) << r.error().message;
  const Cage& c = r->cage;
  // vertex 0 (the lowest id) becomes the merged vertex; 2 closes up: old 1 -> 1, 3 -> 2, 4 -> 3, 5 -> 4
  ASSERT_EQ(c.num_vertices(), 5u);
  EXPECT_NEAR(c.polygons.positions[0].x, 0.5f, 1e-7);
  EXPECT_NEAR(c.polygons.positions[0].y, 0.5f, 1e-7);
  EXPECT_EQ(r->change.parents_of_vertex(0).size(), 2u);
  EXPECT_EQ(V(r->change.parents_of_vertex(0).begin(), r->change.parents_of_vertex(0).end()), (V{0, 2}));
  EXPECT_DOUBLE_EQ(r->change.weights_of_vertex(0)[0], 0.5);
  EXPECT_EQ(r->change.parents_of_vertex(2)[0], 3u);
  // faces 0 (0 2 4) and 4 (2 0 5) used the merged edge: they collapse
  EXPECT_EQ(r->change.dropped_faces, (V{0, 4}));
  ASSERT_EQ(c.polygons.num_faces(), 6u);
  EXPECT_EQ(r->change.face_parent, (V{1, 2, 3, 5, 6, 7}));
  EXPECT_EQ(face_of(c.polygons, 0), (V{0, 1, 3}));  // old 2 1 4
  ASSERT_EQ(r->warnings.size(), 2u);
  EXPECT_NE(r->warnings[0].find("face 0 collapsed"), std::string::npos) << r->warnings[0];
  // still a closed, consistently oriented surface; elements map one to one to their old triangles
  EXPECT_TRUE(manifold_and_oriented(c.polygons));
  EXPECT_TRUE(test::boundary_edges(c.polygons).empty());
  EXPECT_GT(signed_volume(c), 0.0);
  for (size_t e = 0; e < c.num_elements(); ++e)
    EXPECT_EQ(V(r->change.parents_of_element(e).begin(), r->change.parents_of_element(e).end()),
              (V{r->change.face_parent[e]}));
  EXPECT_TRUE(check_change(r->change, oct, c).ok());
  EXPECT_TRUE(rows_reproduce(r->change, oct, c));
}

TEST(MergeVertices, DuplicateFacesAreDroppedAndOneVertexIsANoOp) {
  // a tetrahedron: merging two vertices collapses the two faces on their edge and makes the other two
  // the same triangle (opposite windings): the second is dropped as a duplicate
  PolyMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.add_face({0, 2, 1});
  m.add_face({0, 1, 3});
  m.add_face({1, 2, 3});
  m.add_face({2, 0, 3});
  const Cage tet = std::move(make_cage(m, "tet")).value();
  auto r = merge_vertices(tet, V{0, 1});
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r->cage.polygons.num_faces(), 1u);
  EXPECT_EQ(r->change.dropped_faces, (V{0, 1, 3}));
  ASSERT_EQ(r->warnings.size(), 3u);
  EXPECT_NE(r->warnings[2].find("face 3 now has the same corners as face 2"), std::string::npos)
      << r->warnings[2];

  auto same = merge_vertices(tet, V{2, 2});
  ASSERT_TRUE(same.ok());
  EXPECT_EQ(same->cage.polygons.face_vertices, tet.polygons.face_vertices);
  EXPECT_EQ(same->cage.polygons.positions, tet.polygons.positions);
  EXPECT_TRUE(same->change.dropped_faces.empty());
}

TEST(MergeVertices, QuadLosesACornerAndKeepsItsElementsParents) {
  // two quads side by side; merging the two ends of their shared edge turns both into triangles
  PolyMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 1, 0}};
  m.add_face({0, 1, 4, 3});
  m.add_face({1, 2, 5, 4});
  const Cage two = std::move(make_cage(m, "two quads")).value();
  auto r = merge_vertices(two, V{1, 4});
  ASSERT_TRUE(r.ok()) << r.error().message;
  ASSERT_EQ(r->cage.polygons.num_faces(), 2u);
  EXPECT_EQ(r->cage.polygons.face(0).size(), 3u);
  EXPECT_EQ(r->cage.polygons.face(1).size(), 3u);
  EXPECT_TRUE(r->change.dropped_faces.empty());
  // each new triangle lies in its old quad and overlaps the old elements of that quad only
  for (size_t e = 0; e < r->cage.num_elements(); ++e)
    for (uint32_t k : r->change.parents_of_element(e))
      EXPECT_EQ(two.element_face[k], r->change.face_parent[e]);
  EXPECT_TRUE(check_change(r->change, two, r->cage).ok());
}

TEST(WeldCageVertices, JoinsCopiesAtASeam) {
  // the octahedron with +x duplicated (vertex 6, 1e-5 away) for the faces below z = 0: an open seam
  Cage oct = test::octahedron_cage();
  PolyMesh m = oct.polygons;
  m.positions.push_back({1.f, 1e-5f, 0.f});
  for (size_t f = 4; f < m.num_faces(); ++f)
    for (uint32_t k = m.face_start[f]; k < m.face_start[f + 1]; ++k)
      if (m.face_vertices[k] == 0) m.face_vertices[k] = 6;
  const Cage seam = std::move(make_cage(m, "seam")).value();
  EXPECT_FALSE(test::boundary_edges(seam.polygons).empty());
  auto r = weld_cage_vertices(seam, 1e-3);
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r->cage.num_vertices(), 6u);
  EXPECT_EQ(r->cage.polygons.face_vertices, oct.polygons.face_vertices);
  EXPECT_NEAR(r->cage.polygons.positions[0].y, 0.5e-5f, 1e-9);  // the centroid of the two copies
  EXPECT_TRUE(test::boundary_edges(r->cage.polygons).empty());
  EXPECT_TRUE(manifold_and_oriented(r->cage.polygons));
  EXPECT_TRUE(r->change.dropped_faces.empty());
  EXPECT_TRUE(rows_reproduce(r->change, seam, r->cage));

  // a distance larger than the edges collapses everything
  EXPECT_TRUE(Fails(weld_cage_vertices(seam, 10.0), ErrorCode::kEmpty, {"collapses every face"}));
}

TEST(FlipFaces, ReversesWindingAndVolume) {
  const Cage box = fixtures::box_cage(1.0, 2);
  auto r = flip_all_faces(box);
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_NEAR(signed_volume(r->cage), -signed_volume(box), 1e-9);
  EXPECT_TRUE(manifold_and_oriented(r->cage.polygons));
  for (size_t f = 0; f < box.polygons.num_faces(); ++f) {
    V old = face_of(box.polygons, f), now = face_of(r->cage.polygons, f);
    EXPECT_EQ(now[0], old[0]);
    EXPECT_EQ(V(now.rbegin(), now.rend() - 1), V(old.begin() + 1, old.end()));
  }
  for (size_t e = 0; e < r->cage.num_elements(); ++e) {
    auto parents = r->change.parents_of_element(e);
    ASSERT_FALSE(parents.empty());
    for (uint32_t k : parents) EXPECT_EQ(box.element_face[k], r->cage.element_face[e]);
  }
  // flipping twice gives the cage back
  auto back = flip_all_faces(r->cage);
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(back->cage.polygons.face_vertices, box.polygons.face_vertices);

  // one face: only it changes, and its edges become misoriented against its neighbours
  auto one = flip_faces(box, V{3});
  ASSERT_TRUE(one.ok());
  for (size_t f = 0; f < box.polygons.num_faces(); ++f)
    if (f != 3) {
      EXPECT_EQ(face_of(one->cage.polygons, f), face_of(box.polygons, f));
    }
  EXPECT_NE(face_of(one->cage.polygons, 3), face_of(box.polygons, 3));
  EXPECT_FALSE(manifold_and_oriented(one->cage.polygons));
}

TEST(TriangulateCage, ElementsBecomeFacesOneToOne) {
  const Cage cyl = fixtures::cylinder_cage();
  auto r = triangulate_cage(cyl);
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(r->cage.polygons.all_triangles());
  ASSERT_EQ(r->cage.num_elements(), cyl.num_elements());
  for (size_t e = 0; e < cyl.num_elements(); ++e) {
    EXPECT_EQ(r->cage.elements[e], cyl.elements[e]);
    EXPECT_EQ(r->change.parents_of_element(e)[0], e);
    EXPECT_EQ(r->change.face_parent[e], cyl.element_face[e]);
  }
  EXPECT_TRUE(check_change(r->change, cyl, r->cage).ok());
}

TEST(CageEditErrors, NameTheVertexOrFace) {
  const Cage oct = test::octahedron_cage();
  EXPECT_TRUE(Fails(merge_vertices(oct, V{1, 40}), ErrorCode::kIndexOutOfRange,
                    {"vertex 40 out of range", "6 vertices"}));
  EXPECT_TRUE(Fails(merge_vertices(oct, V{}), ErrorCode::kInvalidArgument, {"no vertices"}));
  EXPECT_TRUE(Fails(merge_vertices(oct, V{0, 1, 2, 3, 4, 5}), ErrorCode::kEmpty, {"collapses every face"}));
  EXPECT_TRUE(Fails(weld_cage_vertices(oct, 0.0), ErrorCode::kInvalidArgument, {"weld distance"}));
  EXPECT_TRUE(Fails(weld_cage_vertices(oct, NAN), ErrorCode::kInvalidArgument, {"weld distance"}));
  EXPECT_TRUE(
      Fails(flip_faces(oct, V{2, 12}), ErrorCode::kIndexOutOfRange, {"face 12 out of range", "8 faces"}));
  EXPECT_TRUE(Fails(flip_faces(oct, V{}), ErrorCode::kInvalidArgument, {"no faces"}));
  Cage bad = oct;
  bad.polygons.positions[3].x = NAN;
  EXPECT_TRUE(Fails(flip_all_faces(bad), ErrorCode::kNonFinite, {"vertex 3"}));
  EXPECT_TRUE(Fails(triangulate_cage(bad), ErrorCode::kNonFinite, {"vertex 3"}));
}

}  // namespace
}  // namespace cagewrap
