// Tests for app/workspace/soft_selection.h: falloff curves, volume against surface distance, mirrored
// moves (a plane vertex keeps x = 0, a symmetric shape stays symmetric), and bad input named.
#include <gtest/gtest.h>

#include "app/workspace/soft_selection.h"
#include "tests/expect_error.h"
#include "tests/fixtures.h"

namespace cagewrap {
namespace {

// A row of vertices along x at unit spacing (x = 0..n-1), joined by quads to a second row at y = 1.
PolyMesh strip(int n) {
  PolyMesh m;
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < n; ++x) m.positions.emplace_back(x, y, 0);
  for (uint32_t x = 0; x + 1 < static_cast<uint32_t>(n); ++x)
    m.add_face({x, x + 1, x + 1 + uint32_t(n), x + uint32_t(n)});
  return m;
}

float weight_of(const MoveWeights& w, uint32_t v) {
  for (size_t i = 0; i < w.vertices.size(); ++i)
    if (w.vertices[i] == v) return w.direct[i];
  return 0.f;
}

TEST(Falloff, CurvesAreOneAtTheSelectionAndZeroAtTheRadius) {
  for (Falloff f : {Falloff::kSmooth, Falloff::kLinear, Falloff::kSharp, Falloff::kConstant}) {
    SCOPED_TRACE(falloff_name(f));
    EXPECT_DOUBLE_EQ(falloff_weight(f, 0.0), 1.0);
    EXPECT_DOUBLE_EQ(falloff_weight(f, 1.0), 0.0);
    EXPECT_DOUBLE_EQ(falloff_weight(f, 3.0), 0.0);
    double previous = 1.0;
    for (double t = 0.05; t < 1.0; t += 0.05) {  // never increases with distance
      EXPECT_LE(falloff_weight(f, t), previous + 1e-15);
      previous = falloff_weight(f, t);
    }
  }
  EXPECT_DOUBLE_EQ(falloff_weight(Falloff::kLinear, 0.25), 0.75);
  EXPECT_DOUBLE_EQ(falloff_weight(Falloff::kSmooth, 0.5), 0.5);
  EXPECT_DOUBLE_EQ(falloff_weight(Falloff::kSharp, 0.5), 0.25);
  EXPECT_DOUBLE_EQ(falloff_weight(Falloff::kConstant, 0.99), 1.0);
}

TEST(SoftSelection, OffMovesOnlyTheSelection) {
  PolyMesh m = strip(6);
  auto w = move_weights(IndexSet{2, 3}, m.positions, m, {}, {});
  ASSERT_TRUE(w.ok()) << w.error().message;
  EXPECT_EQ(w.value().vertices, (std::vector<uint32_t>{2, 3}));
  EXPECT_EQ(w.value().direct, (std::vector<float>{1.f, 1.f}));
  EXPECT_EQ(w.value().mirrored, (std::vector<float>{0.f, 0.f}));
}

TEST(SoftSelection, LinearVolumeFalloffFollowsTheNearestSelectedVertex) {
  PolyMesh m = strip(8);
  SoftSelectionParams soft{true, 4.0, Falloff::kLinear, FalloffDistance::kVolume};
  auto w = move_weights(IndexSet{0}, m.positions, m, soft, {});
  ASSERT_TRUE(w.ok());
  EXPECT_FLOAT_EQ(weight_of(w.value(), 0), 1.f);
  EXPECT_FLOAT_EQ(weight_of(w.value(), 1), 0.75f);
  EXPECT_FLOAT_EQ(weight_of(w.value(), 3), 0.25f);
  EXPECT_FLOAT_EQ(weight_of(w.value(), 4), 0.f);  // at the radius
  EXPECT_FLOAT_EQ(weight_of(w.value(), 8), 0.75f);  // (0, 1): straight up, distance 1
  EXPECT_NEAR(weight_of(w.value(), 9), 1.0 - std::sqrt(2.0) / 4.0, 1e-6);
}

TEST(SoftSelection, SurfaceDistanceDoesNotJumpAGap) {
  // Two strips side by side 0.5 apart in z, not connected: the volume falloff reaches across the
  // gap, the surface falloff does not.
  PolyMesh a = strip(4), m = a;
  const uint32_t offset = static_cast<uint32_t>(a.num_vertices());
  for (auto p : a.positions) m.positions.push_back(p + glm::vec3(0, 0, 0.5f));
  for (size_t f = 0; f < a.num_faces(); ++f) {
    std::vector<uint32_t> corners;
    for (uint32_t c : a.face(f)) corners.push_back(c + offset);
    m.add_face(corners);
  }
  SoftSelectionParams soft{true, 2.0, Falloff::kLinear, FalloffDistance::kVolume};
  auto volume = move_weights(IndexSet{0}, m.positions, m, soft, {});
  soft.distance = FalloffDistance::kSurface;
  auto surface = move_weights(IndexSet{0}, m.positions, m, soft, {});
  ASSERT_TRUE(volume.ok() && surface.ok());
  EXPECT_FLOAT_EQ(weight_of(volume.value(), offset), 0.75f);
  EXPECT_FLOAT_EQ(weight_of(surface.value(), offset), 0.f);
  // along the surface: the diagonal neighbour (1, 1) is two edges away, not sqrt(2)
  EXPECT_FLOAT_EQ(weight_of(surface.value(), 5), 0.f);
  EXPECT_FLOAT_EQ(weight_of(surface.value(), 1), 0.5f);
  EXPECT_NEAR(weight_of(volume.value(), 5), 1.0 - std::sqrt(2.0) / 2.0, 1e-6);
}

TEST(Mirror, CounterpartMovesWithXNegatedAndThePlaneVertexStaysOnThePlane) {
  // vertices at x = -2..2 (5 of them) and a row above
  PolyMesh m = strip(5);
  for (auto& p : m.positions) p.x -= 2.f;
  MirrorParams mirror{true, 1e-3};
  auto w = move_weights(IndexSet{0, 2}, m.positions, m, {}, mirror);  // x = -2 and x = 0
  ASSERT_TRUE(w.ok());
  const MoveWeights& mw = w.value();
  EXPECT_EQ(mw.vertices, (std::vector<uint32_t>{0, 2, 4}));
  const glm::dvec3 d(0.3, 0.2, -0.1);
  EXPECT_EQ(mw.displacement(0, d), d);
  EXPECT_EQ(mw.displacement(1, d), glm::dvec3(0.0, 0.2, -0.1));  // on the plane: its own counterpart
  EXPECT_EQ(mw.displacement(2, d), glm::dvec3(-0.3, 0.2, -0.1));
  EXPECT_TRUE(mw.unmatched.empty());
}

TEST(Mirror, SymmetricCageStaysSymmetricUnderASoftMirroredMove) {
  Cage cage = fixtures::box_cage(1.0, 4);
  const auto& p = cage.polygons.positions;
  SoftSelectionParams soft{true, 0.8, Falloff::kSmooth, FalloffDistance::kSurface};
  MirrorParams mirror{true, 1e-4};
  IndexSet sel;
  for (uint32_t v = 0; v < p.size(); ++v)
    if (p[v].x > 0.9f && p[v].y > 0.9f) sel.add(std::vector<uint32_t>{v});
  ASSERT_FALSE(sel.empty());
  auto w = move_weights(sel, p, cage.polygons, soft, mirror);
  ASSERT_TRUE(w.ok());
  std::vector<glm::vec3> moved = p;
  const glm::dvec3 d(0.2, 0.4, 0.1);
  for (size_t i = 0; i < w.value().vertices.size(); ++i)
    moved[w.value().vertices[i]] += glm::vec3(w.value().displacement(i, d));
  // every moved vertex has a counterpart at (-x, y, z) in the moved cage
  auto counterparts = mirror_x(select_all(static_cast<uint32_t>(p.size())), p, 1e-4);
  ASSERT_TRUE(counterparts.unmatched.empty());
  for (uint32_t v = 0; v < p.size(); ++v) {
    bool found = false;
    for (uint32_t u = 0; u < p.size() && !found; ++u)
      found = glm::length(glm::dvec3(moved[u]) - glm::dvec3(-moved[v].x, moved[v].y, moved[v].z)) < 1e-5;
    EXPECT_TRUE(found) << "vertex " << v << " lost its mirror image";
  }
  EXPECT_GT(w.value().vertices.size(), 2 * sel.size());  // the falloff reached beyond the selection
}

TEST(Mirror, UnmatchedVerticesAreReported) {
  PolyMesh m = strip(3);  // x = 0, 1, 2: nothing at x = -1, -2
  auto w = move_weights(IndexSet{0, 2}, m.positions, m, {}, MirrorParams{true, 1e-3});
  ASSERT_TRUE(w.ok());
  EXPECT_EQ(w.value().unmatched, (std::vector<uint32_t>{2}));
}

TEST(SoftSelection, BadInputIsNamed) {
  PolyMesh m = strip(3);
  EXPECT_TRUE(Fails(move_weights(IndexSet{9}, m.positions, m, {}, {}), ErrorCode::kIndexOutOfRange, {"vertex 9", "6 vertices"}));
  EXPECT_TRUE(Fails(move_weights(IndexSet{0}, m.positions, m, {true, 0.0}, {}), ErrorCode::kInvalidArgument, {"radius"}));
  EXPECT_TRUE(Fails(move_weights(IndexSet{0}, m.positions, PolyMesh{}, {true, 1.0, Falloff::kSmooth, FalloffDistance::kSurface}, {}),
                    ErrorCode::kInvalidArgument, {"faces"}));
  EXPECT_TRUE(Fails(move_weights(IndexSet{0}, m.positions, m, {}, {true, -1.0}), ErrorCode::kInvalidArgument, {"tolerance"}));
}

TEST(SoftSelection, FaceVerticesAreTheCornersOfTheSelectedFaces) {
  PolyMesh m = strip(4);
  EXPECT_EQ(face_vertices(IndexSet{0, 2}, m), (IndexSet{0, 1, 2, 3, 4, 5, 6, 7}));
  EXPECT_EQ(face_vertices(IndexSet{1, 99}, m), (IndexSet{1, 2, 5, 6}));
}

}  // namespace
}  // namespace cagewrap
