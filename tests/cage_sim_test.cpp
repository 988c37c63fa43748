// The cage solver (core/cage/cage_sim.h) on hand-built sheets: pins, hard goals, determinism, energy,
// collisions, edge lengths and bad input.
#include <cmath>
#include <cstring>
#include <limits>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "core/cage/cage_sim.h"
#include "core/rig/demo_sim.h"
#include "tests/expect_error.h"

namespace cagewrap {
namespace {

constexpr int kCols = 10, kRows = 10;

// A 1 m x 1 m sheet in the x-z plane at height 1, top row (j = 0) at z = 0.
PolyMesh sheet() { return grid_sheet({-0.5, 1.0, 0.0}, {1.0, 0.0, 0.0}, {0.0, 0.0, 1.0}, kCols, kRows); }

// Top row pinned, the rest free with this stiffness.
SimSettings hanging(float stiffness) {
  SimSettings s;
  s.enabled = true;
  s.vertices.assign((kCols + 1) * (kRows + 1), SimVertex{false, 1.0f, stiffness});
  for (int i = 0; i <= kCols; ++i) s.vertices[i].pinned = true;
  return s;
}

// The rest sheet moved rigidly: rotated by `deg` about y and shifted along x.
std::vector<glm::vec3> moved(const PolyMesh& m, double deg, double dx) {
  const double c = std::cos(glm::radians(deg)), s = std::sin(glm::radians(deg));
  std::vector<glm::vec3> out;
  for (const glm::vec3& p : m.positions)
    out.emplace_back(static_cast<float>(c * p.x + s * p.z + dx), p.y, static_cast<float>(-s * p.x + c * p.z));
  return out;
}

CageSim make(const PolyMesh& m, const SimSettings& s) {
  auto sim = CageSim::create(m, m.positions, s);
  EXPECT_TRUE(sim.ok()) << sim.error().message;
  return std::move(sim).value();
}

TEST(CageSim, PinnedVerticesEqualTheirTargetsExactly) {
  const PolyMesh m = sheet();
  CageSim sim = make(m, hanging(0.2f));
  sim.reset(m.positions, {});
  for (int f = 1; f <= 30; ++f) {
    const auto targets = moved(m, 3.0 * f, 0.02 * f);
    sim.step_frame(targets, {});
    for (int i = 0; i <= kCols; ++i) {
      ASSERT_TRUE(sim.pinned(i));
      ASSERT_EQ(glm::vec3(sim.positions()[i]), targets[i]) << "vertex " << i << " frame " << f;
    }
  }
  // and the free vertices did move away from their targets (gravity, lag): the test can fail
  const auto last = moved(m, 90.0, 0.6);
  double off = 0.0;
  for (size_t v = kCols + 1; v < m.num_vertices(); ++v)
    off = std::max(off, glm::length(sim.positions()[v] - glm::dvec3(last[v])));
  EXPECT_GT(off, 0.01);
}

TEST(CageSim, HardGoalWithoutGravityIsTheSkinnedCage) {
  const PolyMesh m = sheet();
  SimSettings s = hanging(1.0f);
  s.params.gravity = glm::dvec3(0.0);
  CageSim sim = make(m, s);
  EXPECT_EQ(sim.num_free(), 0u);  // stiffness 1 is handled as pinned
  sim.reset(m.positions, {});
  for (int f = 1; f <= 20; ++f) {
    const auto targets = moved(m, 7.0 * f, -0.03 * f);
    sim.step_frame(targets, {});
    for (size_t v = 0; v < m.num_vertices(); ++v) ASSERT_EQ(glm::vec3(sim.positions()[v]), targets[v]) << v;
  }
  // just below 1 the vertices follow closely but not exactly
  s.vertices.assign(m.num_vertices(), SimVertex{false, 1.0f, 0.999f});
  CageSim soft = make(m, s);
  soft.reset(m.positions, {});
  soft.step_frame(moved(m, 20.0, 0.1), {});
  EXPECT_EQ(soft.num_free(), m.num_vertices());
}

TEST(CageSim, TwoRunsAreBitIdentical) {
  const PolyMesh m = sheet();
  SimSettings s = hanging(0.1f);
  s.params.iterations = 3;
  s.colliders.push_back({"ball", ColliderKind::kSphere, {0.0, 0.8, 0.5}, {}, 0.25, -1});
  std::vector<std::vector<glm::dvec3>> runs;
  for (int run = 0; run < 2; ++run) {
    CageSim sim = make(m, s);
    const ColliderShape ball{ColliderKind::kSphere, {0.0, 0.8, 0.5}, {}, 0.25};
    sim.reset(m.positions, std::span(&ball, 1));
    for (int f = 1; f <= 40; ++f) sim.step_frame(moved(m, 2.0 * f, 0.0), std::span(&ball, 1));
    runs.emplace_back(sim.positions().begin(), sim.positions().end());
  }
  ASSERT_EQ(runs[0].size(), runs[1].size());
  EXPECT_EQ(std::memcmp(runs[0].data(), runs[1].data(), runs[0].size() * sizeof(glm::dvec3)), 0);
}

TEST(CageSim, EnergyDecaysWithDampingOnceTheMotionStops) {
  const PolyMesh m = sheet();
  SimSettings s = hanging(0.5f);
  s.params.gravity = glm::dvec3(0.0);
  s.params.edges = false;
  s.params.damping = 2.0;
  CageSim sim = make(m, s);
  sim.reset(m.positions, {});
  // a fast move for 5 frames, then the targets stand still
  std::vector<glm::vec3> targets;
  for (int f = 1; f <= 5; ++f) sim.step_frame(targets = moved(m, 0.0, 0.04 * f), {});
  const double start = sim.energy();
  ASSERT_GT(start, 1e-4);
  double previous = start;
  for (int second = 0; second < 3; ++second) {
    for (int f = 0; f < 30; ++f) sim.step_frame(targets, {});
    EXPECT_LT(sim.energy(), previous) << "after " << second + 1 << " s";
    previous = sim.energy();
  }
  EXPECT_LT(previous, 0.01 * start);
  // without damping the (implicit) goal springs lose far less
  s.params.damping = 0.0;
  CageSim undamped = make(m, s);
  undamped.reset(m.positions, {});
  for (int f = 1; f <= 5; ++f) undamped.step_frame(moved(m, 0.0, 0.04 * f), {});
  for (int f = 0; f < 90; ++f) undamped.step_frame(targets, {});
  EXPECT_GT(undamped.energy(), 10.0 * previous);
}

// A free sheet (no goal, top row pinned) falls and swings onto each collider in turn.
TEST(CageSim, NoFreeVertexEndsInsideACollider) {
  const PolyMesh m = sheet();
  const std::vector<Collider> shapes = {
      {"floor", ColliderKind::kPlane, {0.0, 0.6, 0.0}, {0.0, 1.0, 0.2}, 0.0, -1},
      {"ball", ColliderKind::kSphere, {0.1, 0.75, 0.3}, {}, 0.2, -1},
      {"pole", ColliderKind::kCapsule, {-0.6, 0.7, 0.4}, {0.6, 0.8, 0.4}, 0.08, -1},
  };
  for (const Collider& c : shapes) {
    SimSettings s = hanging(0.0f);
    s.params.iterations = 2;
    s.params.collision_margin = 0.01;
    s.colliders = {c};
    CageSim sim = make(m, s);
    std::vector<ColliderShape> posed;
    pose_colliders(s.colliders, {}, {}, {}, {}, posed);
    sim.reset(m.positions, posed);
    size_t touching = 0;
    for (int f = 1; f <= 60; ++f) {
      sim.step_frame(moved(m, 0.0, 0.1 * std::sin(f * 0.2)), posed);
      for (size_t v = 0; v < m.num_vertices(); ++v) {
        if (sim.pinned(v)) continue;
        const glm::dvec3 p = sim.positions()[v];
        double d = 0.0;  // signed distance to the surface
        if (c.kind == ColliderKind::kPlane) d = glm::dot(p - c.a, glm::normalize(c.b));
        if (c.kind == ColliderKind::kSphere) d = glm::length(p - c.a) - c.radius;
        if (c.kind == ColliderKind::kCapsule) {
          const glm::dvec3 ab = c.b - c.a;
          const double t = std::clamp(glm::dot(p - c.a, ab) / glm::dot(ab, ab), 0.0, 1.0);
          d = glm::length(p - (c.a + t * ab)) - c.radius;
        }
        ASSERT_GE(d, 0.01 - 1e-9) << c.name << ": vertex " << v << " frame " << f;
        touching += d < 0.0101;
      }
    }
    EXPECT_GT(touching, 0u) << c.name << ": the sheet never reached it, so the test shows nothing";
  }
}

TEST(CageSim, ClothEdgeLengthsStayWithinTolerance) {
  const PolyMesh m = sheet();
  SimSettings s = hanging(0.0f);
  s.params.iterations = 4;
  CageSim sim = make(m, s);
  sim.reset(m.positions, {});
  const auto edges = unique_edges(m);
  double worst = 0.0, moved_most = 0.0;
  for (int f = 1; f <= 90; ++f) {
    const auto targets = moved(m, 30.0 * std::sin(f * 0.15), 0.2 * std::sin(f * 0.1));
    sim.step_frame(targets, {});
    double frame_worst = 0.0;
    for (const auto& e : edges) {
      const double rest = glm::length(glm::dvec3(m.positions[e[0]]) - glm::dvec3(m.positions[e[1]]));
      const double now = glm::length(sim.positions()[e[0]] - sim.positions()[e[1]]);
      frame_worst = std::max(frame_worst, std::abs(now - rest) / rest);
    }
    ASSERT_NEAR(sim.max_edge_strain(), frame_worst, 1e-12) << "frame " << f;  // what `simulate` reports
    worst = std::max(worst, frame_worst);
    moved_most = std::max(moved_most, glm::length(sim.positions().back() - glm::dvec3(m.positions.back())));
  }
  EXPECT_GT(moved_most, 0.3);  // the sheet fell and swung
  EXPECT_LT(worst, 0.05) << "largest relative edge-length change";
}

TEST(CageSim, BadInputIsRefusedNamingTheVertexOrCollider) {
  const PolyMesh m = sheet();
  SimSettings s = hanging(0.5f);
  s.vertices.resize(3);
  EXPECT_TRUE(Fails(CageSim::create(m, m.positions, s), ErrorCode::kInvalidArgument, {"3 vertices", "121"}));
  s = hanging(0.5f);
  s.vertices[17].mass = -1.0f;
  EXPECT_TRUE(Fails(CageSim::create(m, m.positions, s), ErrorCode::kInvalidArgument, {"cage vertex 17", "mass -1"}));
  s = hanging(0.5f);
  s.vertices[5].stiffness = std::numeric_limits<float>::quiet_NaN();
  EXPECT_TRUE(Fails(CageSim::create(m, m.positions, s), ErrorCode::kInvalidArgument, {"cage vertex 5", "stiffness"}));
  s = hanging(0.5f);
  s.vertices[40].stiffness = 1.5f;
  EXPECT_TRUE(Fails(CageSim::create(m, m.positions, s), ErrorCode::kInvalidArgument, {"cage vertex 40", "0..1"}));
  s = hanging(0.5f);
  s.params.substeps = 0;
  EXPECT_TRUE(Fails(CageSim::create(m, m.positions, s), ErrorCode::kInvalidArgument, {"substeps 0"}));
  s = hanging(0.5f);
  s.params.damping = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(Fails(CageSim::create(m, m.positions, s), ErrorCode::kInvalidArgument, {"damping"}));
  s = hanging(0.5f);
  s.colliders.push_back({"table", ColliderKind::kSphere, {0, 0, 0}, {}, 0.0, -1});
  EXPECT_TRUE(Fails(CageSim::create(m, m.positions, s), ErrorCode::kInvalidArgument, {"collider 0", "'table'", "radius"}));
  s.colliders[0] = {"floor", ColliderKind::kPlane, {0, 0, 0}, {0, 0, 0}, 0.0, -1};
  EXPECT_TRUE(Fails(CageSim::create(m, m.positions, s), ErrorCode::kInvalidArgument, {"'floor'", "zero normal"}));
  s.colliders[0] = {"", ColliderKind::kSphere, {0, 0, 0}, {}, 0.1, 99};
  EXPECT_TRUE(Fails(validate_sim_settings(s, m.num_vertices(), 5), ErrorCode::kInvalidArgument, {"collider 0", "node 99"}));
  std::vector<glm::vec3> rest = m.positions;
  rest[9].y = std::numeric_limits<float>::infinity();
  EXPECT_TRUE(Fails(CageSim::create(m, rest, hanging(0.5f)), ErrorCode::kNonFinite, {"cage vertex 9"}));
}

}  // namespace
}  // namespace cagewrap
