// Several parametric drivers in the editor (issue 21: a project holds any number of deformers, drivers
// among them), driven in-process on the demo character: driver_add makes the first (bound before it
// enters the document) and then more (each one undo step, bound in the background by the scene's driver
// rigs); driver_edit makes another the first, which the patch_* actions sculpt; the frame is what Rig
// makes for `pose` and the exports (within 1e-5 of the diagonal) with both drivers moving the skin, and
// changes by each one's sculpt alone; mute and remove act on the driver named, undo brings it back; the
// project file keeps both.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "app/workspace/scene.h"
#include "core/document/project_io.h"
#include "core/io/patch_io.h"
#include "core/rig/rig.h"
#include "tests/driver_fixtures.h"
#include "tests/workspace_fixtures.h"

namespace cagewrap::app {
namespace {

namespace fs = std::filesystem;

// The demo with the chest driver added (its file in `dir`), control point 14 sculpted out of the chest, at
// the walk's 0.3 s: what the tests of the first driver's attachment and set edits start from.
class WorkspaceDriversTest : public DemoWorkspaceTest {
 protected:
  void add_sculpted_chest_driver(const fs::path& dir) {
    fs::create_directories(dir);
    ASSERT_TRUE(save_patch_any((dir / "chest.cwpatch").string(), test::chest_driver(0.0)->rest).ok());
    finish_bind();
    ws.run("driver_add " + (dir / "chest.cwpatch").string());
    poll_while([this] { return ws.binding_patch_driver(); });
    ws.run("patch_panel");
    ws.run("patch_select 14");
    ws.run("patch_move 0 0 0.05");
    ws.run("clip walk");
    ws.run("time 0.3");
  }
};

TEST_F(WorkspaceDriversTest, SeveralDriversAreAddedEditedMutedAndMatchTheRig) {
  const fs::path dir = fs::temp_directory_path() / "cagewrap_workspace_drivers_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  // two drivers over the chest sheet: the same rest surface, a file each (no sculpt: posed = rest)
  const auto chest = test::chest_driver(0.0);
  ASSERT_TRUE(save_patch_any((dir / "front.cwpatch").string(), chest->rest).ok());
  ASSERT_TRUE(save_patch_any((dir / "second.cwpatch").string(), chest->rest).ok());
  finish_bind();
  ws.run("clip walk");
  ws.run("time 0.3");
  const auto w = [this]() -> const Document& { return ws.scene()->work(); };

  ws.run("driver_add " + (dir / "front.cwpatch").string());
  poll_while([this] { return ws.binding_patch_driver(); });
  ASSERT_EQ(driver_count(w()), 1u) << "the first driver enters once bound";
  const size_t steps = undo_steps();
  ws.run("driver_add " + (dir / "second.cwpatch").string());
  ASSERT_EQ(driver_count(w()), 2u);
  EXPECT_EQ(undo_steps(), steps + 1);
  EXPECT_EQ(driver_name(w(), 1), "second");
  ASSERT_EQ(ws.scene()->driver_rigs.size(), 1u) << "the second binds in the background";
  poll_while([this] { return ws.binding_any(); });
  ASSERT_TRUE(ws.scene()->driver_rigs[0].layer) << ws.scene()->driver_rigs[0].error;
  EXPECT_TRUE(logged("parametric driver 'second' bound"));

  // the frame's largest distance from what the rig makes (pose, the exports), relative to the diagonal
  const auto frame = [this] {
    ws.update_pose();
    return ws.scene()->skin_posed();
  };
  const auto largest_change = [](const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
    double d = 0.0;
    for (size_t i = 0; i < a.size(); ++i) d = std::max(d, double(glm::distance(a[i], b[i])));
    return d;
  };
  const std::vector<glm::vec3> unsculpted = frame();

  // sculpt the first (control point 14 out of the chest), then make the second the first and sculpt it
  ws.run("patch_panel");
  ws.run("patch_select 14");
  ws.run("patch_move 0 0 0.05");
  const std::vector<glm::vec3> one = frame();
  EXPECT_TRUE(ws.scene()->skin_driven());
  EXPECT_GT(largest_change(unsculpted, one), 0.01) << "the first driver's sculpt moves the chest";
  ws.run("driver_edit 1");
  EXPECT_EQ(driver_name(w(), 0), "second");
  EXPECT_EQ(driver_name(w(), 1), "driver");
  poll_while([this] { return ws.binding_patch_driver() || ws.binding_any(); });
  EXPECT_LT(largest_change(one, frame()), 1e-6) << "which driver is first does not change the skin";
  ws.run("patch_select 20");
  ws.run("patch_move 0 -0.04 0.03");
  const std::vector<glm::vec3> both = frame();
  EXPECT_GT(largest_change(one, both), 0.01) << "the second driver's sculpt moves the skin too";
  EXPECT_LT(rig_gap(), 1e-5) << "with both drivers the frame is the rig's";

  // muting the one that is not first leaves its sculpt out; undo brings it back
  ws.run("driver_mute 1 on");
  EXPECT_FALSE(driver_at(w(), 1).driver->drive_skin);
  EXPECT_TRUE(driver_at(w(), 0).driver->drive_skin);
  const std::vector<glm::vec3> muted = frame();
  EXPECT_GT(largest_change(both, muted), 0.01);
  EXPECT_LT(rig_gap(), 1e-5);
  ws.run("undo");
  EXPECT_FALSE(ws.binding_any()) << "a muted driver keeps its binding: unmuting binds nothing";
  EXPECT_LT(largest_change(both, frame()), 1e-6);

  // each driver's place among the layers (none here: 0, or after them all)
  ws.run("driver_after 1 0");
  EXPECT_EQ(driver_at(w(), 1).place->after, 0);
  EXPECT_EQ(driver_at(w(), 0).place->after, -1) << "the other stays";
  ws.run("driver_after 1 2");
  EXPECT_TRUE(logged("parametric driver: it goes after 0 to 0 layers"));
  ws.run("driver_after 1 last");
  EXPECT_EQ(driver_at(w(), 1).place->after, -1);

  // soloed: only that driver moves the skin (the cages leave the rest skin); one undo step, and off again
  ws.run("driver_solo 1");
  ASSERT_EQ(soloed_driver(w()), std::optional<size_t>(1));
  const std::vector<glm::vec3> solo = frame();
  EXPECT_LT(rig_gap(), 1e-5) << "the soloed driver alone, as the rig makes it";
  EXPECT_GT(largest_change(both, solo), 0.01);
  ws.run("driver_solo off");
  EXPECT_FALSE(soloed_driver(w()));
  EXPECT_LT(largest_change(both, frame()), 1e-6);

  // hidden: its control net is not drawn; the project keeps that
  ws.run("driver_hide 1 on");
  EXPECT_TRUE(driver_at(w(), 1).place->hidden);
  EXPECT_FALSE(driver_at(w(), 0).place->hidden);

  // the project keeps both, with their names and sculpts
  ASSERT_TRUE(save_project((dir / "two.cagewrap").string(), w()).ok());
  auto loaded = load_project((dir / "two.cagewrap").string());
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  ASSERT_EQ(driver_count(loaded->document), 2u);
  EXPECT_EQ(driver_name(loaded->document, 0), "second");
  EXPECT_TRUE(*driver_at(loaded->document, 1).driver == *driver_at(w(), 1).driver);
  EXPECT_TRUE(driver_at(loaded->document, 1).place->hidden);

  // saved with caching on and the editor's bindings (the first driver's, the other's rig's): each goes to its
  // cache file (P.D1.cwb, P.D2.cwb); the project opened again uses both caches (no bind) and the frame is the rig's
  const std::vector<const Binding*> bindings = ws.scene()->driver_bindings();
  ASSERT_EQ(bindings.size(), 2u);
  EXPECT_NE(bindings[0], nullptr);
  EXPECT_NE(bindings[1], nullptr);
  SaveOptions cache;
  cache.binding = ws.scene()->deformer_bindings()[0];
  cache.driver_bindings = bindings;
  const std::string cached_path = (dir / "cached.cagewrap").string();
  ASSERT_TRUE(save_project(cached_path, with_cache_binding(w(), true), cache).ok());
  EXPECT_TRUE(fs::exists(cached_path + ".D1.cwb"));
  EXPECT_TRUE(fs::exists(cached_path + ".D2.cwb"));
  {
    ProjectOpen opened;
    auto reopened = load_project_scene(cached_path, opened);
    ASSERT_TRUE(reopened.ok()) << reopened.error().message;
    ws.set_scene(std::move(reopened).value());
    ws.run("clip walk");
    ws.run("time 0.3");
    ws.poll_jobs();
    poll_while([this] { return ws.binding_patch_driver() || ws.binding_any(); });
    EXPECT_TRUE(logged("parametric driver: used the cached binding " + cached_path + ".D1.cwb (no bind)"));
    EXPECT_TRUE(logged("parametric driver 'driver': using the cached binding " + cached_path + ".D2.cwb (no bind)"));
    EXPECT_TRUE(ws.scene()->driver_bound());
    EXPECT_LT(largest_change(both, frame()), 1e-6);
    EXPECT_LT(rig_gap(), 1e-5) << "the drivers from their caches make the rig's frame";
  }

  // removing the first makes the other the first; a driver that is not there is an error naming it
  ws.run("driver_remove 0");
  ASSERT_EQ(driver_count(w()), 1u);
  EXPECT_EQ(driver_name(w(), 0), "driver");
  ws.run("driver_remove 3");
  EXPECT_TRUE(logged("error: action: no parametric driver 3 (the drivers are 0 to 0)"));
  ws.run("undo");
  EXPECT_EQ(driver_count(w()), 2u);
}

// The first driver's attachment in the editor (patch_attach, patch_attach_point; the driver window's
// "control points follow" and "attach it to the selected joint"): one undo step each, refused when it cannot
// attach (fitted, a control point past the driver's, a node that is not a joint), and the frame is the rig's.
TEST_F(WorkspaceDriversTest, TheDriversAttachmentIsEditedAndTheFrameIsTheRigs) {
  const fs::path dir = fs::temp_directory_path() / "cagewrap_workspace_drivers_attach";
  add_sculpted_chest_driver(dir);
  const auto w = [this]() -> const Document& { return ws.scene()->work(); };
  const size_t steps = undo_steps();
  ws.run("patch_attach skin_weights");
  ASSERT_TRUE(w().driver_place.attachment);
  EXPECT_EQ(w().driver_place.attachment->mode, AttachmentMode::kSkinWeights);
  ws.run("patch_attach_point 14 hips");
  ASSERT_EQ(w().driver_place.attachment->overrides.size(), 1u);
  EXPECT_EQ(w().driver_place.attachment->overrides[0].vertex, 14u);
  EXPECT_EQ(undo_steps(), steps + 2);
  ws.run("patch_attach fitted");
  EXPECT_TRUE(logged("patch_attach closest|rigid|smooth|skin_weights"));
  ws.run("patch_attach_point 30 hips");
  EXPECT_TRUE(logged("parametric driver: attachment: no control point 30 (the driver has 30)"));
  ws.run("patch_attach_point 3 nowhere");
  EXPECT_TRUE(logged("the skeleton has no node 'nowhere'"));
  EXPECT_EQ(undo_steps(), steps + 2) << "refused edits leave no step";

  ws.update_pose();
  ASSERT_TRUE(ws.scene()->skin_driven());
  const std::vector<glm::vec3> shown = ws.scene()->skin_posed();
  EXPECT_LT(rig_gap(), 1e-5);
  // its set edits from a file (sample ids): one undo step, bound again, the frame still the rig's
  {
    std::ofstream((dir / "edits.json").string())
        << R"({"format": "cagewrap-set-edits", "version": 1, "edits": [{"point": 32831, "include": [0], "only": true}]})";
    std::ofstream((dir / "edits_bad.json").string())
        << R"({"format": "cagewrap-set-edits", "version": 1, "edits": [{"point": 32831, "include": [99]}]})";
  }
  ws.run("patch_set_edits " + (dir / "edits.json").string());
  ASSERT_EQ(w().driver_place.set_edits.size(), 1u);
  EXPECT_EQ(w().driver_place.set_edits[0].point, 32831u);
  ws.poll_jobs();  // the frame loop's poll: the driver is bound again with its edits
  EXPECT_TRUE(ws.binding_patch_driver());
  poll_while([this] { return ws.binding_patch_driver(); });
  EXPECT_TRUE(ws.scene()->driving()) << "bound again with the edits";
  ws.update_pose();
  EXPECT_LT(rig_gap(), 1e-5);
  ws.run("patch_set_edits " + (dir / "edits_bad.json").string());
  ASSERT_FALSE(errors.empty());
  EXPECT_NE(errors.back().find("names sample 99"), std::string::npos) << errors.back();
  EXPECT_EQ(w().driver_place.set_edits.size(), 1u) << "a bad file changes nothing";
  ws.run("patch_set_edits none");
  EXPECT_TRUE(w().driver_place.set_edits.empty());
  ws.poll_jobs();
  poll_while([this] { return ws.binding_patch_driver(); });

  // and it matters: back to the closest limbs, the frame changes
  ws.run("patch_attach closest");
  EXPECT_FALSE(w().driver_place.attachment);
  ws.update_pose();
  double moved = 0.0;
  for (size_t i = 0; i < shown.size(); ++i) moved = std::max(moved, double(glm::distance(shown[i], ws.scene()->skin_posed()[i])));
  EXPECT_GT(moved, 1e-3);
  ws.run("undo");
  EXPECT_TRUE(w().driver_place.attachment);
}

// The first driver's set edits picked in the view (patch_samples, patch_select_set_samples, patch_sample_select,
// patch_set_edit; the driver window's "pick samples in the view"): the samples driving a selected chest vertex
// are its binding's set; "only" with one picked sample is one undo step, binds again, and the vertex then follows
// that sample alone, as the file-made edit does; remove and reset act the same way; refused edits (no
// samples picked, no skin selected, a sample past the driver's) are named and leave no step.
TEST_F(WorkspaceDriversTest, SetEditsArePickedInTheViewAndTheFrameIsTheRigs) {
  const fs::path dir = fs::temp_directory_path() / "cagewrap_workspace_drivers_sets";
  add_sculpted_chest_driver(dir);
  const auto w = [this]() -> const Document& { return ws.scene()->work(); };
  ws.run("patch_samples on");
  EXPECT_TRUE(ws.view.patch.samples);
  EXPECT_EQ(ws.driver_sample_points().size(), 35u) << "5 x 4 spans at density 2: 7 x 5 samples";

  constexpr uint32_t kChest = 32831;
  const Binding& before = *ws.scene()->driver_binding.binding;
  std::vector<uint32_t> set;
  for (uint32_t i = before.offsets[kChest]; i < before.offsets[kChest + 1]; ++i)
    if (before.weights[i] > 0) set.push_back(before.ids[i]);
  std::sort(set.begin(), set.end());
  ASSERT_GT(set.size(), 1u) << "the chest vertex is driven by several samples";
  ws.run("select_skin_vertex " + std::to_string(kChest));
  ws.run("patch_select_set_samples");
  EXPECT_EQ(std::vector<uint32_t>(ws.view.patch.picked.begin(), ws.view.patch.picked.end()), set);
  const std::vector<uint8_t> states = ws.driver_sample_states();
  EXPECT_EQ(std::count(states.begin(), states.end(), 2), std::ptrdiff_t(set.size())) << "the picked samples are shown picked";

  // only sample 0: one undo step, bound again, the vertex follows sample 0 alone; the frame is the rig's
  const size_t steps = undo_steps();
  ws.run("patch_sample_select 0");
  ws.run("patch_set_edit only");
  EXPECT_EQ(undo_steps(), steps + 1);
  ASSERT_EQ(w().driver_place.set_edits.size(), 1u);
  EXPECT_TRUE(w().driver_place.set_edits[0] == (SetEdit{kChest, {}, {0}, true}));
  ws.poll_jobs();
  poll_while([this] { return ws.binding_patch_driver(); });
  ASSERT_TRUE(ws.scene()->driving()) << "bound again with the edit";
  const Binding& after = *ws.scene()->driver_binding.binding;
  ASSERT_EQ(after.offsets[kChest + 1] - after.offsets[kChest], 1u);
  EXPECT_EQ(after.ids[after.offsets[kChest]], 0u);
  ws.update_pose();
  EXPECT_LT(rig_gap(), 1e-5) << "the picked edit is in the rig pose and export use";

  // remove two samples of another vertex's set; reset brings the vertex back; undo restores
  ws.run("select_skin_vertex " + std::to_string(kChest + 1));
  ws.run("patch_sample_select " + std::to_string(set[0]) + "," + std::to_string(set[1]));
  ws.run("patch_set_edit remove");
  ASSERT_EQ(w().driver_place.set_edits.size(), 2u);
  EXPECT_EQ(w().driver_place.set_edits[1].exclude, (std::vector<uint32_t>{set[0], set[1]}));
  ws.run("patch_set_edit reset");
  EXPECT_EQ(w().driver_place.set_edits.size(), 1u);
  EXPECT_EQ(undo_steps(), steps + 3);
  ws.run("undo");
  EXPECT_EQ(w().driver_place.set_edits.size(), 2u);

  // refused: nothing picked, no skin selected, a sample past the driver's; no step
  const size_t refused = undo_steps();
  ws.run("patch_sample_select none");
  ws.run("patch_set_edit add");
  EXPECT_TRUE(logged("pick the driver's samples to add first"));
  ws.run("patch_sample_select 35");
  EXPECT_TRUE(logged("no sample 35 (the driver has 35)"));
  ws.run("select none");
  ws.view.selection.skin_vertices.clear();
  ws.run("patch_sample_select 3");
  ws.run("patch_set_edit add");
  EXPECT_TRUE(logged("select the skin vertices to edit first"));
  EXPECT_EQ(undo_steps(), refused);
}

}  // namespace
}  // namespace cagewrap::app
