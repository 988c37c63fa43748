// Tests for core/io/cage_import.h: each kind of cage problem is found and named by element, face,
// edge or vertex; a clean cage has none; glTF files can be read as cages.
#include <gtest/gtest.h>

#include <algorithm>

#include "core/io/cage_import.h"
#include "core/character/demo_character.h"
#include "core/io/gltf_writer.h"
#include "tests/expect_error.h"
#include "tests/fixtures.h"

namespace cagewrap {
namespace {

bool has_line(const CageProblems& p, const std::string& part) {
  return std::any_of(p.lines.begin(), p.lines.end(), [&](const std::string& l) { return l.find(part) != std::string::npos; });
}

Cage cage_of(PolyMesh m) { return std::move(make_cage(std::move(m), "test cage")).value(); }

TEST(CageImport, ClosedBoxHasNoProblems) {
  CageProblems p = find_cage_problems(fixtures::box_cage(1.0, 3));
  EXPECT_EQ(p.total(), 0u);
  EXPECT_TRUE(p.lines.empty());
}

TEST(CageImport, EachProblemIsNamed) {
  PolyMesh m = fixtures::box_cage(1.0, 2).polygons;
  // flip face 0: its four edges now run the same way as the neighbours'
  std::vector<uint32_t> f0(m.face(0).begin(), m.face(0).end());
  std::reverse(f0.begin(), f0.end());
  std::copy(f0.begin(), f0.end(), m.face_vertices.begin() + m.face_start[0]);
  // a zero-area triangle on three collinear new vertices, and an unused vertex
  const auto n = static_cast<uint32_t>(m.positions.size());
  m.positions.insert(m.positions.end(), {{5, 0, 0}, {6, 0, 0}, {7, 0, 0}, {9, 9, 9}});
  m.add_face({n, n + 1, n + 2});
  Cage cage = cage_of(m);
  CageProblems p = find_cage_problems(cage);
  EXPECT_EQ(p.misoriented_edges, 4u);
  EXPECT_EQ(p.bad_elements, 1u);
  EXPECT_EQ(p.unused_vertices, 1u);
  EXPECT_EQ(p.open_edges, 3u);  // the lone triangle's edges
  EXPECT_TRUE(has_line(p, "disagree on orientation"));
  EXPECT_TRUE(has_line(p, "zero area - skipped by the bind"));
  EXPECT_TRUE(has_line(p, "face " + std::to_string(m.num_faces() - 1)));
  EXPECT_TRUE(has_line(p, "vertex " + std::to_string(n + 3) + ": in no face"));
}

TEST(CageImport, NonManifoldEdgeAndCapOnLines) {
  PolyMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  m.add_face({0, 1, 2});
  m.add_face({1, 0, 3});
  m.add_face({0, 1, 4});  // a third face on edge 0-1
  CageProblems p = find_cage_problems(cage_of(m));
  EXPECT_EQ(p.non_manifold_edges, 1u);
  EXPECT_TRUE(has_line(p, "edge 0-1: non-manifold, shared by 3 faces"));
  CageProblems capped = find_cage_problems(cage_of(m), 2);
  EXPECT_EQ(capped.lines.size(), 2u);
  EXPECT_EQ(capped.total(), p.total());
}

TEST(CageImport, GltfFileIsReadAsACage) {
  const std::string path = ::testing::TempDir() + "cage_import_demo.glb";
  Character demo = make_demo_character();
  ASSERT_TRUE(write_glb(path, demo).ok());
  auto m = load_cage_mesh(path);
  ASSERT_TRUE(m.ok()) << m.error().message;
  size_t v = 0, t = 0;
  for (const auto& prim : demo.primitives) v += prim.positions.size(), t += prim.triangles.size();
  EXPECT_EQ(m->num_vertices(), v);
  EXPECT_EQ(m->num_faces(), t);
  EXPECT_TRUE(Fails(load_cage_mesh(::testing::TempDir() + "no_such_cage.glb"), ErrorCode::kFileNotFound, {"no_such_cage.glb"}));
}

}  // namespace
}  // namespace cagewrap
