// The Rig window's edits driven in-process on the demo character (app/workspace/workspace_rig.cpp, issue
// 20): attachment modes and assignments, keypose sets, a key made from what was sculpted at a pose,
// undo and redo, deleting and mirroring, and the errors named. The window only draws these.
#include <algorithm>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tests/workspace_fixtures.h"

namespace cagewrap::app {
namespace {

class WorkspaceRigTest : public DemoWorkspaceTest {
 protected:
  void SetUp() override {
    DemoWorkspaceTest::SetUp();
    ws.run("clip rest");  // the bind pose: the drivers' angles are the posing's alone
    forearm_l = node("forearm.L");
    forearm_r = node("forearm.R");
    ASSERT_GE(forearm_l, 0);
    ASSERT_GE(forearm_r, 0);
  }
  std::vector<glm::vec3> posed_cage() {
    ws.update_pose();
    return ws.scene()->cage_posed;
  }
  static double max_distance(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
    double m = 0.0;
    for (size_t i = 0; i < a.size(); ++i) m = std::max(m, double(glm::length(a[i] - b[i])));
    return m;
  }
  int forearm_l = -1, forearm_r = -1;
};

TEST_F(WorkspaceRigTest, AKeyHoldsWhatWasSculptedAtThePoseAndUndoTakesItBack) {
  ASSERT_TRUE(doc().keyposes.empty());
  const std::vector<glm::vec3> rest_cage = posed_cage();
  ws.run("select_joint " + std::to_string(forearm_l));
  ASSERT_TRUE(ws.run("keyset x"));
  ASSERT_EQ(doc().keyposes.size(), 1u);
  EXPECT_EQ(doc().keyposes[0].name, "forearm.L_X");
  EXPECT_EQ(ws.view.keypose_set, 0u);

  // pose the forearm, sculpt a cage vertex at that pose, key it
  ws.run("pose " + std::to_string(forearm_l) + " 60 0 0");
  ws.run("mode cage_vertices");
  ws.run("select_cage_vertex 310");
  ws.run("move 0 0.02 0");
  const std::vector<glm::vec3> sculpted = posed_cage();
  ASSERT_GT(glm::length(doc().cage_offsets.at(310)), 0.01f);  // sculpted: a pose offset
  const size_t steps = ws.scene()->history().undo_steps();
  ASSERT_TRUE(ws.run("key"));
  ASSERT_EQ(ws.scene()->history().undo_steps(), steps + 1);  // one undo step
  ASSERT_EQ(doc().keyposes[0].keys.size(), 1u);
  EXPECT_NEAR(doc().keyposes[0].keys[0].values[0], 60.0, 0.05);
  for (const glm::vec3& o : doc().cage_offsets) EXPECT_EQ(o, glm::vec3(0.f));  // taken out of the offsets
  // ... into the key: at the pose the cage is where it was sculpted, at rest where it was
  EXPECT_LT(max_distance(posed_cage(), sculpted), 1e-5);
  ws.run("reset_pose");
  EXPECT_LT(max_distance(posed_cage(), rest_cage), 1e-5);

  ws.run("undo");  // the key
  EXPECT_TRUE(doc().keyposes[0].keys.empty());
  EXPECT_GT(glm::length(doc().cage_offsets.at(310)), 0.01f);  // the sculpt is back in the offsets
  ws.run("redo");
  ASSERT_EQ(doc().keyposes[0].keys.size(), 1u);
  ASSERT_TRUE(ws.run("remove_key 0"));
  EXPECT_TRUE(doc().keyposes[0].keys.empty());
  ws.run("remove_key 3");
  EXPECT_TRUE(logged("has no key 3"));
}

TEST_F(WorkspaceRigTest, MirrorAndActiveSetAndMissingThingsAreNamed) {
  ws.run("key");  // no set yet
  EXPECT_TRUE(logged("add a keypose set first"));
  ws.run("keyset x");  // no joint selected
  EXPECT_TRUE(logged("select the joint that drives the keypose"));
  ws.run("keyset w");
  EXPECT_TRUE(logged("keyset x|y|z"));
  EXPECT_TRUE(doc().keyposes.empty());

  ws.run("select_joint " + std::to_string(forearm_l));
  ws.run("keyset x");
  ws.run("pose " + std::to_string(forearm_l) + " 45 0 0");
  ws.run("select_cage_vertex 310");
  ws.run("move 0.01 0 0");
  ws.run("key");
  ASSERT_TRUE(ws.run("mirror_keyset"));
  ASSERT_EQ(doc().keyposes.size(), 2u);
  const auto mirrored = std::find_if(doc().keyposes.begin(), doc().keyposes.end(),
                                     [](const KeyposeSet& s) { return s.name == "forearm.R_X"; });
  ASSERT_NE(mirrored, doc().keyposes.end()) << doc().keyposes.front().name << " " << doc().keyposes.back().name;
  ASSERT_EQ(mirrored->drivers.size(), 1u);
  EXPECT_EQ(mirrored->drivers[0].node, static_cast<uint32_t>(forearm_r));
  ASSERT_EQ(mirrored->keys.size(), 1u);

  ASSERT_TRUE(ws.run("keyset_active forearm.R_X"));
  EXPECT_EQ(doc().keyposes[ws.view.keypose_set].name, "forearm.R_X");
  ws.run("keyset_active nothing");
  EXPECT_TRUE(logged("no keypose set 'nothing'"));
  EXPECT_EQ(doc().keyposes[ws.view.keypose_set].name, "forearm.R_X");

  // an edit of the set (the window's mute, values...) is checked before it is taken
  KeyposeSet bad = doc().keyposes[ws.view.keypose_set];
  bad.drivers[0].node = 9999;
  EXPECT_FALSE(ws.replace_keypose_set(bad, "Bad"));
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(doc().keyposes[ws.view.keypose_set].drivers[0].node, static_cast<uint32_t>(forearm_r));
  KeyposeSet muted = doc().keyposes[ws.view.keypose_set];
  muted.mute = true;
  EXPECT_TRUE(ws.replace_keypose_set(muted, "Mute"));
  EXPECT_TRUE(doc().keyposes[ws.view.keypose_set].mute);
}

TEST_F(WorkspaceRigTest, AttachmentModesAndAssignmentsAreUndoableAndCheckedFirst) {
  ASSERT_TRUE(ws.run("attach smooth 0.3"));
  EXPECT_EQ(doc().attachment.mode, AttachmentMode::kSmooth);
  EXPECT_DOUBLE_EQ(doc().attachment.smooth_width, 0.3);
  ws.run("attach smooth -1");
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_NE(errors[0].find("width must be above 0"), std::string::npos);
  EXPECT_DOUBLE_EQ(doc().attachment.smooth_width, 0.3);
  ws.run("attach sideways");
  EXPECT_TRUE(logged("attach rigid|smooth"));

  ws.run("attach joint");  // nothing selected
  EXPECT_TRUE(logged("select cage vertices first"));
  ws.run("select_cage_vertex 310");
  ws.run("attach joint");  // no joint
  EXPECT_TRUE(logged("select exactly one joint"));
  ws.run("select_joint " + std::to_string(forearm_r));
  ASSERT_TRUE(ws.run("attach joint"));
  ASSERT_EQ(doc().attachment.overrides.size(), 1u);
  EXPECT_EQ(doc().attachment.overrides[0].vertex, 310u);
  EXPECT_EQ(doc().attachment.overrides[0].node, static_cast<uint32_t>(forearm_r));
  ws.run("attach auto");
  EXPECT_TRUE(doc().attachment.overrides.empty());
  ws.run("undo");
  EXPECT_EQ(doc().attachment.overrides.size(), 1u);
  ws.run("undo");
  ws.run("undo");
  EXPECT_EQ(doc().attachment.mode, AttachmentMode::kFitted);  // the default, before `attach smooth`
}

}  // namespace
}  // namespace cagewrap::app
