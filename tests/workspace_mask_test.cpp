// The mask brush (issue 21: a deformer's skin mask painted), driven in-process on the demo character with
// a copy of its cage as a layer (app/workspace/workspace_mask.cpp): a dab moves the weights within the
// radius toward the brush's value (in full at the centre with strength 1, not beyond the radius), the
// stroke is one undo step and leaves the mask "painted" (no source); the frame is then what Rig makes
// for pose and the exports; fill sets every weight; the project's own cage has no mask to paint; a
// parametric driver's mask is painted the same way; the colours show the weights while painting.
#include <filesystem>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "core/io/patch_io.h"
#include "core/rig/rig.h"
#include "tests/driver_fixtures.h"
#include "tests/workspace_fixtures.h"

namespace cagewrap::app {
namespace {

using WorkspaceMaskTest = DemoWorkspaceTest;

TEST_F(WorkspaceMaskTest, PaintedMaskIsOneUndoStepAndWhatTheRigUses) {
  finish_bind();
  const auto w = [this]() -> const Document& { return ws.scene()->work(); };
  // the project's own cage is the base of the stack: no mask to paint
  ws.run("mask_paint on");
  EXPECT_FALSE(ws.view.mask.painting);
  EXPECT_TRUE(logged("the project's own cage is the base of the stack and has no mask"));

  ws.run("deformer_add " + std::string(CAGEWRAP_SOURCE_DIR) + "/assets/demo_cage.obj");
  ASSERT_EQ(w().layers.size(), 1u);
  ws.run("deformer_stack sum");  // in a sum a layer with mask 1 doubles the motion: the mask shows
  poll_while([this] { return ws.binding_any(); });
  ws.run("deformer_active 1");
  ws.run("mask_paint on");
  ASSERT_TRUE(ws.view.mask.painting);
  ASSERT_FALSE(ws.mask_colors().empty()) << "the skin shows the weights while painting";
  EXPECT_EQ(ws.mask_colors().size(), ws.scene()->skin_rest.size());

  // one dab at a chest vertex, radius 5 cm, toward 0 at full strength
  const std::vector<glm::vec3>& rest = ws.scene()->skin_rest;
  uint32_t centre = 0;
  for (uint32_t i = 0; i < rest.size(); ++i)
    if (glm::distance(rest[i], glm::vec3(0, 1.2f, 0.1f)) < glm::distance(rest[centre], glm::vec3(0, 1.2f, 0.1f))) centre = i;
  const size_t steps = undo_steps();
  ws.run("mask_brush 0 1 0.05");
  ws.run("clip rest");
  ws.run("mask_paint_at_skin_vertex " + std::to_string(centre));
  EXPECT_EQ(undo_steps(), steps + 1) << "a stroke is one undo step";
  ASSERT_TRUE(w().layers[0].mask);
  EXPECT_TRUE(w().layers[0].mask_source.empty()) << "a painted mask has no source";
  const std::vector<float>& m = *w().layers[0].mask;
  EXPECT_EQ(m[centre], 0.0f) << "the centre painted out in full";
  size_t changed = 0, far_changed = 0;
  for (size_t i = 0; i < m.size(); ++i) {
    if (m[i] != 1.0f) ++changed;
    if (m[i] != 1.0f && glm::distance(rest[i], rest[centre]) > 0.05f + 1e-4f) ++far_changed;
  }
  EXPECT_GT(changed, 10u);
  EXPECT_LT(changed, m.size() / 10);
  EXPECT_EQ(far_changed, 0u) << "nothing beyond the radius (a surface distance is never shorter than the straight one)";

  // posed, the frame is the rig's with the painted mask
  ws.run("clip walk");
  ws.run("time 0.3");
  ws.update_pose();
  EXPECT_LT(rig_gap(), 1e-5);
  const std::vector<glm::vec3> expected = ws.scene()->skin_posed();
  const auto& pb = ws.view.playback;
  PosedCage cage;
  // and the painted mask matters: without it the sum moves the chest further
  Document unmasked = w();
  unmasked.layers[0].mask = nullptr;
  unmasked.revision = next_revision();
  auto plain = Rig::create(unmasked);
  ASSERT_TRUE(plain.ok());
  std::vector<glm::vec3> doubled(plain->num_skin_points());
  ASSERT_TRUE(plain->pose_clip(unmasked, pb.clip, pb.player.time(), pb.pose_override, cage, doubled).ok());
  EXPECT_GT(glm::distance(doubled[centre], expected[centre]), 1e-3f);

  // fill, undo
  ws.run("mask_fill 0.25");
  ASSERT_TRUE(w().layers[0].mask);
  EXPECT_EQ((*w().layers[0].mask)[12345], 0.25f);
  ws.run("mask_fill 2");
  EXPECT_TRUE(logged("mask: a weight is 0 to 1"));
  ws.run("undo");
  EXPECT_EQ((*w().layers[0].mask)[centre], 0.0f) << "the stroke's mask is back";
  ws.run("undo");
  EXPECT_FALSE(w().layers[0].mask) << "and before it, none";

  // a parametric driver's mask: painted the same way
  ws.run("mask_paint on driver 0");
  EXPECT_FALSE(ws.view.mask.painting);
  EXPECT_TRUE(logged("mask: no parametric driver 0"));
  const std::string patch = (std::filesystem::temp_directory_path() / "cagewrap_workspace_mask_chest.cwpatch").string();
  ASSERT_TRUE(save_patch_any(patch, test::chest_driver(0.0)->rest).ok());
  ws.run("driver_add " + patch);
  poll_while([this] { return ws.binding_patch_driver(); });
  ASSERT_EQ(driver_count(w()), 1u);
  ws.run("mask_paint on driver 0");
  ASSERT_TRUE(ws.view.mask.painting);
  ws.run("mask_paint_at_skin_vertex " + std::to_string(centre));
  ASSERT_TRUE(w().driver_place.mask);
  EXPECT_EQ((*w().driver_place.mask)[centre], 0.0f);
  EXPECT_FALSE(w().layers[0].mask) << "the layer's mask is untouched";
  ws.run("mask_paint off");
  EXPECT_TRUE(ws.mask_colors().empty());
}

}  // namespace
}  // namespace cagewrap::app
