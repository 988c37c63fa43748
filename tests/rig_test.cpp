// Tests for core/rig/rig.h, and the acceptance test of "the cage follows the skeleton; keypose cage
// vertices against joint angles" on the demo character (core/character/demo_character.h) and its cage
// (assets/demo_cage.obj): a biceps bulge keyed at 120 degrees of elbow flexion appears fully at
// 120, half at 60 with linear interpolation, not at all at rest, and follows the arm when the
// shoulder also moves; mirrored keys act on the other arm; removing a key restores the earlier
// shape. Measured on the posed cage and on the skin deformed through it (extended variant).
#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include "core/io/cage_import.h"
#include "core/character/demo_character.h"
#include "core/rig/rig.h"
#include "core/cage/cage_attachment.h"
#include "core/character/skinning.h"
#include "tests/rig_fixtures.h"

namespace cagewrap {
namespace {

using test::about_deg;

struct Demo {
  Document doc;  // no keyposes
  std::optional<Rig> rig;
  std::vector<uint32_t> biceps;     // cage vertices of the left upper arm's front, mid-bone
  std::vector<glm::vec3> bulge;     // #Vc offsets: 2 cm outwards on those vertices (bind space)
  KeyposeSet biceps_set;            // forearm.L rotation about X, key at 120 degrees, linear
};

Demo make_demo() {
  Demo d;
  d.doc = test::demo_document();
  // Keyposes alone: automatic separation (on by default) draws its part labels from the attachment
  // of this only nearly symmetric cage, which alone makes the mirrored bulge's total 0.77 of the
  // original's; the left/right comparisons below are about mirroring keys, so it is off here.
  d.doc.params.separate = false;
  // The cage follows the closest limb rigidly (not the default skin weights): the bulge tests below
  // check that keyed offsets turn exactly with the one joint their vertices follow, and the smooth
  // test compares against this rigid cage.
  d.doc.attachment.mode = AttachmentMode::kRigid;
  d.doc.revision = next_revision();
  auto rig = Rig::create(d.doc);
  EXPECT_TRUE(rig.ok()) << rig.error().message;
  d.rig.emplace(std::move(rig).value());

  test::BicepsKeypose b = test::demo_biceps_keypose(*d.doc.character, d.doc.cage_positions(), *d.rig->attachment());
  d.biceps = std::move(b.vertices);
  d.bulge = std::move(b.bulge);
  d.biceps_set = std::move(b.set);
  return d;
}

Demo& demo() {
  static Demo d = make_demo();
  return d;
}

// The rest pose with the elbows bent by the given degrees about their local X (the demo's bending
// axis) and the left upper arm raised by `raise` degrees about its local Z.
Pose arm_pose(double elbow_l, double elbow_r = 0, double raise = 0) {
  const Skeleton& sk = demo().doc.character->skeleton;
  Pose p = sk.rest_pose();
  test::rotate(sk, p, "forearm.L", about_deg(elbow_l, {1, 0, 0}));
  test::rotate(sk, p, "forearm.R", about_deg(elbow_r, {1, 0, 0}));
  test::rotate(sk, p, "upper_arm.L", about_deg(raise, {0, 0, 1}));
  test::rotate(sk, p, "shoulder.L", about_deg(raise / 4, {0, 0, 1}));
  return p;
}

struct Posed {
  PosedCage cage;
  std::vector<glm::vec3> skin;
};

Posed pose_doc(const Document& doc, const Pose& pose) {
  Posed out;
  out.skin.resize(demo().rig->num_skin_points());
  Status s = demo().rig->pose(doc, pose, out.cage, out.skin);
  EXPECT_TRUE(s.ok()) << s.error().message;
  return out;
}

Document with_sets(std::vector<KeyposeSet> sets) { return with_keyposes(demo().doc, std::move(sets)); }

// keyed - plain, per skin vertex
std::vector<glm::vec3> skin_bulge(const Document& keyed, const Pose& pose) {
  Posed a = pose_doc(keyed, pose), b = pose_doc(demo().doc, pose);
  std::vector<glm::vec3> d(a.skin.size());
  for (size_t i = 0; i < d.size(); ++i) d[i] = a.skin[i] - b.skin[i];
  return d;
}

float max_length(const std::vector<glm::vec3>& v) {
  float m = 0;
  for (const glm::vec3& x : v) m = std::max(m, glm::length(x));
  return m;
}

TEST(DemoKeypose, TheSelectionIsABicepsRegion) {
  EXPECT_GE(demo().biceps.size(), 5u);
  EXPECT_LE(demo().biceps.size(), 60u);
}

TEST(DemoKeypose, BulgeIsFullAt120HalfAt60AndAbsentAtRest) {
  Document keyed = with_sets({demo().biceps_set});
  // the posed cage: the keyed vertices move by the offset carried by their joint (the upper arm,
  // at rest here), scaled by the interpolation weight; nothing else moves
  for (double deg : {0.0, 30.0, 60.0, 120.0, 150.0}) {
    Posed k = pose_doc(keyed, arm_pose(deg)), p = pose_doc(demo().doc, arm_pose(deg));
    const double share = std::min(deg, 120.0) / 120.0;
    for (uint32_t v = 0; v < k.cage.positions.size(); ++v) {
      glm::vec3 want = glm::vec3(k.cage.linear[v] * glm::dvec3(demo().bulge[v])) * float(share);
      glm::vec3 got = k.cage.positions[v] - p.cage.positions[v];
      ASSERT_NEAR(glm::length(got - want), 0.0f, 2e-6f) << "cage vertex " << v << " at " << deg << " degrees";
    }
  }
  // the skin: a visible bulge at 120, exactly half of it at 60 (the extended variant is affine in
  // the posed cage), none at rest
  auto full = skin_bulge(keyed, arm_pose(120));
  auto half = skin_bulge(keyed, arm_pose(60));
  auto none = skin_bulge(keyed, arm_pose(0));
  EXPECT_GT(max_length(full), 0.01f);
  EXPECT_EQ(max_length(none), 0.0f);
  for (size_t i = 0; i < full.size(); ++i)
    ASSERT_NEAR(glm::length(half[i] - 0.5f * full[i]), 0.0f, 1e-5f) << i;
  // where it shows: on the left upper arm
  size_t top = 0;
  for (size_t i = 0; i < full.size(); ++i)
    if (glm::length(full[i]) > glm::length(full[top])) top = i;
  glm::vec3 p = demo().rig->skin_rest()[top];
  EXPECT_GT(p.x, 0.2f);
  EXPECT_LT(p.x, 0.45f);
  EXPECT_GT(p.y, 1.1f);
  EXPECT_LT(p.y, 1.45f);
  // and at rest the keyed document reproduces the character's rest skin
  Posed rest = pose_doc(keyed, demo().doc.character->skeleton.rest_pose());
  for (size_t i = 0; i < rest.skin.size(); ++i)
    ASSERT_NEAR(glm::length(rest.skin[i] - demo().rig->skin_rest()[i]), 0.0f, 2e-5f) << i;
}

TEST(DemoKeypose, BulgeFollowsTheArmWhenTheShoulderAlsoMoves) {
  Document keyed = with_sets({demo().biceps_set});
  const Pose raised = arm_pose(120, 0, 60);
  auto moved = skin_bulge(keyed, raised);
  auto still = skin_bulge(keyed, arm_pose(120));
  // the elbow reads 120 whatever the shoulder does, so the bulge is fully there, turned with the
  // upper arm: moved = R_upper_arm * still
  Posed k = pose_doc(keyed, raised);
  const uint32_t v0 = demo().biceps.front();
  const glm::mat3 r = glm::mat3(k.cage.linear[v0]);
  EXPECT_GT(glm::length(r * glm::vec3(1, 0, 0) - glm::vec3(1, 0, 0)), 0.5f);  // it did turn
  for (size_t i = 0; i < moved.size(); ++i)
    ASSERT_NEAR(glm::length(moved[i] - r * still[i]), 0.0f, 1e-5f) << i;
  EXPECT_NEAR(max_length(moved), max_length(still), 1e-5f);
  // and it sits on the raised arm: the most displaced skin point is near the posed upper arm
  const Skeleton& sk = demo().doc.character->skeleton;
  auto globals = sk.global_transforms(raised);
  glm::vec3 shoulder(globals[sk.find("upper_arm.L")][3]), elbow(globals[sk.find("forearm.L")][3]);
  size_t top = 0;
  for (size_t i = 0; i < moved.size(); ++i)
    if (glm::length(moved[i]) > glm::length(moved[top])) top = i;
  Posed plain = pose_doc(demo().doc, raised);
  glm::vec3 q = plain.skin[top];
  float t = glm::clamp(
      glm::dot(q - shoulder, elbow - shoulder) / glm::dot(elbow - shoulder, elbow - shoulder), 0.0f, 1.0f);
  EXPECT_LT(glm::length(q - (shoulder + t * (elbow - shoulder))), 0.08f);
}

TEST(DemoKeypose, MirroredKeysActOnTheOtherArm) {
  const KeyposeSet& left = demo().biceps_set;
  auto m = mirror_keypose_set(left, demo().doc.character->skeleton, demo().doc.cage_positions(), 0.05);
  ASSERT_TRUE(m.ok()) << m.error().message;
  const KeyposeSet& right = m->set;
  EXPECT_EQ(right.name, "biceps.R");
  EXPECT_EQ(right.drivers[0].node, static_cast<uint32_t>(demo().doc.character->skeleton.find("forearm.R")));
  EXPECT_EQ(right.drivers[0].axis, glm::vec3(1, 0, 0));
  EXPECT_EQ(right.keys[0].values, std::vector<double>{120});
  // the cage is only nearly symmetric: a keyed vertex may be nobody's nearest mirror image
  EXPECT_LT(m->unmatched.size(), demo().biceps.size() / 3)
      << m->unmatched.size() << " of " << demo().biceps.size();
  // the mirrored set alone: the right elbow at 120 bulges the right arm, the left stays put
  Document mirrored = with_sets({right});
  auto r = skin_bulge(mirrored, arm_pose(0, 120));
  auto l = skin_bulge(with_sets({left}), arm_pose(120, 0));
  const auto rest = demo().rig->skin_rest();
  auto summary = [&](const std::vector<glm::vec3>& d, float& total, glm::vec3& centre, float& other_side,
                     float side) {
    total = 0;
    other_side = 0;
    centre = glm::vec3(0.0f);
    for (size_t i = 0; i < d.size(); ++i) {
      float len = glm::length(d[i]);
      total += len;
      centre += len * rest[i];
      if (rest[i].x * side < 0) other_side = std::max(other_side, len);
    }
    centre /= total;
  };
  float total_l, total_r, other_l, other_r;
  glm::vec3 centre_l, centre_r;
  summary(l, total_l, centre_l, other_l, 1.0f);
  summary(r, total_r, centre_r, other_r, -1.0f);
  EXPECT_EQ(other_l, 0.0f);
  EXPECT_EQ(other_r, 0.0f);
  // the same bulge, mirrored (the cage and the skin are only nearly symmetric)
  EXPECT_NEAR(total_r / total_l, 1.0f, 0.2f);
  EXPECT_NEAR(max_length(r) / max_length(l), 1.0f, 0.2f);
  EXPECT_LT(glm::length(centre_r - glm::vec3(-centre_l.x, centre_l.y, centre_l.z)), 0.015f);
  // the left set does nothing for the right elbow, the mirrored one nothing for the left elbow
  EXPECT_EQ(max_length(skin_bulge(with_sets({left}), arm_pose(0, 120))), 0.0f);
  EXPECT_EQ(max_length(skin_bulge(mirrored, arm_pose(120, 0))), 0.0f);
  // both sets together: each arm its own bulge
  auto both = skin_bulge(with_sets({left, right}), arm_pose(120, 120));
  for (size_t i = 0; i < both.size(); ++i)
    ASSERT_NEAR(glm::length(both[i] - (l[i] + r[i])), 0.0f, 1e-5f) << i;
}

TEST(DemoKeypose, RemovingAKeyRestoresTheEarlierShape) {
  KeyposeSet set = demo().biceps_set;
  const Document before = with_sets({set});
  // a second key at 60: a flatter arm half way (offsets inwards)
  std::vector<glm::vec3> flat = demo().bulge;
  for (glm::vec3& o : flat) o *= -0.5f;
  set_key(set, make_key({60}, flat));
  const Document with_second = with_sets({set});
  const Pose at60 = arm_pose(60), at90 = arm_pose(90);
  EXPECT_GT(max_length(skin_bulge(with_second, at60)), 0.003f);
  auto shape_before = pose_doc(before, at60).skin;
  EXPECT_NE(pose_doc(with_second, at60).skin, shape_before);
  // removing the key gives back the earlier keyposes and the earlier shape, bit for bit
  ASSERT_TRUE(remove_key(set, std::vector<double>{60}));
  const Document after = with_sets({set});
  EXPECT_EQ(after.keyposes, before.keyposes);
  EXPECT_TRUE(same_content(after, before));
  EXPECT_EQ(pose_doc(after, at60).skin, shape_before);
  EXPECT_EQ(pose_doc(after, at90).skin, pose_doc(before, at90).skin);
  // removing the last key too: the plain character again
  ASSERT_TRUE(remove_key(set, std::vector<double>{120}));
  EXPECT_EQ(pose_doc(with_sets({set}), arm_pose(120)).skin, pose_doc(demo().doc, arm_pose(120)).skin);
}

TEST(DemoKeypose, SmoothAttachmentBendsTheCageAtTheElbow) {
  // the cage's edges across the left elbow stretch less with the smooth attachment than with the
  // rigid one, and both leave the rest pose alone
  Document smooth = demo().doc;
  smooth.attachment.mode = AttachmentMode::kSmooth;
  smooth.revision = next_revision();
  auto rig = Rig::create(smooth);
  ASSERT_TRUE(rig.ok()) << rig.error().message;
  EXPECT_FALSE(rig->fits(demo().doc));
  EXPECT_FALSE(demo().rig->fits(smooth));
  auto stretch = [&](Rig& r, const Document& doc, const Pose& pose) {
    PosedCage c;
    std::vector<glm::vec3> skin(r.num_skin_points());
    EXPECT_TRUE(r.pose(doc, pose, c, skin).ok());
    const auto rest = doc.cage_positions();
    const PolyMesh& m = doc.cage->polygons;
    float worst = 0;
    for (size_t f = 0; f < m.num_faces(); ++f) {
      auto face = m.face(f);
      for (size_t k = 0; k < face.size(); ++k) {
        uint32_t a = face[k], b = face[(k + 1) % face.size()];
        worst =
            std::max(worst, glm::length(c.positions[a] - c.positions[b]) / glm::length(rest[a] - rest[b]));
      }
    }
    return worst;
  };
  EXPECT_NEAR(stretch(*rig, smooth, demo().doc.character->skeleton.rest_pose()), 1.0f, 1e-5f);
  const float rigid_stretch = stretch(*demo().rig, demo().doc, arm_pose(120));
  const float smooth_stretch = stretch(*rig, smooth, arm_pose(120));
  EXPECT_LT(smooth_stretch, rigid_stretch);
  // the posed cage blends the two joints near the elbow
  PosedCage c;
  std::vector<glm::vec3> skin(rig->num_skin_points());
  ASSERT_TRUE(rig->pose(smooth, arm_pose(120), c, skin).ok());
  const CageAttachment& att = *rig->attachment();
  size_t blended = 0;
  for (size_t v = 0; v + 1 < att.influence_start.size(); ++v)
    blended += att.influence_start[v + 1] - att.influence_start[v] > 1;
  EXPECT_GT(blended, 10u);
  EXPECT_LT(blended, att.joint.size());
}

TEST(Rig, ComposePoseAppliesOverridesOnTopOfTheClip) {
  const Character& c = *demo().doc.character;
  std::vector<glm::quat> overrides(c.skeleton.size(), glm::quat(1, 0, 0, 0));
  const uint32_t fl = c.skeleton.find("forearm.L");
  overrides[fl] = rotation_xyz_degrees(90, 0, 0);
  Pose clip = compose_pose(c, c.find_clip("arm_raise"), 1.0, false);
  Pose both = compose_pose(c, c.find_clip("arm_raise"), 1.0, false, overrides);
  glm::quat want = glm::normalize(clip.local[fl].rotation * about_deg(90, {1, 0, 0}));
  EXPECT_NEAR(std::abs(glm::dot(both.local[fl].rotation, want)), 1.0f, 1e-6f);
  const uint32_t fr = c.skeleton.find("forearm.R");
  EXPECT_EQ(both.local[fr].rotation, clip.local[fr].rotation);
  // X first, then Y, then Z
  glm::quat xyz = rotation_xyz_degrees(10, 20, 30);
  glm::quat expect = about_deg(30, {0, 0, 1}) * about_deg(20, {0, 1, 0}) * about_deg(10, {1, 0, 0});
  EXPECT_NEAR(std::abs(glm::dot(xyz, expect)), 1.0f, 1e-6f);
}

TEST(Rig, CreateNamesWhatFailed) {
  Document no_cage = demo().doc;
  no_cage.cage = nullptr;
  auto r = Rig::create(no_cage);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, "the document has no cage to pose the skin with");
  Document bad = demo().doc;
  bad.attachment = assign_vertices({}, std::vector<uint32_t>{7},
                                   static_cast<uint32_t>(bad.character->skeleton.find("body")));
  r = Rig::create(bad);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message,
            "attachment: cage vertex 7 is assigned to node 'body', which is not a joint of skin 'rig'");
}

// Moving rest cage vertices of the demo (skin-weights attachment, automatic separation on) and
// rebinding through rebind_document gives what a full bind_document gives, bit for bit, having
// registered only part of the skin; with a scale of 0 it binds in full.
TEST(Rig, RestEditRegistersOnlyNearbyPointsAndEqualsAFullBind) {
  Document doc = test::demo_document();
  const Character& ch = *doc.character;
  const std::vector<glm::vec3> skin = skin_character(ch, ch.skeleton.rest_pose());
  auto attach = [&](const Document& d) {
    auto a = attach_cage(ch, d.cage_positions(), d.attachment);
    EXPECT_TRUE(a.ok()) << (a.ok() ? "" : a.error().message);
    return std::move(a).value();
  };
  CageAttachment before_att = attach(doc);
  ASSERT_TRUE(doc.params.separate);
  ASSERT_EQ(doc.params.scale, 0.0);
  // bound as the editor binds it (h from the mean edge length); the edit fixes the scale to that h
  auto previous = bind_document(doc, skin, &before_att);
  ASSERT_TRUE(previous.ok()) << previous.error().message;
  BindParams fixed = doc.params;
  fixed.scale = previous->h;
  doc = with_params(doc, fixed);

  // three neighbouring vertices of the belly move out by a few cm
  std::vector<glm::vec3> rest(doc.cage_positions().begin(), doc.cage_positions().end());
  const Tri moved = doc.cage->elements[doc.cage->num_elements() / 2];
  for (uint32_t v : moved) rest[v] += glm::vec3(0.02f, -0.01f, 0.03f);
  const Document edited = with_cage_positions(doc, rest);
  CageAttachment after_att = attach(edited);

  RestRebindReport report;
  auto incremental = rebind_document(edited, skin, &after_att, *previous, &before_att, {}, &report);
  ASSERT_TRUE(incremental.ok()) << incremental.error().message;
  auto full = bind_document(edited, skin, &after_att);
  ASSERT_TRUE(full.ok()) << full.error().message;
  EXPECT_GE(report.moved_vertices, 3u);
  EXPECT_GT(report.points, 0u);
  EXPECT_LT(report.points, skin.size() / 4) << "a local edit registers a small part of the skin";
  EXPECT_EQ(incremental->offsets, full->offsets);
  EXPECT_EQ(incremental->ids, full->ids);
  EXPECT_EQ(incremental->weights, full->weights);
  EXPECT_EQ(incremental->set_ids, full->set_ids);
  EXPECT_EQ(incremental->set_weights, full->set_weights);
  EXPECT_EQ(incremental->rigid_points, full->rigid_points);
  EXPECT_EQ(incremental->separated, full->separated);
  EXPECT_EQ(incremental->reach, full->reach);
  EXPECT_EQ(incremental->rest_cage, full->rest_cage);
  EXPECT_NE(incremental->weights, previous->weights) << "the edit changed the registration";

  // a scale of 0 now: h follows the mean edge length, so everything is registered again
  BindParams automatic = edited.params;
  automatic.scale = 0;
  auto whole = rebind_document(with_params(edited, automatic), skin, &after_att, *previous, &before_att, {}, &report);
  ASSERT_TRUE(whole.ok()) << whole.error().message;
  EXPECT_EQ(report.points, skin.size());
}

}  // namespace
}  // namespace cagewrap
