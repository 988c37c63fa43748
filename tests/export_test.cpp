// Tests for core/rig_export.h on the demo character (core/demo_character.h) and its cage
// (assets/demo_cage.obj) at a few frames per second: every mode passes the Khronos glTF validator,
// keeps its mesh on a root node with identity transform, and loads again (core/gltf_loader.h)
// reproducing the rig at the sampled frames, posed by core/skinning.h with the file's morph
// weights; the fitted weights of baked-skin are at most four per vertex, non-negative and sum to 1
// in float32. Errors and timings are recorded as properties, never asserted as timings.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <glm/geometric.hpp>
#include <sstream>

#include "core/cage_import.h"
#include "core/demo_character.h"
#include "core/gltf_loader.h"
#include "core/gltf_writer.h"
#include "core/rig_export.h"
#include "core/skinning.h"
#include "tests/gltf_builder.h"

namespace cagewrap {
namespace {

constexpr double kFps = 4.0;  // walk (1 s): 5 frames; arm_raise (2 s): 9 frames

struct Demo {
  Document doc;
  std::optional<Rig> rig;
};

Demo& demo() {
  static Demo d = [] {
    Demo d;
    d.doc.character = std::make_shared<const Character>(make_demo_character());
    d.doc.character_hash = "demo";
    auto mesh = load_cage_mesh(std::string(CAGEWRAP_SOURCE_DIR) + "/assets/demo_cage.obj");
    EXPECT_TRUE(mesh.ok()) << mesh.error().message;
    auto cage = make_cage(std::move(mesh).value(), "demo_cage.obj");
    EXPECT_TRUE(cage.ok());
    d.doc.cage = std::make_shared<const Cage>(std::move(cage).value());
    auto rig = Rig::create(d.doc);
    EXPECT_TRUE(rig.ok()) << rig.error().message;
    d.rig.emplace(std::move(rig).value());
    return d;
  }();
  return d;
}

bool node_available() {
  return std::system("node --version > /dev/null 2>&1") == 0;
}

// The validator's report line for `file`, e.g. "x.glb: 0 errors, 0 warnings, ..."; rc in `rc`.
std::string validate(const std::string& file, int& rc) {
  const std::string report = file + ".report.txt";
  std::string cmd = "node '" + std::string(CAGEWRAP_SOURCE_DIR) + "/tests/gltf_validate/validate.js' '" +
                    file + "' > '" + report + "' 2>&1";
  int status = std::system(cmd.c_str());
  rc = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream in(report);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

struct Exported {
  ExportResult result;
  Character loaded;
  std::string path;
};

Exported export_and_reload(ExportMode mode, const std::string& name) {
  Demo& d = demo();
  ExportOptions options;
  options.mode = mode;
  options.fps = kFps;
  const auto start = std::chrono::steady_clock::now();
  auto r = export_rig(d.doc, *d.rig, options);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_TRUE(r.ok()) << r.error().message;
  Exported e;
  e.result = std::move(r).value();
  e.path = test::temp_dir("export_" + name) + "/" + name + ".glb";
  EXPECT_TRUE(write_glb(e.path, e.result.character).ok());
  auto loaded = load_character(e.path);
  EXPECT_TRUE(loaded.ok()) << loaded.error().message;
  e.loaded = std::move(loaded).value();
  ::testing::Test::RecordProperty("export_seconds", std::to_string(seconds));
  ::testing::Test::RecordProperty("bytes", std::to_string(encode_glb(e.result.character).size()));
  ::testing::Test::RecordProperty("error_at_frames_max", std::to_string(e.result.at_frames.max));
  ::testing::Test::RecordProperty("error_between_frames_max", std::to_string(e.result.between_frames.max));
  ::testing::Test::RecordProperty("error_skeleton_only_max", std::to_string(e.result.fitted.max));
  return e;
}

void expect_valid_and_rooted(const Exported& e) {
  if (node_available()) {
    int rc = 0;
    std::string log = validate(e.path, rc);
    ASSERT_NE(rc, 2) << "gltf-validator is not installed: run scripts/setup.sh\n" << log;
    EXPECT_EQ(rc, 0) << log;
    EXPECT_NE(log.find(e.path + ": 0 errors"), std::string::npos) << log;
  }
  ASSERT_FALSE(e.loaded.primitives.empty());
  for (const Primitive& p : e.loaded.primitives) {
    const SkeletonNode& n = e.loaded.skeleton.node(p.node);
    EXPECT_EQ(n.parent, -1) << "the mesh node is a root";
    EXPECT_FALSE(n.has_matrix);
    EXPECT_EQ(n.rest.translation, glm::vec3(0.0f));
    EXPECT_EQ(n.rest.rotation, glm::quat(1.0f, 0.0f, 0.0f, 0.0f));
    EXPECT_EQ(n.rest.scale, glm::vec3(1.0f));
  }
}

// Max distance between the reloaded file posed at the frames and the live rig's skin (or cage).
double reload_error(const Exported& e, bool cage) {
  Demo& d = demo();
  const Character& ch = *d.doc.character;
  double worst = 0.0;
  PosedCage posed;
  std::vector<glm::vec3> skin(d.rig->num_skin_points());
  for (size_t c = 0; c < ch.clips.size(); ++c) {
    const int32_t lc = e.loaded.find_clip(ch.clips[c].name);
    EXPECT_GE(lc, 0) << ch.clips[c].name;
    for (double t : export_frame_times(ch.clips[c].duration, kFps)) {
      EXPECT_TRUE(d.rig->pose(d.doc, compose_pose(ch, int32_t(c), t, false), posed, skin).ok());
      std::vector<glm::vec3> mine = skin_character(e.loaded, sample_pose(e.loaded, lc, t));
      const std::vector<glm::vec3>& want = cage ? posed.positions : skin;
      EXPECT_EQ(mine.size(), want.size());
      for (size_t i = 0; i < mine.size() && i < want.size(); ++i)
        worst = std::max(worst, double(glm::length(mine[i] - want[i])));
    }
  }
  return worst;
}

TEST(ExportFrameTimes, CoverTheClipAtTheRate) {
  EXPECT_EQ(export_frame_times(1.0, 4.0), (std::vector<double>{0.0, 0.25, 0.5, 0.75, 1.0}));
  EXPECT_EQ(export_frame_times(0.0, 30.0), (std::vector<double>{0.0}));
  auto t = export_frame_times(1.1, 2.0);  // 3 intervals of 0.3667 s, both ends included
  ASSERT_EQ(t.size(), 4u);
  EXPECT_DOUBLE_EQ(t.back(), 1.1);
}

TEST(ExportModeNames, RoundTrip) {
  for (ExportMode m : {ExportMode::kBakedAnimation, ExportMode::kBakedSkin, ExportMode::kCage}) {
    ExportMode back;
    ASSERT_TRUE(parse_export_mode(export_mode_name(m), back));
    EXPECT_EQ(back, m);
  }
  ExportMode x;
  EXPECT_FALSE(parse_export_mode("baked", x));
}

TEST(Export, RejectsAClipOutOfRange) {
  ExportOptions o;
  o.clips = {7};
  auto r = export_rig(demo().doc, *demo().rig, o);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("clip 7 is out of range (the character has 2)"), std::string::npos)
      << r.error().message;
}

TEST(Export, CageIsTheSkinnedCageWithTheClips) {
  Exported e = export_and_reload(ExportMode::kCage, "cage");
  expect_valid_and_rooted(e);
  ASSERT_EQ(e.loaded.primitives.size(), 1u);
  EXPECT_EQ(e.loaded.primitives[0].num_vertices(), demo().doc.cage->num_vertices());
  EXPECT_EQ(e.loaded.clips.size(), 2u);
  EXPECT_LT(e.result.at_frames.max, 1e-5);
  EXPECT_LT(reload_error(e, true), 1e-5);
}

TEST(Export, BakedAnimationReproducesTheRigAtEveryFrame) {
  Exported e = export_and_reload(ExportMode::kBakedAnimation, "baked_animation");
  expect_valid_and_rooted(e);
  EXPECT_EQ(e.result.frames, 14u);
  EXPECT_EQ(e.loaded.primitives[0].morph_targets.size(), 14u);
  EXPECT_EQ(e.loaded.primitives[0].skin, -1);
  EXPECT_LT(e.result.at_frames.max, 1e-5);
  EXPECT_LT(reload_error(e, false), 1e-5);
}

TEST(Export, BakedSkinFitsWeightsAndCorrectsTheRest) {
  Exported e = export_and_reload(ExportMode::kBakedSkin, "baked_skin");
  expect_valid_and_rooted(e);
  for (const Primitive& p : e.loaded.primitives) {
    ASSERT_EQ(p.influence_start.size(), p.num_vertices() + 1);
    for (size_t v = 0; v < p.num_vertices(); ++v) {
      ASSERT_GE(p.num_influences(v), 1u);
      ASSERT_LE(p.num_influences(v), 4u);
      float sum = 0.0f;
      for (uint32_t k = p.influence_start[v]; k < p.influence_start[v + 1]; ++k) {
        EXPECT_GE(p.influence_weight[k], 0.0f);
        sum += p.influence_weight[k];
      }
      EXPECT_NEAR(sum, 1.0f, 1e-6f) << "vertex " << v;  // the loader renormalizes in its own way
    }
  }
  // Written weights (before the loader's own cleanup) sum to 1 in float32 too.
  for (const Primitive& p : e.result.character.primitives)
    for (size_t v = 0; v < p.num_vertices(); ++v) {
      float sum = 0.0f;
      for (uint32_t k = p.influence_start[v]; k < p.influence_start[v + 1]; ++k) sum += p.influence_weight[k];
      ASSERT_EQ(sum, 1.0f) << "vertex " << v;
    }
  // The skeleton alone comes close (the demo's limbs are rigid; the cage smooths the joints) and the
  // correctives make the frames exact.
  EXPECT_LT(e.result.fitted.mean, 2e-3);
  EXPECT_LT(e.result.fitted.max, 0.05);
  EXPECT_LT(e.result.at_frames.max, 1e-5);
  EXPECT_LT(e.result.between_frames.max, e.result.fitted.max);
  EXPECT_LT(reload_error(e, false), 1e-5);
}

}  // namespace
}  // namespace cagewrap
