// The editor's layout logic without a window: the outliner's joint tree (app/workspace/joint_tree.h)
// and the panel sizes (app/workspace/panel_layout.h).
#include <gtest/gtest.h>

#include "app/workspace/joint_tree.h"
#include "app/workspace/panel_layout.h"

namespace cagewrap::app {
namespace {

// Nodes in a file order with children before their parents, an armature group between two joints,
// a camera and a mesh node.
Character scrambled_character() {
  std::vector<SkeletonNode> nodes(7);
  const char* names[] = {"hand", "camera", "forearm", "armature", "shoulder", "body_mesh", "finger"};
  const int32_t parents[] = {2, -1, 4, -1, 3, 3, 0};
  for (size_t i = 0; i < nodes.size(); ++i) {
    nodes[i].name = names[i];
    nodes[i].parent = parents[i];
  }
  Character ch;
  ch.skeleton = Skeleton::create(std::move(nodes), "test").value();
  Skin skin;
  skin.joints = {4, 2, 0, 6};  // shoulder, forearm, hand, finger
  skin.inverse_bind.assign(4, glm::mat4(1.0f));
  ch.skins.push_back(skin);
  Primitive p;
  p.node = 5;
  ch.primitives.push_back(p);
  return ch;
}

TEST(JointTree, JointsNestUnderTheirParentsWhateverTheFileOrder) {
  const Character ch = scrambled_character();
  const JointTree t = joint_tree(ch);
  EXPECT_EQ(t.joints, 4u);
  // shoulder's parent is the armature group, not a joint: it is the root
  ASSERT_EQ(t.roots, std::vector<uint32_t>{4});
  EXPECT_EQ(t.children[4], std::vector<uint32_t>{2});
  EXPECT_EQ(t.children[2], std::vector<uint32_t>{0});
  EXPECT_EQ(t.children[0], std::vector<uint32_t>{6});
  EXPECT_TRUE(t.children[6].empty());
  // the camera, the armature and the mesh node are apart, the mesh marked
  EXPECT_EQ(t.other_nodes, (std::vector<uint32_t>{1, 3, 5}));
  EXPECT_EQ(t.mesh_node[5], 1);
  EXPECT_EQ(t.mesh_node[1], 0);
}

TEST(JointTree, ACharacterWithoutSkinsHasNoJoints) {
  Character ch = scrambled_character();
  ch.skins.clear();
  const JointTree t = joint_tree(ch);
  EXPECT_EQ(t.joints, 0u);
  EXPECT_TRUE(t.roots.empty());
  EXPECT_EQ(t.other_nodes.size(), ch.skeleton.size());
}

TEST(PanelLayout, TheDefaultsLeaveTheViewWhatThePanelsDoNotTake) {
  const PanelLayout p;
  const ViewRect v = p.view(1920, 1080);
  EXPECT_EQ(v.x, p.left);
  EXPECT_EQ(v.y, PanelLayout::kMenuHeight);
  EXPECT_EQ(v.w, 1920 - p.left - p.right);
  EXPECT_EQ(v.h, 1080 - PanelLayout::kMenuHeight - p.bottom);
}

TEST(PanelLayout, PanelsGiveWayBeforeTheViewGetsTooSmall) {
  PanelLayout p;
  p.left = 900;
  p.right = 700;
  for (float w : {1280.0f, 1024.0f, 800.0f}) {
    const PanelLayout f = p.fitted(w, 720);
    const ViewRect v = f.view(w, 720);
    EXPECT_GE(v.w, PanelLayout::kMinView - 0.5f) << w;
    EXPECT_NEAR(f.left / f.right, 900.0 / 700.0, 1e-3) << "both sides give way alike";
    EXPECT_LE(v.x + v.w, w - f.right + 0.5f);
  }
  // a bottom row taller than the window leaves half the minimum view
  p.bottom = 5000;
  const PanelLayout f = p.fitted(1280, 720);
  EXPECT_GE(f.view(1280, 720).h, PanelLayout::kMinView * 0.5f - 0.5f);
  // sizes within bounds are kept as they are
  PanelLayout q;
  q.left = 300;
  q.right = 400;
  q.bottom = 200;
  const PanelLayout g = q.fitted(1920, 1080);
  EXPECT_EQ(g.left, 300);
  EXPECT_EQ(g.right, 400);
  EXPECT_EQ(g.bottom, 200);
}

}  // namespace
}  // namespace cagewrap::app
