// The editor without a window (app/workspace/workspace.h): selection, moves, undo and redo, and the
// action table that menus, shortcuts and scripts run, driven in-process.
#include "app/workspace/workspace.h"

#include <chrono>
#include <thread>

#include <gtest/gtest.h>

#include "tests/document_fixtures.h"

namespace cagewrap::app {
namespace {

class WorkspaceTest : public test::TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    test::write_tiny_character(path("tet.gltf"));
    test::write_box_cage(path("box.obj"), 3.0, 2);
    auto scene = load_scene(path("tet.gltf"), path("box.obj"));
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    ws.set_scene(std::move(scene).value());
    finish_bind();
  }
  // Waits for the background bind, as the editor's frame loop polls it.
  void finish_bind() {
    Scene& s = *ws.scene();
    for (int i = 0; i < 2000 && s.job; ++i) {
      s.poll_bind();
      if (s.job) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    ASSERT_FALSE(s.job) << "the bind did not finish";
    ASSERT_TRUE(s.deformer) << "no deformer after the bind";
    ws.update_pose();
  }
  size_t cage_vertices() const { return ws.scene()->doc().cage->num_vertices(); }
  std::vector<glm::vec3> posed() {
    ws.update_pose();
    return ws.scene()->cage_posed;
  }
  std::string last_log() const { return ws.log_lines().empty() ? "" : ws.log_lines().back().text; }
  Workspace ws;
};

TEST_F(WorkspaceTest, SelectionActionsActOnTheActiveMode) {
  ASSERT_TRUE(ws.run("mode cage_vertices"));
  ASSERT_TRUE(ws.run("select all"));
  EXPECT_EQ(ws.view.selection.cage_vertices.size(), cage_vertices());
  ASSERT_TRUE(ws.run("select invert"));
  EXPECT_TRUE(ws.view.selection.cage_vertices.empty());
  ws.run("select_cage_vertex 3");
  ws.run("select_cage_vertex 5 add");
  EXPECT_EQ(ws.view.selection.cage_vertices.size(), 2u);
  ws.run("select grow");
  EXPECT_GT(ws.view.selection.cage_vertices.size(), 2u);
  // faces are their own set: the vertex selection stays
  const size_t vertices = ws.view.selection.cage_vertices.size();
  ws.run("mode cage_faces");
  ws.run("select all");
  EXPECT_EQ(ws.view.selection.cage_faces.size(), ws.scene()->doc().cage->polygons.num_faces());
  EXPECT_EQ(ws.view.selection.cage_vertices.size(), vertices);
  EXPECT_EQ(ws.view.mode, SelectMode::kCageFaces);
}

TEST_F(WorkspaceTest, MirrorSelectionAddsTheCounterpartAcrossX) {
  const auto& p = ws.scene()->doc().cage->polygons.positions;
  uint32_t v = 0;
  while (v < p.size() && !(p[v].x > 0.1f)) ++v;
  ASSERT_LT(v, p.size());
  ws.run("select_cage_vertex " + std::to_string(v));
  ws.run("select mirror");
  ASSERT_EQ(ws.view.selection.cage_vertices.size(), 2u);
  for (uint32_t m : ws.view.selection.cage_vertices)
    if (m != v) {
      EXPECT_NEAR(p[m].x, -p[v].x, 1e-5);
      EXPECT_NEAR(p[m].y, p[v].y, 1e-5);
      EXPECT_NEAR(p[m].z, p[v].z, 1e-5);
    }
}

TEST_F(WorkspaceTest, ADragIsOneUndoStepAndUndoRestoresTheStartExactly) {
  const std::vector<glm::vec3> before = posed();
  const size_t steps = ws.scene()->history().undo_steps();
  ws.run("select_cage_vertex 0");
  ASSERT_TRUE(ws.begin_move());
  for (int k = 1; k <= 5; ++k) ws.update_move(glm::dvec3(0.0, 0.02 * k, 0.0));  // mouse events of one drag
  EXPECT_TRUE(ws.moving());
  ws.end_move();
  EXPECT_FALSE(ws.moving());
  EXPECT_EQ(ws.scene()->history().undo_steps(), steps + 1);
  std::vector<glm::vec3> after = posed();
  EXPECT_NEAR(after[0].y - before[0].y, 0.1, 1e-5);
  for (size_t v = 1; v < after.size(); ++v) EXPECT_EQ(after[v], before[v]) << "vertex " << v << " moved without being selected";
  ws.run("undo");
  EXPECT_EQ(posed(), before);
  EXPECT_EQ(ws.scene()->history().undo_steps(), steps);
  ws.run("redo");
  EXPECT_EQ(posed(), after);
}

TEST_F(WorkspaceTest, ACancelledDragLeavesNoStep) {
  const std::vector<glm::vec3> before = posed();
  const size_t steps = ws.scene()->history().undo_steps();
  ws.run("select_cage_vertex 1");
  ASSERT_TRUE(ws.begin_move());
  ws.update_move(glm::dvec3(0.3, 0.0, 0.0));
  ws.cancel_move();
  EXPECT_EQ(posed(), before);
  EXPECT_EQ(ws.scene()->history().undo_steps(), steps);
}

TEST_F(WorkspaceTest, SoftSelectionCarriesNeighboursPartWay) {
  const std::vector<glm::vec3> before = posed();
  ws.run("select_cage_vertex 0");
  ws.run("soft on 4.0 linear volume");  // the box's grid step is 3
  EXPECT_TRUE(ws.view.soft.enabled);
  EXPECT_EQ(ws.view.soft.radius, 4.0);
  ws.run("move 0 0.1 0");
  const std::vector<glm::vec3> after = posed();
  EXPECT_NEAR(after[0].y - before[0].y, 0.1, 1e-5);
  int partial = 0;
  for (size_t v = 1; v < after.size(); ++v) {
    const double dy = after[v].y - before[v].y;
    EXPECT_LE(dy, 0.1 + 1e-6);
    if (dy > 1e-6 && dy < 0.1 - 1e-6) ++partial;
  }
  EXPECT_GT(partial, 0) << "no neighbour followed part way";
}

TEST_F(WorkspaceTest, MovingTheRestCageChangesTheReferenceNotThePoseOffsets) {
  const glm::vec3 rest0 = ws.scene()->doc().cage->polygons.positions[2];
  ws.run("move_target rest");
  ws.run("select_cage_vertex 2");
  ws.run("move 0.05 0 0");
  EXPECT_NEAR(ws.scene()->doc().cage->polygons.positions[2].x - rest0.x, 0.05, 1e-6);
  EXPECT_EQ(ws.scene()->history().undo_label(), "Undo Move rest cage vertices");
  ws.run("undo");
  EXPECT_EQ(ws.scene()->doc().cage->polygons.positions[2], rest0);
}

TEST_F(WorkspaceTest, BindParametersAreCheckedAndRebindIsOneStep) {
  EXPECT_TRUE(ws.run("bind_param local -1", "script line 7"));
  EXPECT_NE(last_log().find("script line 7"), std::string::npos) << last_log();
  EXPECT_NE(last_log().find("not a non-negative number"), std::string::npos) << last_log();
  EXPECT_TRUE(ws.log_lines().back().error);
  ws.run("bind_param local 3");
  EXPECT_EQ(ws.scene()->params.local, 3.0);
  EXPECT_NE(ws.scene()->doc().params.local, 3.0) << "the panel's value is not the document's until Rebind";
  ws.run("rebind");
  EXPECT_EQ(ws.scene()->doc().params.local, 3.0);
  EXPECT_EQ(ws.scene()->history().undo_label(), "Undo Change binding parameters");
  finish_bind();
  ws.run("undo");
  EXPECT_NE(ws.scene()->doc().params.local, 3.0);
  EXPECT_NE(ws.scene()->params.local, 3.0) << "undo brings the panel back to the document";
}

TEST_F(WorkspaceTest, UnknownActionsAndMissingDocumentsAreNamed) {
  EXPECT_FALSE(ws.run("frobnicate 3", "script line 12"));
  EXPECT_NE(last_log().find("script line 12"), std::string::npos) << last_log();
  EXPECT_NE(last_log().find("'frobnicate'"), std::string::npos) << last_log();
  EXPECT_FALSE(ws.run("# a comment"));
  EXPECT_FALSE(ws.run("   "));
  ws.run("mode sideways");
  EXPECT_NE(last_log().find("unknown mode 'sideways'"), std::string::npos) << last_log();

  Workspace empty;
  EXPECT_FALSE(empty.run("select all", "script line 1"));
  EXPECT_NE(empty.log_lines().back().text.find("needs an open document"), std::string::npos);
  EXPECT_FALSE(empty.run("undo"));
}

TEST_F(WorkspaceTest, PosingIsViewStateAndNeverAnUndoStep) {
  const size_t steps = ws.scene()->history().undo_steps();
  ws.run("pose 0 0 45 0");
  ASSERT_FALSE(ws.view.playback.pose_override.empty());
  EXPECT_NEAR(glm::angle(ws.view.playback.pose_override[0]), glm::radians(45.0f), 1e-5);
  EXPECT_EQ(ws.scene()->history().undo_steps(), steps);
  ws.run("reset_pose");
  EXPECT_TRUE(ws.view.playback.pose_override.empty());
  ws.run("clip no_such_clip");
  EXPECT_NE(last_log().find("no clip 'no_such_clip'"), std::string::npos);
  EXPECT_TRUE(ws.run("clip rest"));
  EXPECT_EQ(ws.view.playback.clip, -1);
}

// The clip, its time and the joints posed on top are the workspace's view state (issue 20): the
// transport's actions set them, undo leaves them, update_pose poses the scene from them, and another
// document starts again on its own first clip.
TEST(WorkspacePlayback, ClipTimeAndPoseAreViewStateThatPosesTheScene) {
  Workspace ws;
  const std::string demo = std::string(CAGEWRAP_SOURCE_DIR) + "/assets/demo_character.glb";
  auto scene = load_scene(demo, std::string(CAGEWRAP_SOURCE_DIR) + "/assets/demo_cage.obj");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  ws.set_scene(std::move(scene).value());
  const auto& clips = ws.scene()->doc().character->clips;
  ASSERT_GE(clips.size(), 2u);
  const Playback& pb = ws.view.playback;
  EXPECT_EQ(pb.clip, 0);  // a new document shows its first clip, paused at 0
  EXPECT_FALSE(pb.player.playing());
  EXPECT_DOUBLE_EQ(pb.player.time(), 0.0);

  ASSERT_TRUE(ws.run("clip " + clips[1].name));
  EXPECT_EQ(pb.clip, 1);
  EXPECT_DOUBLE_EQ(pb.player.duration(), clips[1].duration);
  ws.update_pose();
  const std::vector<glm::mat4> at_start = ws.scene()->joint_globals;
  ASSERT_TRUE(ws.run("time " + std::to_string(clips[1].duration * 0.5)));
  EXPECT_NEAR(pb.player.time(), clips[1].duration * 0.5, 1e-6);
  ws.update_pose();
  double moved = 0.0;  // the skeleton follows the workspace's time
  for (size_t j = 0; j < at_start.size(); ++j) moved = std::max(moved, double(glm::length(glm::vec3(ws.scene()->joint_globals[j][3] - at_start[j][3]))));
  EXPECT_GT(moved, 1e-3);

  ASSERT_TRUE(ws.run("play"));
  EXPECT_TRUE(pb.player.playing());
  ASSERT_TRUE(ws.run("loop off"));
  EXPECT_FALSE(pb.player.looping());
  ws.run("loop sideways");  // named, and nothing changes
  EXPECT_TRUE(ws.log_lines().back().error);
  EXPECT_NE(ws.log_lines().back().text.find("loop on|off"), std::string::npos);
  EXPECT_FALSE(pb.player.looping());
  ASSERT_TRUE(ws.run("pause"));
  ws.run("pose 1 0 30 0");
  ASSERT_FALSE(pb.pose_override.empty());
  EXPECT_EQ(ws.current_pose().local.size(), ws.scene()->doc().character->skeleton.size());

  // undo leaves the view state alone
  ws.run("select all");
  ws.run("move 0 0.01 0");
  ws.run("undo");
  EXPECT_EQ(pb.clip, 1);
  EXPECT_NEAR(pb.player.time(), clips[1].duration * 0.5, 1e-6);
  EXPECT_FALSE(pb.pose_override.empty());

  // another document: its first clip, no posing
  auto other = load_scene(demo, "");
  ASSERT_TRUE(other.ok());
  ws.set_scene(std::move(other).value());
  EXPECT_EQ(pb.clip, 0);
  EXPECT_DOUBLE_EQ(pb.player.time(), 0.0);
  EXPECT_TRUE(pb.pose_override.empty());
}

TEST(ActionTable, EveryActionHasHelpAndTheReferenceListsItOnce) {
  Workspace ws;
  const auto actions = ws.actions.list();
  ASSERT_GE(actions.size(), 20u);
  const std::string ref = ws.actions.reference();
  for (const Action* a : actions) {
    EXPECT_FALSE(a->help.empty()) << a->name;
    const std::string row = "| `" + a->name + "` |";
    const size_t at = ref.find(row);
    EXPECT_NE(at, std::string::npos) << a->name;
    EXPECT_EQ(ref.find(row, at + 1), std::string::npos) << a->name << " listed twice";
  }
  // a later action of the same name replaces the first (the window overrides a headless default)
  int ran = 0;
  ws.actions.add({"undo", "", "replaced", true, 0, [&](std::istringstream&) { ++ran; }});
  EXPECT_EQ(ws.actions.list().size(), actions.size());
  EXPECT_TRUE(ws.actions.run("undo"));
  EXPECT_EQ(ran, 1);
}

}  // namespace
}  // namespace cagewrap::app
