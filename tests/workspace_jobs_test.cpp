// The workspace's other background work and document storage, driven in-process on the demo
// character (issue 20): the parametric driver (app/workspace/workspace_patch.cpp: fit, control-point
// moves by index and by the move gizmo's path, undo and redo, density, cancel, a missing file), the
// fidelity check (workspace_fidelity.cpp: with the scene's binding, the same figures as a rig bound on
// its own, cancel, the frame's heat map) and project storage (workspace_project.cpp: embedding the
// character, writing it out, caching the binding). The windows only draw these
// (tests/editor_patch_gui_test.cpp and editor_fidelity_gui_test.cpp keep what is drawn).
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "core/deform/patch_fit.h"
#include "tests/patch_fixtures.h"
#include "core/document/project_io.h"
#include "core/geometry/mesh_io.h"
#include "core/rig/fidelity.h"
#include "core/rig/rig.h"
#include "tests/workspace_fixtures.h"

namespace cagewrap::app {
namespace {

namespace fs = std::filesystem;

fs::path test_dir() {
  const fs::path dir = fs::temp_directory_path() / "cagewrap_workspace_jobs_test" /
                       ::testing::UnitTest::GetInstance()->current_test_info()->name();
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

using WorkspacePatchTest = DemoWorkspaceTest;

TEST_F(WorkspacePatchTest, FitMovesUndoDensityAndCancel) {
  const fs::path dir = test_dir();
  const PolyMesh sheet = test::chest_sheet();
  ASSERT_TRUE(save_obj((dir / "sheet.obj").string(), sheet.positions, sheet).ok());
  ASSERT_TRUE(ws.import_cage((dir / "sheet.obj").string()));
  ws.run("mode cage_faces");
  ws.run("select all");
  ASSERT_EQ(ws.view.selection.cage_faces.size(), 20u);
  auto grid = fit_patch_to_faces(sheet, sheet.positions, ws.view.selection.cage_faces.indices());
  ASSERT_TRUE(grid.ok()) << grid.error().message;

  // the fit enters the document once its bind has succeeded, as one undo step
  const size_t steps = undo_steps();
  ws.run("patch_fit");
  EXPECT_TRUE(ws.binding_patch_driver());
  EXPECT_FALSE(doc().patch_driver) << "not before it is bound";
  poll_while([this] { return ws.binding_patch_driver(); });
  ASSERT_TRUE(doc().patch_driver);
  EXPECT_EQ(undo_steps(), steps + 1);
  EXPECT_TRUE(logged("Fit a 5 x 6 parametric driver to 20 cage faces"));
  EXPECT_TRUE(logged("to 35 samples (density 2"));
  EXPECT_TRUE(ws.scene()->driver_bound());

  // point 14 by the move gizmo's path (begin/update/end_move while the window is open), 15 by index
  ws.view.patch.editing = true;
  ws.run("patch_select 14");
  ASSERT_TRUE(ws.patch_point_position());
  EXPECT_LT(glm::length(*ws.patch_point_position() - grid->points[14]), 1e-12);
  ASSERT_TRUE(ws.begin_move());
  ws.update_move(glm::dvec3(0.05, 0.0, 0.0));
  ws.update_move(glm::dvec3(0.1, 0.15, 0.0));  // a drag rebuilds from its start: the total counts
  ws.end_move();
  ws.run("patch_select 15");
  ws.run("patch_move -0.1 0.15 0");
  EXPECT_EQ(undo_steps(), steps + 3);
  auto point = [this](size_t k) { return doc().patch_driver->posed.control_points()[k]; };
  EXPECT_LT(glm::length(point(14) - (grid->points[14] + glm::dvec3(0.1, 0.15, 0))), 1e-12);
  EXPECT_LT(glm::length(point(15) - (grid->points[15] + glm::dvec3(-0.1, 0.15, 0))), 1e-12);
  EXPECT_LT(glm::length(point(13) - grid->points[13]), 1e-12) << "the others stay";

  // driving the skin: the frame shows the driver's skin, moved around the chest only
  ws.run("patch_drive on");
  ws.run("clip rest");
  ws.update_pose();
  ASSERT_TRUE(ws.scene()->skin_driven());
  const std::vector<glm::vec3>& skin = ws.scene()->skin_posed();
  float largest = 0.0f;
  for (size_t i = 0; i < skin.size(); ++i) largest = std::max(largest, glm::length(skin[i] - ws.scene()->skin_rest[i]));
  EXPECT_GT(largest, 0.01f);
  EXPECT_LT(largest, 0.5f);
  // posed, the frame is what the rig (pose, the exports) makes: the sculpt carried by the skeleton
  finish_bind();  // the sheet's own bind (the cage), so that the frame is the cage's skin and the sculpt
  ws.run("clip walk");
  ws.run("time 0.3");
  ws.update_pose();
  ASSERT_TRUE(ws.scene()->skin_driven());
  ASSERT_TRUE(ws.scene()->skin_from_cage);
  // the frame's largest distance from what the rig makes (pose, the exports), relative to the diagonal
  const auto frame_gap = [this] {
    ws.update_pose();
    EXPECT_TRUE(ws.scene()->skin_driven());
    return rig_gap();
  };
  EXPECT_LT(frame_gap(), 1e-5);
  // the driver as a deformer of the stack: its sculpt keyed against the spine's X at this pose, a mask, a
  // place; each one undo step, and the frame still the rig's
  {
    const Skeleton& sk = doc().character->skeleton;
    uint32_t spine = 0;
    for (uint32_t n = 0; n < sk.size(); ++n)
      if (sk.node(n).name == "spine") spine = n;
    const size_t before_key = undo_steps();
    const PatchDriver sculpted = *doc().patch_driver;
    ws.run("patch_key X");
    EXPECT_TRUE(logged("select the joint whose rotation keys the sculpt")) << "no joint selected: refused";
    ws.run("select_joint " + std::to_string(spine));
    ws.run("patch_key X");
    EXPECT_EQ(undo_steps(), before_key + 1);
    ASSERT_EQ(doc().driver_place.keyposes.size(), 1u);
    EXPECT_EQ(doc().driver_place.keyposes[0].name, "spine_X");
    EXPECT_TRUE(doc().patch_driver->posed == doc().patch_driver->rest) << "the sculpt went into the key";
    EXPECT_LT(frame_gap(), 1e-5);
    ws.run("patch_mask joints chest,nope");
    EXPECT_TRUE(logged("nope")) << "an unknown joint is named";
    ws.run("patch_mask joints chest");
    ASSERT_TRUE(doc().driver_place.mask);
    EXPECT_EQ(doc().driver_place.mask_source, "joints chest");
    EXPECT_LT(frame_gap(), 1e-5);
    ws.run("patch_after 0");
    EXPECT_EQ(doc().driver_place.after, 0);
    EXPECT_EQ(undo_steps(), before_key + 3);
    // its own binding parameters: one step, bound again in the background, and the frame is the rig's
    ws.run("patch_binding 6 0.1 8");
    EXPECT_EQ(undo_steps(), before_key + 4);
    ASSERT_TRUE(doc().driver_place.params);
    EXPECT_EQ(doc().driver_place.params->local, 6.0);
    EXPECT_FALSE(ws.scene()->driver_bound()) << "bound with the old parameters";
    ws.poll_jobs();
    poll_while([this] { return ws.binding_patch_driver(); });
    EXPECT_TRUE(ws.scene()->driver_bound());
    EXPECT_LT(frame_gap(), 1e-5);
    ws.run("patch_binding 6 2 8");
    EXPECT_TRUE(logged("parametric driver: binding:")) << "a bad epsilon is refused";
    EXPECT_EQ(undo_steps(), before_key + 4);
    ws.run("undo");
    ws.run("undo");
    ws.run("undo");
    ws.run("undo");
    EXPECT_EQ(doc().driver_place, DriverPlacement{});
    EXPECT_TRUE(*doc().patch_driver == sculpted) << "the sculpt is back";
  }
  ws.run("clip rest");

  // undo and redo the second move
  ws.run("undo");  // drive
  ws.run("undo");  // point 15
  EXPECT_LT(glm::length(point(15) - grid->points[15]), 1e-12);
  EXPECT_LT(glm::length(point(14) - (grid->points[14] + glm::dvec3(0.1, 0.15, 0))), 1e-12);
  ws.run("redo");
  EXPECT_LT(glm::length(point(15) - (grid->points[15] + glm::dvec3(-0.1, 0.15, 0))), 1e-12);

  // density: bound again, one undo step; undone, the workspace binds the old density by itself
  ws.run("patch_density 6");
  poll_while([this] { return ws.binding_patch_driver(); });
  EXPECT_EQ(doc().patch_driver->density, 6u);
  EXPECT_TRUE(logged("to 247 samples (density 6"));
  ws.run("undo");
  EXPECT_EQ(doc().patch_driver->density, 2u);
  EXPECT_FALSE(ws.scene()->driver_bound());
  ws.poll_jobs();
  poll_while([this] { return ws.binding_patch_driver(); });
  EXPECT_TRUE(ws.scene()->driver_bound()) << "the undone density is bound again";

  // a bind cancelled leaves the driver as it was; a missing file is an error naming it
  const size_t before = undo_steps();
  ws.run("patch_density 150 nowait");
  EXPECT_TRUE(ws.patch_state().nowait);
  ws.run("patch_cancel");
  poll_while([this] { return ws.binding_patch_driver(); });
  EXPECT_TRUE(logged("parametric driver: bind cancelled; the driver is unchanged"));
  EXPECT_EQ(doc().patch_driver->density, 2u);
  EXPECT_EQ(undo_steps(), before);
  ws.run("patch_import " + (dir / "missing.cwpatch").string());
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_NE(errors[0].find("missing.cwpatch"), std::string::npos) << errors[0];
  EXPECT_EQ(undo_steps(), before);
  // a saved project opens with its driver, posed, and the workspace binds it
  ASSERT_TRUE(save_project((dir / "driver.cagewrap").string(), doc()).ok());
  const PatchSurface posed = doc().patch_driver->posed;
  ProjectOpen opened;
  auto reopened = load_project_scene((dir / "driver.cagewrap").string(), opened);
  ASSERT_TRUE(reopened.ok()) << reopened.error().message;
  ws.set_scene(std::move(reopened).value());
  ASSERT_TRUE(doc().patch_driver);
  EXPECT_EQ(doc().patch_driver->posed, posed);
  EXPECT_EQ(doc().patch_driver->density, 2u);
  ws.poll_jobs();
  poll_while([this] { return ws.binding_patch_driver(); });
  EXPECT_TRUE(ws.scene()->driver_bound());
  EXPECT_EQ(undo_steps(), 0u) << "the driver is the opened project's, not an undo step";

  ws.run("patch_density 0");
  EXPECT_TRUE(logged("density 0 (use 1 to 1024)"));
  ws.run("patch_drive maybe");
  EXPECT_TRUE(logged("patch_drive on|off"));
}

using WorkspaceFidelityTest = DemoWorkspaceTest;

// The check of every clip takes the scene's binding (no bind of its own) and reports what a rig bound
// on its own reports; Cancel stops it; the frame's figures and heat map are the workspace's.
TEST_F(WorkspaceFidelityTest, TheCheckUsesTheSceneBindingAndMatchesAFreshRig) {
  finish_bind();
  ASSERT_TRUE(ws.scene()->binding_for_jobs()) << "the scene's binding is the document's";
  ws.run("fidelity_check");
  EXPECT_TRUE(ws.checking_fidelity());
  poll_while([this] { return ws.checking_fidelity(); });
  EXPECT_TRUE(logged("checking the rig against the file's skinning on every clip (with the current binding)"));
  ASSERT_TRUE(ws.fidelity().report);
  EXPECT_EQ(ws.fidelity().report_key, ws.rig_key());
  EXPECT_TRUE(logged("fidelity, every clip ("));

  auto rig = Rig::create(doc());
  ASSERT_TRUE(rig.ok()) << rig.error().message;
  FidelityOptions options;
  options.thresholds = ws.view.fidelity.thresholds;
  auto fresh = check_fidelity(doc(), *rig, options);
  ASSERT_TRUE(fresh.ok()) << fresh.error().message;
  const FidelityReport& got = *ws.fidelity().report;
  ASSERT_EQ(got.clips.size(), fresh->clips.size());
  EXPECT_EQ(got.overall.frames, fresh->overall.frames);
  EXPECT_NEAR(got.overall.worst.worst, fresh->overall.worst.worst, 1e-7);
  EXPECT_NEAR(got.overall.rms.rms, fresh->overall.rms.rms, 1e-7);
  EXPECT_NEAR(got.overall.stretch.stretch, fresh->overall.stretch.stretch, 1e-5);

  // a second check while one runs is refused; Cancel stops it and keeps the last report
  ws.run("fidelity_check nowait");
  EXPECT_TRUE(ws.fidelity().nowait);
  ws.run("fidelity_check");
  EXPECT_TRUE(logged("fidelity: a check is running already"));
  ws.run("fidelity_cancel");
  poll_while([this] { return ws.checking_fidelity(); });
  EXPECT_TRUE(logged("fidelity check cancelled"));
  EXPECT_EQ(ws.fidelity().outcome, "cancelled");
  EXPECT_TRUE(ws.fidelity().report);

  // at rest the demo's rig is its skinning: the heat map is grey everywhere
  ws.run("clip rest");
  ws.run("heatmap on");
  ws.run("fidelity_frame");
  EXPECT_TRUE(logged("fidelity, this frame: worst 0.0000%"));
  const auto& colors = ws.fidelity().colors;
  ASSERT_EQ(colors.size(), ws.scene()->skin_rest.size());
  for (const glm::vec4& c : colors) ASSERT_EQ(c, fidelity_color(0.0f));
  ws.run("heatmap off");
  ws.run("fidelity_frame");
  EXPECT_TRUE(ws.fidelity().colors.empty());
}

// With the cage moved since the bind (a bind under way), the job binds on its own and says nothing
// of the current binding.
TEST_F(WorkspaceFidelityTest, AnOutOfDateBindingIsNotUsed) {
  finish_bind();
  ws.run("bind_param epsilon 0.2");
  ws.run("rebind");
  ASSERT_TRUE(ws.scene()->job);
  EXPECT_FALSE(ws.scene()->binding_for_jobs());
  ws.run("fidelity_check nowait");
  EXPECT_TRUE(logged("checking the rig against the file's skinning on every clip ..."));
  ws.run("fidelity_cancel");
  poll_while([this] { return ws.checking_fidelity(); });
}

using WorkspaceProjectTest = DemoWorkspaceTest;

TEST_F(WorkspaceProjectTest, EmbeddingWritingOutAndCachingAreUndoSteps) {
  const fs::path dir = test_dir();
  const std::string assets = std::string(CAGEWRAP_SOURCE_DIR) + "/assets/";
  fs::copy_file(assets + "demo_character.glb", dir / "hero.glb");
  auto scene = load_scene((dir / "hero.glb").string(), assets + "demo_cage.obj");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  ws.set_scene(std::move(scene).value());
  const std::string bytes = read_bytes(dir / "hero.glb");

  ws.run("embed on");
  ASSERT_TRUE(doc().embedded_character);
  EXPECT_EQ(doc().embedded_character->size(), bytes.size());
  EXPECT_EQ(undo_steps(), 1u);
  EXPECT_TRUE(logged("embedded the character " + (dir / "hero.glb").string()));
  EXPECT_FALSE(ws.where_to_unembed()) << "the file it came from still holds the bytes";

  // the file gone: `embed off` alone is refused by name, the browser is told where to propose
  fs::remove(dir / "hero.glb");
  auto ask = ws.where_to_unembed();
  ASSERT_TRUE(ask);
  EXPECT_EQ(ask->name, "hero.glb");
  ws.run("embed off");
  EXPECT_TRUE(logged("the character file " + (dir / "hero.glb").string() + " is gone or holds other bytes"));
  EXPECT_TRUE(doc().embedded_character);
  ws.run("embed off " + (dir / "back.glb").string());
  EXPECT_FALSE(doc().embedded_character);
  EXPECT_EQ(doc().character_path, (dir / "back.glb").string());
  EXPECT_EQ(read_bytes(dir / "back.glb"), bytes);
  EXPECT_EQ(undo_steps(), 2u);
  ws.run("undo");
  EXPECT_TRUE(doc().embedded_character) << "undo embeds it again";

  ws.run("cache_binding on");
  EXPECT_TRUE(doc().cache_binding);
  EXPECT_TRUE(logged("the binding will be saved beside the project"));
  ws.run("undo");
  EXPECT_FALSE(doc().cache_binding);
  const size_t steps = undo_steps();
  ws.run("cache_binding off");  // already off: no step
  ws.run("cache_binding maybe");
  EXPECT_TRUE(logged("cache_binding on|off"));
  EXPECT_EQ(undo_steps(), steps);
}

// Live binding parameters (issue 24): a drag binds the skin with the panel's parameters as they move,
// in the background (a fresh bind each time: the result is what the parameters give), without an undo
// step; the release makes them the document's in one step, which undo takes back.
using WorkspaceLiveParamsTest = DemoWorkspaceTest;

TEST_F(WorkspaceLiveParamsTest, ADragBindsLiveAndIsOneUndoStep) {
  finish_bind();
  Scene& s = *ws.scene();
  ASSERT_TRUE(s.live_params_possible()) << s.skin_rest.size() << " points";
  const BindParams before = doc().params;
  const size_t steps = undo_steps();
  // three positions of the epsilon slider, each frame of the drag polled as the editor does
  std::vector<std::string> messages;
  auto poll = [&] {
    if (auto m = s.poll_bind()) messages.push_back(*m);
  };
  for (const char* eps : {"0.15", "0.2", "0.3"}) {
    ws.run(std::string("bind_param epsilon ") + eps);
    ws.run("bind_param_drag");
    EXPECT_TRUE(s.job) << "the drag binds at once";
    poll();
  }
  while (s.job) {  // the binds that ran with older positions are followed by one with the last
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    poll();
  }
  ASSERT_TRUE(s.binding);
  EXPECT_DOUBLE_EQ(s.binding->params.epsilon, 0.3) << "the skin follows the slider before the release";
  EXPECT_EQ(undo_steps(), steps) << "no undo step while dragging";
  EXPECT_DOUBLE_EQ(doc().params.epsilon, before.epsilon);
  // the live result is the bind the parameters give
  BindParams p = before;
  p.epsilon = 0.3;
  ws.run("bind_param_release");
  EXPECT_EQ(undo_steps(), steps + 1) << "one undo step per drag";
  EXPECT_DOUBLE_EQ(doc().params.epsilon, 0.3);
  EXPECT_FALSE(s.job) << "released on the bound parameters: nothing more to bind";
  EXPECT_EQ(s.binding->params, p);
  // the drag's binds re-weighted from a candidate cache made by its first: identical to a fresh bind
  EXPECT_TRUE(s.candidate_cache().last_from_cache);
  ASSERT_TRUE(s.candidate_cache().cache);
  ASSERT_GE(messages.size(), 2u);
  EXPECT_NE(messages.front().find("candidate cache made in"), std::string::npos) << messages.front();
  EXPECT_NE(messages.back().find("re-weighted from the candidate cache"), std::string::npos) << messages.back();
  auto fresh = bind_document(with_params(doc(), p), s.skin_rest, s.attachment ? &*s.attachment : nullptr);
  ASSERT_TRUE(fresh.ok());
  EXPECT_EQ(registration_difference(*s.binding, *fresh), "");
  ws.run("undo");
  EXPECT_DOUBLE_EQ(doc().params.epsilon, before.epsilon);
  finish_bind();
  EXPECT_EQ(s.binding->params, before) << "undo binds the old parameters again";
  EXPECT_TRUE(errors.empty()) << errors.front();
}

TEST_F(WorkspaceLiveParamsTest, AReleaseDuringABindBindsTheReleasedParameters) {
  finish_bind();
  Scene& s = *ws.scene();
  ws.run("bind_param max_elements 4");
  ws.run("bind_param_drag");
  ASSERT_TRUE(s.job);
  ws.run("bind_param max_elements 6");  // moved on while the first bind runs, released at once
  ws.run("bind_param_release");
  EXPECT_EQ(doc().params.max_elements, 6u);
  finish_bind();
  EXPECT_EQ(s.binding->params.max_elements, 6u) << "the bind that ran with 4 is followed by one with 6";
}

}  // namespace
}  // namespace cagewrap::app
