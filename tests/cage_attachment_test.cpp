// Tests for core/cage/cage_attachment.h: rigid attachment to the closest limb, the smooth blend near
// joints (weights sum to 1, rigid far away, 1/2 on the bisector, continuous, hence a cage that bends
// instead of tearing), per-vertex overrides and their mirror, and the errors that name the vertex
// and the node.
#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include "core/cage/cage_attachment.h"
#include "core/io/gltf_loader.h"
#include "core/character/skinning.h"
#include "tests/rig_fixtures.h"

namespace cagewrap {
namespace {

using test::about_deg;

struct Influences {
  std::vector<std::pair<std::string, float>> list;  // node name, weight
  float weight_of(const std::string& name) const {
    for (const auto& [n, w] : list)
      if (n == name) return w;
    return 0.0f;
  }
};

Influences influences(const Character& c, const CageAttachment& att, size_t v) {
  Influences out;
  for (uint32_t i = att.influence_start[v]; i < att.influence_start[v + 1]; ++i)
    out.list.emplace_back(c.skeleton.node(c.skins[att.skin].joints[att.influence_joint[i]]).name,
                          att.influence_weight[i]);
  return out;
}

AttachmentSettings smooth(double width = 1.0) {
  AttachmentSettings s;
  s.mode = AttachmentMode::kSmooth;
  s.smooth_width = width;
  return s;
}

// The chain with "lower" bent 90 degrees about Z: posed positions of `points` and their linear parts.
std::vector<glm::vec3> posed(const Character& c, const CageAttachment& att, std::span<const glm::vec3> points,
                             std::vector<glm::dmat3>* linear = nullptr) {
  Pose pose = c.skeleton.rest_pose();
  test::rotate(c.skeleton, pose, "lower", about_deg(90, {0, 0, 1}));
  auto globals = c.skeleton.global_transforms(pose);
  std::vector<glm::mat4> skinning(c.skins[0].joints.size());
  joint_matrices(c.skins[0], globals, skinning);
  std::vector<glm::vec3> out(points.size());
  if (linear) linear->resize(points.size());
  pose_cage(att, skinning, points, out, linear ? std::span<glm::dmat3>(*linear) : std::span<glm::dmat3>());
  return out;
}

TEST(CageAttachment, RigidFollowsTheClosestLimb) {
  Character c = test::chain_character();
  std::vector<glm::vec3> pts = {{0.1f, 0.5f, 0}, {0.1f, 1.4f, 0}, {0.0f, 2.3f, 0.1f}, {0.3f, 0.99f, 0}};
  auto att = attach_to_closest_limb(c, pts);
  ASSERT_TRUE(att.ok()) << att.error().message;
  EXPECT_EQ(influences(c, *att, 0).list, (std::vector<std::pair<std::string, float>>{{"upper", 1.0f}}));
  EXPECT_EQ(influences(c, *att, 1).list, (std::vector<std::pair<std::string, float>>{{"lower", 1.0f}}));
  EXPECT_EQ(influences(c, *att, 2).list, (std::vector<std::pair<std::string, float>>{{"hand", 1.0f}}));
  EXPECT_EQ(influences(c, *att, 3).list, (std::vector<std::pair<std::string, float>>{{"upper", 1.0f}}));
  // the default (skin weights, fitted later) falls back to the closest limb where no skin point is near: this
  // character has no mesh at all
  auto same = attach_cage(c, pts, AttachmentSettings{});
  EXPECT_EQ(AttachmentSettings{}.mode, AttachmentMode::kFitted);  // skin weights, refitted once bound
  EXPECT_EQ(same->joint, att->joint);
  EXPECT_EQ(same->influence_joint, att->influence_joint);
}

TEST(CageAttachment, SmoothWeightsSumToOneAreHalfOnTheBisectorAndRigidFarAway) {
  Character c = test::chain_character();
  std::vector<glm::vec3> pts = {
      {0.2f, 1.0f, 0},    // beside the elbow: equidistant from both limbs
      {0.1f, 0.5f, 0},    // mid upper arm, close to the bone: rigid (the lower limb is 5x farther)
      {0.2f, 0.9f, 0},    // just above the elbow: mostly upper
      {0.2f, 1.1f, 0},    // just below: mostly lower, mirror image of the previous one
      {-0.3f, 0.2f, 0.1f}, {0.05f, 1.9f, 0.3f}, {0.0f, 1.0f, 0.0f}};  // and a point on the joint itself
  auto att = attach_cage(c, pts, smooth());
  ASSERT_TRUE(att.ok());
  for (size_t v = 0; v < pts.size(); ++v) {
    Influences in = influences(c, *att, v);
    float sum = 0;
    for (const auto& [n, w] : in.list) {
      sum += w;
      EXPECT_GT(w, 0.0f);
    }
    EXPECT_NEAR(sum, 1.0f, 1e-6f) << v;
    EXPECT_LE(in.list.size(), kMaxAttachmentInfluences);
    for (size_t i = 1; i < in.list.size(); ++i)
      EXPECT_GE(in.list[i - 1].second, in.list[i].second);  // heaviest first
  }
  EXPECT_NEAR(influences(c, *att, 0).weight_of("upper"), 0.5f, 1e-6f);
  EXPECT_NEAR(influences(c, *att, 0).weight_of("lower"), 0.5f, 1e-6f);
  EXPECT_EQ(influences(c, *att, 1).list.size(), 1u);
  EXPECT_GT(influences(c, *att, 2).weight_of("upper"), 0.5f);
  EXPECT_LT(influences(c, *att, 2).weight_of("upper"), 1.0f);
  EXPECT_NEAR(influences(c, *att, 2).weight_of("upper"), influences(c, *att, 3).weight_of("lower"), 1e-6f);
  EXPECT_NEAR(influences(c, *att, 6).weight_of("upper"), 0.5f, 1e-6f);
  // the falloff: rigid exactly where the second limb is (1 + width) times farther (width 1 here)
  // at (0.2, 1 - s): d_upper = 0.2, d_lower = sqrt(0.04 + s^2); 0.4 = 2 * 0.2 at s = sqrt(0.12)
  const float s = std::sqrt(0.12f);
  auto edge =
      attach_cage(c, std::vector<glm::vec3>{{0.2f, 1 - s - 1e-3f, 0}, {0.2f, 1 - s + 1e-3f, 0}}, smooth());
  EXPECT_EQ(influences(c, *edge, 0).list.size(), 1u);
  EXPECT_EQ(influences(c, *edge, 1).list.size(), 2u);
  // a narrower width gives a narrower zone
  auto narrow = attach_cage(c, std::vector<glm::vec3>{{0.2f, 0.9f, 0}}, smooth(0.05));
  EXPECT_EQ(influences(c, *narrow, 0).list.size(), 1u);
}

TEST(CageAttachment, SmoothIsContinuousWhereRigidTears) {
  Character c = test::chain_character();
  // a line of points beside the chain, through the elbow and the wrist, 1e-4 apart
  std::vector<glm::vec3> line;
  const float step = 1e-4f;
  for (float y = 0.05f; y <= 2.4f; y += step) line.push_back({0.2f, y, 0.05f});
  auto rigid = attach_cage(c, line, AttachmentSettings{});
  auto soft = attach_cage(c, line, smooth());
  ASSERT_TRUE(rigid.ok() && soft.ok());
  auto jump = [&](const std::vector<glm::vec3>& p) {
    float worst = 0;
    for (size_t i = 1; i < p.size(); ++i) worst = std::max(worst, glm::length(p[i] - p[i - 1]));
    return worst;
  };
  std::vector<glm::dmat3> linear;
  auto soft_posed = posed(c, *soft, line, &linear);
  auto rigid_posed = posed(c, *rigid, line);
  EXPECT_GT(jump(rigid_posed), 0.1f);          // the rigid cage tears at the bent elbow
  EXPECT_LT(jump(soft_posed), 40 * step);       // the smooth one bends (Lipschitz, no jump)
  // and the weights themselves change gradually
  float worst = 0;
  for (size_t i = 1; i < line.size(); ++i)
    for (const char* n : {"upper", "lower", "hand"})
      worst = std::max(
          worst, std::abs(influences(c, *soft, i).weight_of(n) - influences(c, *soft, i - 1).weight_of(n)));
  EXPECT_LT(worst, 0.01f);
  // the linear part is the blend of the joints' 3x3s: at the bisector, half of identity and half
  // of the 90 degree turn
  size_t at_elbow = static_cast<size_t>((1.0f - 0.05f) / step);
  Influences in = influences(c, *soft, at_elbow);
  glm::dmat3 r90 = glm::dmat3(glm::mat3_cast(about_deg(90, {0, 0, 1})));
  glm::dmat3 expect = double(in.weight_of("upper")) * glm::dmat3(1.0) + double(in.weight_of("lower")) * r90;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(linear[at_elbow][i][k], expect[i][k], 1e-5);
}

TEST(CageAttachment, OverridesPinVerticesToAJointInEitherMode) {
  Character c = test::chain_character();
  std::vector<glm::vec3> pts = {{0.1f, 0.5f, 0}, {0.2f, 1.0f, 0}, {0.1f, 1.5f, 0}};
  const uint32_t hand = static_cast<uint32_t>(c.skeleton.find("hand"));
  AttachmentSettings s = assign_vertices(smooth(), std::vector<uint32_t>{1, 0, 1}, hand);
  EXPECT_EQ(s.overrides, (std::vector<AttachmentOverride>{{0, hand}, {1, hand}}));
  EXPECT_EQ(assigned_node(s, 1), hand);
  EXPECT_EQ(assigned_node(s, 2), std::nullopt);
  auto att = attach_cage(c, pts, s);
  ASSERT_TRUE(att.ok());
  EXPECT_EQ(influences(c, *att, 0).list, (std::vector<std::pair<std::string, float>>{{"hand", 1.0f}}));
  EXPECT_EQ(influences(c, *att, 1).list, (std::vector<std::pair<std::string, float>>{{"hand", 1.0f}}));
  EXPECT_EQ(influences(c, *att, 2).list, (std::vector<std::pair<std::string, float>>{{"lower", 1.0f}}));
  // back to automatic
  AttachmentSettings back = assign_vertices(s, std::vector<uint32_t>{1}, std::nullopt);
  EXPECT_EQ(back.overrides, (std::vector<AttachmentOverride>{{0, hand}}));
  att = attach_cage(c, pts, back);
  EXPECT_NEAR(influences(c, *att, 1).weight_of("upper"), 0.5f, 1e-6f);
  // per-vertex form
  std::vector<int32_t> per_vertex = overrides_per_vertex(s, 3);
  EXPECT_EQ(per_vertex, (std::vector<int32_t>{int32_t(hand), int32_t(hand), -1}));
  EXPECT_EQ(with_overrides_per_vertex(AttachmentSettings{}, per_vertex).overrides, s.overrides);
  // reassigning keeps one entry per vertex, sorted
  AttachmentSettings again = assign_vertices(s, std::vector<uint32_t>{2, 0}, 1u);
  EXPECT_EQ(again.overrides, (std::vector<AttachmentOverride>{{0, 1}, {1, hand}, {2, 1}}));
}

TEST(CageAttachment, BadOverridesNameTheVertexAndTheNode) {
  Character c = test::chain_character();
  std::vector<glm::vec3> pts = {{0.1f, 0.5f, 0}};
  auto not_joint = attach_cage(c, pts, assign_vertices({}, std::vector<uint32_t>{0}, 3u));
  ASSERT_FALSE(not_joint.ok());
  EXPECT_EQ(not_joint.error().message,
            "cage vertex 0 is assigned to node 'mesh', which is not a joint of skin 'rig'");
  auto out_of_range = attach_cage(c, pts, assign_vertices({}, std::vector<uint32_t>{4}, 0u));
  ASSERT_FALSE(out_of_range.ok());
  EXPECT_EQ(out_of_range.error().code, ErrorCode::kIndexOutOfRange);
  EXPECT_EQ(out_of_range.error().message,
            "the attachment assigns cage vertex 4, but the cage has 1 vertices");
  Character bare;
  bare.source = "bare.glb";
  EXPECT_EQ(attach_cage(bare, pts, {}).error().message,
            "bare.glb: has no skin (no skeleton to attach the cage to)");
}

TEST(CageAttachment, MirroredAssignmentUsesTheOtherSidesJoint) {
  Character c = test::symmetric_character(true);
  const Skeleton& sk = c.skeleton;
  const uint32_t hand_l = sk.find("hand.L"), hand_r = sk.find("hand.R"), arm_l = sk.find("arm.L"),
                 spine = sk.find("spine"), tail = sk.find("tail.L");
  // pairs 0 <-> 1, 2 <-> 3, 4 on the plane, 5 without a counterpart
  std::vector<glm::vec3> cage = {{0.8f, 0.1f, 0}, {-0.8f, 0.1f, 0}, {1.2f, 0.0f, 0.1f},
                                 {-1.2f, 0.0f, 0.1f}, {0.0f, 0.4f, 0}, {0.6f, -0.5f, 0}};
  AttachmentSettings s = assign_vertices({}, std::vector<uint32_t>{0}, hand_l);
  s = assign_vertices(s, std::vector<uint32_t>{4}, spine);
  s = assign_vertices(s, std::vector<uint32_t>{3}, arm_l);  // will be reset: vertex 2 is automatic
  auto m = mirror_assignment(s, sk, cage, std::vector<uint32_t>{0, 2, 4, 5}, 1e-4);
  ASSERT_TRUE(m.ok()) << m.error().message;
  EXPECT_EQ(m->unmatched, std::vector<uint32_t>{5});
  EXPECT_EQ(assigned_node(m->settings, 1), hand_r);
  EXPECT_EQ(assigned_node(m->settings, 0), hand_l);
  EXPECT_EQ(assigned_node(m->settings, 3), std::nullopt);
  EXPECT_EQ(assigned_node(m->settings, 4), spine);
  // and the attachment follows: vertex 1 on the right hand
  auto att = attach_cage(c, cage, m->settings);
  ASSERT_TRUE(att.ok());
  EXPECT_EQ(influences(c, *att, 1).list, (std::vector<std::pair<std::string, float>>{{"hand.R", 1.0f}}));
  // a joint with no counterpart by name: an error, nothing changed
  AttachmentSettings t = assign_vertices({}, std::vector<uint32_t>{0}, tail);
  auto bad = mirror_assignment(t, sk, cage, std::vector<uint32_t>{0}, 1e-4);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().message,
            "cage vertex 0 follows node 'tail.L', which has no mirror: no node is named 'tail.R'");
}


// The skin-weights attachment on the demo character: a cage vertex on the skin takes the weights of
// the skin around it: only the forearm where the skin follows only the forearm, both thighs and
// the hips where the crotch's skin blends them; weights sum to 1, at most 4, heaviest first.
TEST(CageAttachment, SkinWeightsAreTheCharactersOwnAroundTheVertex) {
  auto loaded = load_character(std::string(CAGEWRAP_SOURCE_DIR) + "/assets/demo_character.glb");
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  const Character& c = *loaded;
  const std::vector<glm::vec3> skin = skin_character(c, c.skeleton.rest_pose());
  const PointJoints pj = point_joint_nodes(c);
  ASSERT_EQ(pj.start.size(), skin.size() + 1);
  auto weight_on = [&](size_t p, const std::string& name) {
    float w = 0;
    for (uint32_t i = pj.start[p]; i < pj.start[p + 1]; ++i)
      if (c.skeleton.node(pj.node[i]).name == name) w += pj.weight[i];
    return w;
  };
  // a point whose whole weight is the forearm's and whose neighbourhood is too, and the crotch
  // point that blends the most of both thighs
  size_t forearm = SIZE_MAX, crotch = SIZE_MAX;
  float best_blend = 0;
  for (size_t p = 0; p < skin.size(); ++p) {
    if (forearm == SIZE_MAX && weight_on(p, "forearm.L") == 1.f && skin[p].y > 1.0f) {
      bool all = true;  // every point within 3 cm is forearm only
      for (size_t q = 0; q < skin.size() && all; ++q)
        if (glm::length(skin[q] - skin[p]) < 0.03f) all = weight_on(q, "forearm.L") == 1.f;
      if (all) forearm = p;
    }
    const float blend = std::min(weight_on(p, "thigh.L"), weight_on(p, "thigh.R"));
    if (blend > best_blend) {
      best_blend = blend;
      crotch = p;
    }
  }
  ASSERT_NE(forearm, SIZE_MAX);
  ASSERT_NE(crotch, SIZE_MAX);
  ASSERT_GT(best_blend, 0.1f);
  const std::vector<glm::vec3> pts = {skin[forearm], skin[crotch], {0.f, 10.f, 0.f}};
  auto att = attach_cage(c, pts, AttachmentSettings{});
  ASSERT_TRUE(att.ok()) << att.error().message;
  for (size_t v = 0; v < pts.size(); ++v) {
    const Influences in = influences(c, *att, v);
    ASSERT_LE(in.list.size(), kMaxAttachmentInfluences);
    float sum = 0;
    for (size_t i = 0; i < in.list.size(); ++i) {
      EXPECT_GT(in.list[i].second, 0.f);
      if (i > 0) {
        EXPECT_GE(in.list[i - 1].second, in.list[i].second) << "heaviest first";
      }
      sum += in.list[i].second;
    }
    EXPECT_NEAR(sum, 1.f, 1e-6f);
  }
  EXPECT_EQ(influences(c, *att, 0).list, (std::vector<std::pair<std::string, float>>{{"forearm.L", 1.0f}}));
  const Influences at_crotch = influences(c, *att, 1);
  EXPECT_GT(at_crotch.weight_of("thigh.L"), 0.05f);
  EXPECT_GT(at_crotch.weight_of("thigh.R"), 0.05f);
  EXPECT_NEAR(at_crotch.weight_of("thigh.L") + at_crotch.weight_of("thigh.R") + at_crotch.weight_of("hips"), 1.f,
              0.05f);
  // far above the head the nearest skin points are the head's: that is where it goes
  EXPECT_EQ(influences(c, *att, 2).list.front().first, "head");
}

}  // namespace
}  // namespace cagewrap
