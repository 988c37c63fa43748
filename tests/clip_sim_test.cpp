// The per-clip simulation cache (core/rig/clip_sim.h), Rig::pose_clip and the baked-animation export
// of a simulated cage, on the demo character with its belly jiggling through the walk
// (core/rig/demo_sim.h).
#include <cstring>
#include <optional>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "core/rig/clip_sim.h"
#include "core/rig/demo_sim.h"
#include "core/rig/rig.h"
#include "core/export/rig_export.h"
#include "tests/expect_error.h"
#include "tests/rig_fixtures.h"

namespace cagewrap {
namespace {

struct Demo {
  Document doc;       // no simulation
  Document belly;     // the belly jiggle
  std::optional<Rig> rig;
  int32_t walk = -1;
};

Demo& demo() {
  static Demo d = [] {
    Demo d;
    d.doc = test::demo_document();
    d.belly = with_sim(d.doc, demo_belly_sim(d.doc.cage_positions()));
    auto rig = Rig::create(d.doc);
    EXPECT_TRUE(rig.ok()) << rig.error().message;
    d.rig.emplace(std::move(rig).value());
    d.walk = d.doc.character->find_clip("walk");
    EXPECT_GE(d.walk, 0);
    return d;
  }();
  return d;
}

PosedCage plain_pose(const Document& doc, int32_t clip, double t) {
  PosedCage out;
  pose_document_cage(doc, demo().rig->attachment(), compose_pose(*doc.character, clip, t, false), out);
  return out;
}

TEST(ClipSim, PinnedVerticesAreTheSkinnedCageAtAnyTime) {
  Demo& d = demo();
  SimCache cache;
  const double duration = d.doc.character->clips[d.walk].duration;
  double largest = 0.0;
  size_t free = 0;
  for (double t : {0.0, 0.1, 0.2345, 0.5, 0.71, duration}) {
    const PosedCage plain = plain_pose(d.belly, d.walk, t);
    PosedCage sim;
    ASSERT_TRUE(pose_simulated_cage(cache, d.belly, d.rig->attachment(), d.walk, t,
                                    compose_pose(*d.doc.character, d.walk, t, false), sim)
                    .ok());
    free = 0;
    for (size_t v = 0; v < plain.positions.size(); ++v) {
      if (d.belly.sim.vertices[v].pinned) {
        ASSERT_EQ(sim.positions[v], plain.positions[v]) << "vertex " << v << " t " << t;
        ASSERT_EQ(sim.linear[v], plain.linear[v]) << "vertex " << v;
      } else {
        ++free;
        largest = std::max(largest, static_cast<double>(glm::length(sim.positions[v] - plain.positions[v])));
      }
    }
  }
  EXPECT_GT(free, 10u);
  EXPECT_GT(largest, 1e-3) << "the belly never moved off its skinned position";
  EXPECT_LT(largest, 0.05);
}

TEST(ClipSim, HardGoalsWithoutGravityReproduceTheSkinnedCage) {
  Demo& d = demo();
  SimSettings s = d.belly.sim;
  s.params.gravity = glm::dvec3(0.0);
  for (SimVertex& w : s.vertices) w = {false, 2.0f, 1.0f};
  const Document doc = with_sim(d.doc, s);
  SimCache cache;
  for (double t : {0.0, 0.33, 0.5, 0.9}) {
    const PosedCage plain = plain_pose(doc, d.walk, t);
    PosedCage sim;
    ASSERT_TRUE(pose_simulated_cage(cache, doc, d.rig->attachment(), d.walk, t,
                                    compose_pose(*doc.character, d.walk, t, false), sim)
                    .ok());
    ASSERT_EQ(sim.positions, plain.positions) << "t " << t;
  }
}

TEST(ClipSim, CacheReplayEqualsAFreshRunBitForBit) {
  Demo& d = demo();
  SimCache cache;
  auto got = cache.get(d.belly, d.rig->attachment(), d.walk);
  ASSERT_TRUE(got.ok()) << got.error().message;
  ClipSimulation& cached = **got;
  while (!cached.done()) ASSERT_GT(cached.advance(3, 0.5), 0u);  // in small pieces, as the editor fills it
  auto fresh = ClipSimulation::create(d.belly, d.rig->attachment(), d.walk);
  ASSERT_TRUE(fresh.ok());
  fresh->complete();
  ASSERT_EQ(fresh->frames_done(), cached.frames_done());
  ASSERT_GT(cached.frames_done(), 20u);
  for (size_t f = 0; f < cached.frames_done(); ++f) {
    const auto a = cached.offsets(f), b = fresh->offsets(f);
    ASSERT_EQ(std::memcmp(a.data(), b.data(), a.size_bytes()), 0) << "frame " << f;
  }
  // the rig's own cache: posing the same clip time twice gives the same skin
  std::vector<glm::vec3> first(d.rig->num_skin_points()), second(first.size());
  PosedCage posed;
  ASSERT_TRUE(d.rig->pose_clip(d.belly, d.walk, 0.4, {}, posed, first).ok());
  ASSERT_TRUE(d.rig->pose_clip(d.belly, d.walk, 0.9, {}, posed, second).ok());
  ASSERT_TRUE(d.rig->pose_clip(d.belly, d.walk, 0.4, {}, posed, second).ok());
  EXPECT_EQ(first, second);
}

TEST(ClipSim, CacheIsDroppedWhenWhatItDependsOnChanges) {
  Demo& d = demo();
  SimCache cache;
  ClipSimulation* a = cache.get(d.belly, d.rig->attachment(), d.walk).value();
  a->advance(5);
  // binding parameters do not move the cage: kept
  BindParams p = d.belly.params;
  p.epsilon = 0.2;
  EXPECT_EQ(cache.get(with_params(d.belly, p), d.rig->attachment(), d.walk).value(), a);
  EXPECT_EQ(a->frames_done(), 5u);
  SimSettings s = d.belly.sim;
  s.params.damping = 5.0;
  ClipSimulation* b = cache.get(with_sim(d.belly, s), d.rig->attachment(), d.walk).value();
  EXPECT_EQ(b->frames_done(), 0u);
  s.vertices[0].mass = -2.0f;
  EXPECT_TRUE(Fails(cache.get(with_sim(d.belly, s), d.rig->attachment(), d.walk), ErrorCode::kInvalidArgument,
                    {"cage vertex 0", "mass"}));
  EXPECT_TRUE(Fails(cache.get(d.belly, d.rig->attachment(), 7), ErrorCode::kIndexOutOfRange, {"clip 7"}));
}

TEST(ClipSim, BakedAnimationExportCarriesTheSimulation) {
  Demo& d = demo();
  ExportOptions options;
  options.mode = ExportMode::kBakedAnimation;
  options.clips = {d.walk};
  options.fps = 10.0;
  auto with = export_rig(d.belly, *d.rig, options);
  ASSERT_TRUE(with.ok()) << with.error().message;
  auto without = export_rig(d.doc, *d.rig, options);
  ASSERT_TRUE(without.ok());
  const Primitive& pw = with->character.primitives[0];
  const Primitive& po = without->character.primitives[0];
  ASSERT_EQ(pw.morph_targets.size(), po.morph_targets.size());
  ASSERT_GT(pw.morph_targets.size(), 5u);
  double differs = 0.0;
  for (size_t f = 0; f < pw.morph_targets.size(); ++f)
    for (size_t v = 0; v < pw.num_vertices(); ++v)
      differs = std::max(differs, static_cast<double>(glm::length(pw.morph_targets[f][v] - po.morph_targets[f][v])));
  EXPECT_GT(differs, 1e-3) << "the simulated export is the plain one";
  // each frame is the rig posed through its simulation cache
  std::vector<glm::vec3> skin(d.rig->num_skin_points());
  PosedCage posed;
  const auto rest = d.rig->skin_rest();
  for (size_t f = 0; f < pw.morph_targets.size(); ++f) {
    ASSERT_TRUE(d.rig->pose_clip(d.belly, d.walk, static_cast<double>(f) / options.fps, {}, posed, skin).ok());
    for (size_t v = 0; v < pw.num_vertices(); ++v)
      ASSERT_EQ(pw.morph_targets[f][v], skin[v] - rest[v]) << "frame " << f << " vertex " << v;
  }
  EXPECT_LT(with->at_frames.max, 1e-5);
}

}  // namespace
}  // namespace cagewrap
