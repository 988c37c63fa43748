// What ships is what the rig poses, for a whole deformer stack (issue 21, "How it will be checked"):
// the demo character with three deformers (its own cage; a copy sculpted 3 cm forward under the head's
// mask; a copy under the arms' mask, summed) and the parametric driver in front of the chest, one control
// point pushed out. The baked exports (baked-animation and baked-skin, glb) are written, loaded back and
// posed by the file's own skinning and morph targets at every sampled frame of both clips: each frame is
// the rig's pose (what `cagewrap pose` writes and the editor shows: tests/workspace_stack_test.cpp)
// within 1e-5 of the skin's diagonal. The same frames of the plain rig (the project's cage alone) differ
// by centimetres at the head and the chest, so the check sees the layers and the driver: the driver's
// sculpt is in the file at every frame of the walk, carried by the skeleton.
#include <algorithm>
#include <numeric>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "core/character/skin_mask.h"
#include "core/character/skinning.h"
#include "core/document/document.h"
#include "core/export/rig_export.h"
#include "core/io/gltf_loader.h"
#include "core/io/gltf_writer.h"
#include "core/rig/deformer_stack.h"
#include "core/rig/rig.h"
#include "tests/gltf_builder.h"
#include "tests/driver_fixtures.h"
#include "tests/rig_fixtures.h"

namespace cagewrap {
namespace {

constexpr double kExportFps = 4.0;

DeformerLayer masked_copy(const Document& doc, const std::string& name, std::vector<std::string> joints,
                          glm::vec3 sculpt) {
  DeformerLayer l;
  l.name = name;
  l.cage = doc.cage;
  l.params = doc.params;
  l.attachment = doc.attachment;
  if (sculpt != glm::vec3(0.0f)) l.cage_offsets.assign(l.cage->num_vertices(), sculpt);
  auto mask = joint_region_mask(*doc.character, std::span<const std::string>(joints));
  EXPECT_TRUE(mask.ok()) << mask.error().message;
  l.mask = std::make_shared<const std::vector<float>>(*mask);
  l.mask_source = "joints " + joints.front();
  return l;
}

double diagonal(std::span<const glm::vec3> points) {
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (const glm::vec3& p : points) lo = glm::min(lo, p), hi = glm::max(hi, p);
  return glm::length(hi - lo);
}

TEST(StackExport, BakedFilesOfThreeDeformersAndADriverAreTheRigsPoseAtEveryFrame) {
  const Document plain = test::demo_document();
  Document doc = with_layers(plain, {masked_copy(plain, "face", {"head"}, glm::vec3(0.0f, 0.0f, 0.03f)),
                                     masked_copy(plain, "arms", {"shoulder.L", "shoulder.R"}, glm::vec3(0.0f))});
  doc = with_stack(doc, {StackMode::kSum, 2.0});
  doc = with_patch_driver(doc, test::chest_driver(0.06));
  auto rig = Rig::create(doc);
  ASSERT_TRUE(rig.ok()) << rig.error().message;
  auto plain_rig = Rig::create(plain);
  ASSERT_TRUE(plain_rig.ok()) << plain_rig.error().message;
  const Character& ch = *doc.character;
  const double diag = diagonal(rig->skin_rest());
  ASSERT_GT(diag, 1.0);

  for (ExportMode mode : {ExportMode::kBakedAnimation, ExportMode::kBakedSkin}) {
    SCOPED_TRACE(export_mode_name(mode));
    ExportOptions options;
    options.mode = mode;
    options.fps = kExportFps;
    options.keypose_steps = 0;
    auto exported = export_rig(doc, *rig, options);
    ASSERT_TRUE(exported.ok()) << exported.error().message;
    EXPECT_LT(exported->at_frames.max, 1e-5 * diag) << "the export's own report";
    const std::string path = test::temp_dir("stack_export") + "/" + export_mode_name(mode) + ".glb";
    ASSERT_TRUE(write_glb(path, exported->character).ok());
    auto loaded = load_character(path);
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;

    double worst = 0.0, stack_vs_plain = 0.0, chest_sculpt_min = 1e9;
    size_t frames = 0;
    std::vector<glm::vec3> skin(rig->num_skin_points()), plain_skin(plain_rig->num_skin_points());
    PosedCage posed;
    for (size_t c = 0; c < ch.clips.size(); ++c) {
      const int32_t lc = loaded->find_clip(ch.clips[c].name);
      ASSERT_GE(lc, 0) << ch.clips[c].name;
      for (double t : export_frame_times(ch.clips[c].duration, kExportFps)) {
        ASSERT_TRUE(rig->pose(doc, compose_pose(ch, int32_t(c), t, false), posed, skin).ok());
        ASSERT_TRUE(plain_rig->pose(plain, compose_pose(ch, int32_t(c), t, false), posed, plain_skin).ok());
        const std::vector<glm::vec3> file = skin_character(*loaded, sample_pose(*loaded, lc, t));
        ASSERT_EQ(file.size(), skin.size());
        double largest = 0.0;
        for (size_t i = 0; i < file.size(); ++i) {
          worst = std::max(worst, double(glm::length(file[i] - skin[i])));
          largest = std::max(largest, double(glm::length(file[i] - plain_skin[i])));
        }
        stack_vs_plain = std::max(stack_vs_plain, largest);
        if (ch.clips[c].name == "walk") chest_sculpt_min = std::min(chest_sculpt_min, largest);
        ++frames;
      }
    }
    EXPECT_EQ(frames, exported->frames);
    EXPECT_LT(worst, 1e-5 * diag) << "the file, posed by its own skinning, is the rig's pose";
    EXPECT_GT(stack_vs_plain, 0.02) << "the layers and the driver are in the file";
    EXPECT_GT(chest_sculpt_min, 0.01) << "at every frame of the walk the sculpt moves the skin";
    ::testing::Test::RecordProperty(std::string(export_mode_name(mode)) + "_worst_m", std::to_string(worst));
  }
}

}  // namespace
}  // namespace cagewrap
