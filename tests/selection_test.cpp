// Tests for core/geometry/selection.h: set operations with exact answers, grow/shrink on a hand-checked
// quad grid, their invariants on a closed cage, and mirroring across x = 0.
#include <gtest/gtest.h>

#include <random>

#include "core/geometry/selection.h"
#include "tests/fixtures.h"

namespace cagewrap {
namespace {

using V = std::vector<uint32_t>;

// 4 x 4 vertices (v = 4 y + x), 3 x 3 quads (f = 3 y + x), on the plane z = 0.
PolyMesh grid() {
  PolyMesh m;
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) m.positions.emplace_back(x, y, 0);
  for (uint32_t y = 0; y < 3; ++y)
    for (uint32_t x = 0; x < 3; ++x) m.add_face({4 * y + x, 4 * y + x + 1, 4 * y + x + 5, 4 * y + x + 4});
  return m;
}

V as_vector(const IndexSet& s) { return V(s.begin(), s.end()); }

TEST(IndexSet, SortsAndDeduplicates) {
  IndexSet s(V{5, 1, 3, 1, 5});
  EXPECT_EQ(as_vector(s), (V{1, 3, 5}));
  EXPECT_TRUE(s.contains(3));
  EXPECT_FALSE(s.contains(2));
  EXPECT_EQ(s.size(), 3u);
}

TEST(IndexSet, SetAddRemoveToggle) {
  IndexSet s{1, 3, 5};
  s.add(V{4, 3, 9});
  EXPECT_EQ(as_vector(s), (V{1, 3, 4, 5, 9}));
  s.remove(V{3, 7, 9});
  EXPECT_EQ(as_vector(s), (V{1, 4, 5}));
  s.toggle(V{5, 6, 6, 1});
  EXPECT_EQ(as_vector(s), (V{4, 6}));
  s.set(V{8, 2, 2});
  EXPECT_EQ(as_vector(s), (V{2, 8}));
  s.clear();
  EXPECT_TRUE(s.empty());
}

TEST(IndexSet, AllNoneInvert) {
  EXPECT_EQ(as_vector(select_all(4)), (V{0, 1, 2, 3}));
  EXPECT_TRUE(select_all(0).empty());
  EXPECT_EQ(as_vector(invert(IndexSet{1, 3, 10}, 5)), (V{0, 2, 4}));  // 10 is out of range: dropped
  EXPECT_EQ(invert(invert(IndexSet{0, 2}, 6), 6), (IndexSet{0, 2}));
  EXPECT_TRUE(invert(select_all(7), 7).empty());
}

TEST(Selection, GrowVerticesAlongPolygonEdgesOnly) {
  PolyMesh m = grid();
  EXPECT_EQ(as_vector(grow_vertices(IndexSet{0}, m)), (V{0, 1, 4}));  // not the diagonal 5
  EXPECT_EQ(as_vector(grow_vertices(IndexSet{5}, m)), (V{1, 4, 5, 6, 9}));
  EXPECT_EQ(as_vector(grow_vertices(IndexSet{5, 10}, m)), (V{1, 4, 5, 6, 9, 10, 11, 14}));
  EXPECT_EQ(as_vector(grow_vertices(IndexSet{0, 99}, m)), (V{0, 1, 4}));  // out of range is dropped
}

TEST(Selection, ShrinkVerticesDropsTheBorder) {
  PolyMesh m = grid();
  EXPECT_EQ(as_vector(shrink_vertices(IndexSet{1, 4, 5, 6, 9}, m)), (V{5}));
  EXPECT_TRUE(shrink_vertices(IndexSet{5}, m).empty());
  // the whole open grid: no vertex has an unselected neighbour
  EXPECT_EQ(shrink_vertices(select_all(16), m), select_all(16));
  // a corner block of 3 x 3 vertices keeps those whose every neighbour is in it (0, 1, 4, 5)
  EXPECT_EQ(as_vector(shrink_vertices(IndexSet{0, 1, 2, 4, 5, 6, 8, 9, 10}, m)), (V{0, 1, 4, 5}));
}

TEST(Selection, GrowAndShrinkFacesThroughSharedVertices) {
  PolyMesh m = grid();
  EXPECT_EQ(as_vector(grow_faces(IndexSet{0}, m)), (V{0, 1, 3, 4}));
  EXPECT_EQ(grow_faces(IndexSet{4}, m), select_all(9));  // the centre touches every face
  EXPECT_EQ(as_vector(grow_faces(IndexSet{2}, m)), (V{1, 2, 4, 5}));
  EXPECT_EQ(as_vector(shrink_faces(IndexSet{0, 1, 3, 4}, m)), (V{0}));
  EXPECT_EQ(as_vector(shrink_faces(select_all(9), m)), (V{0, 1, 2, 3, 4, 5, 6, 7, 8}));
  EXPECT_EQ(as_vector(shrink_faces(IndexSet{0, 1, 2, 3, 4, 5}, m)), (V{0, 1, 2}));
}

TEST(Selection, GrowShrinkInvariantsOnAClosedCage) {
  const PolyMesh& m = fixtures::box_cage(1.0, 4).polygons;
  std::mt19937 rng(7);
  for (int trial = 0; trial < 50; ++trial) {
    V pick;
    for (uint32_t v = 0; v < m.num_vertices(); ++v)
      if (rng() % 4 == 0) pick.push_back(v);
    IndexSet s(pick);
    IndexSet grown = grow_vertices(s, m), shrunk = shrink_vertices(s, m);
    EXPECT_TRUE(std::includes(grown.begin(), grown.end(), s.begin(), s.end()));
    EXPECT_TRUE(std::includes(s.begin(), s.end(), shrunk.begin(), shrunk.end()));
    IndexSet back = shrink_vertices(grown, m);  // shrink(grow(S)) contains S
    EXPECT_TRUE(std::includes(back.begin(), back.end(), s.begin(), s.end()));
    IndexSet inner = grow_vertices(shrunk, m);  // grow(shrink(S)) lies in S
    EXPECT_TRUE(std::includes(s.begin(), s.end(), inner.begin(), inner.end()));

    V faces;
    for (uint32_t f = 0; f < m.num_faces(); ++f)
      if (rng() % 4 == 0) faces.push_back(f);
    IndexSet fs(faces);
    IndexSet fback = shrink_faces(grow_faces(fs, m), m);
    EXPECT_TRUE(std::includes(fback.begin(), fback.end(), fs.begin(), fs.end()));
    IndexSet finner = grow_faces(shrink_faces(fs, m), m);
    EXPECT_TRUE(std::includes(fs.begin(), fs.end(), finner.begin(), finner.end()));
  }
  // a closed mesh has no border: select-all survives shrinking
  EXPECT_EQ(shrink_vertices(select_all(uint32_t(m.num_vertices())), m).size(), m.num_vertices());
  EXPECT_EQ(shrink_faces(select_all(uint32_t(m.num_faces())), m).size(), m.num_faces());
}

TEST(Selection, MirrorFindsCounterpartsWithinTolerance) {
  std::vector<glm::vec3> p = {
      {1, 0, 0},        // 0 <-> 1
      {-1, 0, 0},       // 1
      {0, 2, 0},        // 2: on the plane, its own counterpart
      {3, 0, 0},        // 3: nothing at -3
      {2, 1, 1},        // 4 <-> 5 (off by 0.0005)
      {-2.0005f, 1, 1}, // 5
  };
  MirrorResult r = mirror_x(IndexSet{0, 2, 3, 4}, p, 1e-3);
  EXPECT_EQ(as_vector(r.mirrored), (V{1, 2, 5}));
  EXPECT_EQ(r.unmatched, (V{3}));
  MirrorResult strict = mirror_x(IndexSet{4}, p, 1e-4);
  EXPECT_TRUE(strict.mirrored.empty());
  EXPECT_EQ(strict.unmatched, (V{4}));
  EXPECT_EQ(as_vector(mirror_x(IndexSet{1, 5}, p, 1e-3).mirrored), (V{0, 4}));
  // out-of-range selections are ignored
  EXPECT_TRUE(mirror_x(IndexSet{42}, p, 1e-3).mirrored.empty());
}

TEST(Selection, MirrorPicksTheNearestCandidate) {
  std::vector<glm::vec3> p = {{1, 0, 0}, {-1.004f, 0, 0}, {-1.001f, 0, 0}, {-1.003f, 0, 0}};
  EXPECT_EQ(as_vector(mirror_x(IndexSet{0}, p, 0.01).mirrored), (V{2}));
}

TEST(Selection, MirrorOfASymmetricCageIsAnInvolution) {
  Cage cage = fixtures::box_cage(1.0, 4);
  const auto& p = cage.polygons.positions;
  std::mt19937 rng(3);
  V pick;
  for (uint32_t v = 0; v < p.size(); ++v)
    if (rng() % 3 == 0) pick.push_back(v);
  IndexSet s(pick);
  MirrorResult once = mirror_x(s, p, 1e-5);
  EXPECT_TRUE(once.unmatched.empty());
  EXPECT_EQ(once.mirrored.size(), s.size());
  EXPECT_EQ(mirror_x(once.mirrored, p, 1e-5).mirrored, s);
}

}  // namespace
}  // namespace cagewrap
