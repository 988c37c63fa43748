// Tests for core/cage/keyposes.h and core/character/mirror_names.h: driver readings, one-driver interpolation
// (linear and monotone cubic exactness, clamping, the implicit rest key and its removal), pose-space
// RBF sets (every key reproduced, zero at rest), mute/solo, editing helpers, validation messages,
// and mirroring to the other side (checked against a geometrically mirrored pose).
#include <gtest/gtest.h>

#include <random>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include "core/cage/keyposes.h"
#include "core/character/mirror_names.h"
#include "tests/rig_fixtures.h"

namespace cagewrap {
namespace {

using test::about_deg;

// One node with a non-trivial rest rotation; `q` applied on top of it.
struct OneJoint {
  Skeleton skeleton;
  OneJoint() {
    SkeletonNode n;
    n.name = "elbow";
    n.rest.rotation = glm::normalize(glm::quat(0.9f, 0.3f, -0.2f, 0.1f));
    n.rest.translation = {0.1f, 0.2f, 0.3f};
    skeleton = Skeleton::create({n}, "one joint").value();
  }
  Pose pose(const glm::quat& q) const {
    Pose p = skeleton.rest_pose();
    p.local[0].rotation = glm::normalize(skeleton.node(0).rest.rotation * q);
    return p;
  }
};

KeyposeSet one_driver_set(DriverKind kind = DriverKind::kRotation, glm::vec3 axis = {1, 0, 0}) {
  KeyposeSet s;
  s.name = "bulge";
  s.drivers = {JointDriver{0, kind, axis}};
  return s;
}

// A key moving cage vertex `v` by `offset` (sparse).
KeyposeKey key_at(std::vector<double> values, uint32_t v, glm::vec3 offset) {
  return KeyposeKey{std::move(values), {v}, {offset}};
}

std::vector<glm::vec3> evaluate(const std::vector<KeyposeSet>& sets, const Skeleton& sk, const Pose& pose,
                                size_t nv = 4) {
  std::vector<glm::vec3> out(nv, glm::vec3(99.0f));  // overwritten
  evaluate_keyposes(sets, sk, pose, out);
  return out;
}

void expect_near(glm::vec3 a, glm::vec3 b, float tol, const std::string& what = {}) {
  EXPECT_NEAR(a.x, b.x, tol) << what;
  EXPECT_NEAR(a.y, b.y, tol) << what;
  EXPECT_NEAR(a.z, b.z, tol) << what;
}

TEST(Drivers, ReadRotationTwistAndSwingInDegrees) {
  OneJoint j;
  Pose rest = j.skeleton.rest_pose();
  for (DriverKind k : {DriverKind::kRotation, DriverKind::kTwist, DriverKind::kSwing})
    EXPECT_NEAR(driver_value({0, k, {1, 0, 0}}, j.skeleton, rest), 0.0, 1e-4) << driver_kind_name(k);
  Pose bent = j.pose(about_deg(70, {1, 0, 0}));
  EXPECT_NEAR(driver_value({0, DriverKind::kRotation, {1, 0, 0}}, j.skeleton, bent), 70.0, 1e-3);
  EXPECT_NEAR(driver_value({0, DriverKind::kRotation, {2, 0, 0}}, j.skeleton, bent), 70.0,
              1e-3);  // axis normalized
  EXPECT_NEAR(driver_value({0, DriverKind::kRotation, {-1, 0, 0}}, j.skeleton, bent), -70.0, 1e-3);
  EXPECT_NEAR(driver_value({0, DriverKind::kRotation, {0, 1, 0}}, j.skeleton, bent), 0.0, 1e-3);
  EXPECT_NEAR(driver_value({0, DriverKind::kTwist, {1, 0, 0}}, j.skeleton, bent), 70.0, 1e-3);
  EXPECT_NEAR(driver_value({0, DriverKind::kSwing, {1, 0, 0}}, j.skeleton, bent), 0.0, 1e-3);
  EXPECT_NEAR(driver_value({0, DriverKind::kSwing, {0, 1, 0}}, j.skeleton, bent), 70.0, 1e-3);
  // q = swing (30 about z) * twist (50 about y)
  Pose both = j.pose(about_deg(30, {0, 0, 1}) * about_deg(50, {0, 1, 0}));
  EXPECT_NEAR(driver_value({0, DriverKind::kTwist, {0, 1, 0}}, j.skeleton, both), 50.0, 1e-3);
  EXPECT_NEAR(driver_value({0, DriverKind::kSwing, {0, 1, 0}}, j.skeleton, both), 30.0, 1e-3);
  // the rotation kinds about X, Y, Z are the rotation vector's coordinates
  glm::dquat q(about_deg(30, {0, 0, 1}) * about_deg(50, {0, 1, 0}));
  double angle = 2 * std::acos(q.w) * 180 / std::numbers::pi;
  glm::dvec3 axis = glm::normalize(glm::dvec3(q.x, q.y, q.z));
  for (int c = 0; c < 3; ++c) {
    glm::vec3 a(0.0f);
    a[c] = 1;
    EXPECT_NEAR(driver_value({0, DriverKind::kRotation, a}, j.skeleton, both), angle * axis[c], 1e-3) << c;
  }
  for (DriverKind k : {DriverKind::kRotation, DriverKind::kTwist, DriverKind::kSwing}) {
    DriverKind back;
    ASSERT_TRUE(parse_driver_kind(driver_kind_name(k), back));
    EXPECT_EQ(back, k);
  }
}

// pose_at_driver_values inverts driver_values: exactly for one driver per node or rotation
// drivers about orthogonal axes (a shoulder read as X, Y, Z), on a joint with a turned rest frame.
TEST(Drivers, PoseAtDriverValuesReadsThemBack) {
  OneJoint j;
  auto set_of = [](std::vector<JointDriver> drivers) {
    KeyposeSet s;
    s.name = "s";
    s.drivers = std::move(drivers);
    return s;
  };
  auto reads = [&](const KeyposeSet& s, std::vector<double> values) {
    Pose p = pose_at_driver_values(s, values, j.skeleton, j.skeleton.rest_pose());
    auto x = driver_values(s, j.skeleton, p);
    ASSERT_EQ(x.size(), values.size());
    for (size_t i = 0; i < x.size(); ++i) EXPECT_NEAR(x[i], values[i], 1e-3) << "driver " << i;
  };
  const glm::vec3 oblique = glm::normalize(glm::vec3(1, 2, -0.5f));
  reads(set_of({{0, DriverKind::kRotation, oblique}}), {73});
  reads(set_of({{0, DriverKind::kRotation, {2, 0, 0}}}), {-140});  // the axis need not be unit
  reads(set_of({{0, DriverKind::kTwist, oblique}}), {-65});
  reads(set_of({{0, DriverKind::kSwing, oblique}}), {110});
  reads(set_of({{0, DriverKind::kRotation, {1, 0, 0}}, {0, DriverKind::kRotation, {0, 1, 0}},
                {0, DriverKind::kRotation, {0, 0, 1}}}),
        {30, -20, 45});
  // a driver naming no node is skipped, the others still act
  KeyposeSet bad = set_of({{7, DriverKind::kRotation, {1, 0, 0}}, {0, DriverKind::kTwist, {0, 1, 0}}});
  Pose p = pose_at_driver_values(bad, std::vector<double>{10, 25}, j.skeleton, j.skeleton.rest_pose());
  EXPECT_NEAR(driver_value(bad.drivers[1], j.skeleton, p), 25, 1e-3);
  // at zero: the rest pose
  Pose z = pose_at_driver_values(set_of({{0, DriverKind::kSwing, oblique}}), std::vector<double>{0}, j.skeleton,
                                 j.skeleton.rest_pose());
  EXPECT_NEAR(std::abs(glm::dot(z.local[0].rotation, j.skeleton.node(0).rest.rotation)), 1.0f, 1e-6f);
}

TEST(Keyposes, LinearKeyIsFullAtItsAngleHalfWayHalfAndZeroAtRest) {
  OneJoint j;
  KeyposeSet s = one_driver_set();
  set_key(s, key_at({120}, 2, {0, 1, 0}));
  std::vector<KeyposeSet> sets = {s};
  auto at = [&](double deg) { return evaluate(sets, j.skeleton, j.pose(about_deg(deg, {1, 0, 0}))); };
  expect_near(at(120)[2], {0, 1, 0}, 1e-5f);
  expect_near(at(60)[2], {0, 0.5f, 0}, 1e-5f);
  expect_near(at(90)[2], {0, 0.75f, 0}, 1e-5f);
  expect_near(at(0)[2], {0, 0, 0}, 1e-6f);
  // clamped outside the keyed range [0, 120]
  expect_near(at(160)[2], {0, 1, 0}, 1e-5f);
  expect_near(at(-40)[2], {0, 0, 0}, 1e-6f);
  // other vertices untouched, and the output is overwritten, not accumulated
  for (uint32_t v : {0u, 1u, 3u}) expect_near(at(120)[v], {0, 0, 0}, 0.0f);
}

TEST(Keyposes, RemovingTheRestKeyHoldsTheNearestKey) {
  OneJoint j;
  KeyposeSet s = one_driver_set();
  set_key(s, key_at({120}, 2, {0, 1, 0}));
  s.rest_key = false;
  auto at = [&](const KeyposeSet& set, double deg) {
    return evaluate({set}, j.skeleton, j.pose(about_deg(deg, {1, 0, 0})))[2];
  };
  // a single key: constant everywhere
  expect_near(at(s, 0), {0, 1, 0}, 1e-6f);
  expect_near(at(s, 60), {0, 1, 0}, 1e-6f);
  // two keys without rest: interpolated between, clamped to each end; zero at rest no more
  set_key(s, key_at({60}, 2, {1, 0, 0}));
  expect_near(at(s, 90), {0.5f, 0.5f, 0}, 1e-5f);
  expect_near(at(s, 0), {1, 0, 0}, 1e-6f);
  // an explicit key at rest replaces the implicit one
  KeyposeSet r = one_driver_set();
  set_key(r, key_at({120}, 2, {0, 1, 0}));
  set_key(r, key_at({0}, 2, {0, 0, 2}));
  expect_near(at(r, 0), {0, 0, 2}, 1e-6f);
  expect_near(at(r, 60), {0, 0.5f, 1}, 1e-5f);
  expect_near(at(r, -90), {0, 0, 2}, 1e-6f);
}

TEST(Keyposes, NegativeAndSeveralKeys) {
  OneJoint j;
  KeyposeSet s = one_driver_set(DriverKind::kTwist, {0, 0, 1});
  set_key(s, key_at({90}, 1, {0, 0, 1}));
  set_key(s, key_at({-60}, 1, {0, 0, -3}));
  ASSERT_EQ(s.keys.size(), 2u);
  EXPECT_EQ(s.keys[0].values[0], -60);  // kept sorted
  auto at = [&](double deg) { return evaluate({s}, j.skeleton, j.pose(about_deg(deg, {0, 0, 1})))[1].z; };
  EXPECT_NEAR(at(-30), -1.5f, 1e-5);
  EXPECT_NEAR(at(45), 0.5f, 1e-5);
  EXPECT_NEAR(at(-170), -3.0f, 1e-5);
}

TEST(Keyposes, SmoothKeysAreExactMonotoneAndEaseAtTheEnds) {
  OneJoint j;
  KeyposeSet s = one_driver_set();
  s.interpolation = KeyInterpolation::kSmooth;
  set_key(s, key_at({40}, 0, {0, 0.1f, 0}));
  set_key(s, key_at({120}, 0, {0, 1, -1}));
  set_key(s, KeyposeKey{{80}, {0, 3}, {{0, 0.2f, 0}, {5, 0, 0}}});  // vertex 3 only here
  auto at = [&](double deg) { return evaluate({s}, j.skeleton, j.pose(about_deg(deg, {1, 0, 0}))); };
  expect_near(at(40)[0], {0, 0.1f, 0}, 1e-4f);
  expect_near(at(80)[0], {0, 0.2f, 0}, 1e-4f);
  expect_near(at(120)[0], {0, 1, -1}, 1e-4f);
  expect_near(at(80)[3], {5, 0, 0}, 1e-4f);
  expect_near(at(0)[3], {0, 0, 0}, 1e-6f);
  expect_near(at(120)[3], {0, 0, 0}, 1e-4f);
  float prev_y = -1, prev_z = 1;
  for (double deg = 0; deg <= 130; deg += 0.25) {
    glm::vec3 o = at(deg)[0];
    EXPECT_GE(o.y, prev_y - 1e-5f) << deg;  // y: 0, 0.1, 0.2, 1 rises throughout
    EXPECT_LE(o.z, prev_z + 1e-5f) << deg;  // z: 0, 0, 0, -1 falls throughout
    EXPECT_GE(o.y, -1e-5f);
    EXPECT_LE(o.y, 1 + 1e-5f);
    prev_y = o.y;
    prev_z = o.z;
  }
  // vertex 3 (0, 0, 5, 0 in x): up then down, never beyond 5 or below 0
  for (double deg = 0; deg <= 130; deg += 0.25) {
    float x = at(deg)[3].x;
    EXPECT_LE(x, 5 + 1e-4f);
    EXPECT_GE(x, -1e-5f);
  }
}

// Two drivers of one joint (rotation about X and about Z) in pose space.
KeyposeSet shoulder_set(RbfKernel kernel) {
  KeyposeSet s;
  s.name = "shoulder";
  s.drivers = {JointDriver{0, DriverKind::kRotation, {1, 0, 0}},
               JointDriver{0, DriverKind::kRotation, {0, 0, 1}}};
  s.kernel = kernel;
  set_key(s, key_at({90, 0}, 1, {1, 0, 0}));
  set_key(s, key_at({0, 90}, 1, {0, 1, 0}));
  set_key(s, KeyposeKey{{60, 60}, {1, 2}, {{0, 0, 1}, {2, 2, 2}}});
  return s;
}

TEST(Keyposes, PoseSpaceRbfReproducesEveryKeyAndIsZeroAtRest) {
  OneJoint j;
  // pose at driver values (a, b): the rotation vector (a, 0, b) degrees, whose X and Z rotation
  // readings are exactly a and b
  auto pose_at = [&](double a, double b) {
    glm::dvec3 v(a, 0, b);
    double len = glm::length(v);
    return j.pose(len > 0 ? about_deg(len, v / len) : glm::quat(1, 0, 0, 0));
  };
  for (RbfKernel kernel : {RbfKernel::kGaussian, RbfKernel::kThinPlate, RbfKernel::kLinear}) {
    std::vector<KeyposeSet> sets = {shoulder_set(kernel)};
    const std::string name = rbf_kernel_name(kernel);
    expect_near(evaluate(sets, j.skeleton, pose_at(90, 0))[1], {1, 0, 0}, 1e-3f, name);
    expect_near(evaluate(sets, j.skeleton, pose_at(0, 90))[1], {0, 1, 0}, 1e-3f, name);
    auto both = evaluate(sets, j.skeleton, pose_at(60, 60));
    expect_near(both[1], {0, 0, 1}, 1e-3f, name);
    expect_near(both[2], {2, 2, 2}, 1e-3f, name);
    auto rest = evaluate(sets, j.skeleton, j.skeleton.rest_pose());
    for (const glm::vec3& o : rest) expect_near(o, {0, 0, 0}, 1e-5f, name + " at rest");
    // between keys: something in between (bounded by the keys for this layout)
    glm::vec3 mid = evaluate(sets, j.skeleton, pose_at(45, 45))[1];
    EXPECT_GT(glm::length(mid), 0.05f) << name;
    EXPECT_LT(glm::length(mid), 2.0f) << name;
  }
  // without the rest key the set need not vanish at rest
  KeyposeSet no_rest = shoulder_set(RbfKernel::kLinear);
  no_rest.rest_key = false;
  EXPECT_GT(glm::length(evaluate({no_rest}, j.skeleton, j.skeleton.rest_pose())[1]), 0.1f);
}

TEST(Keyposes, SetsAddUpAndMuteSoloChooseWhichAct) {
  OneJoint j;
  KeyposeSet a = one_driver_set();
  a.name = "a";
  set_key(a, key_at({100}, 0, {1, 0, 0}));
  KeyposeSet b = one_driver_set(DriverKind::kTwist);
  b.name = "b";
  set_key(b, key_at({100}, 0, {0, 2, 0}));
  Pose p = j.pose(about_deg(100, {1, 0, 0}));
  expect_near(evaluate({a, b}, j.skeleton, p)[0], {1, 2, 0}, 1e-5f);
  KeyposeSet am = a;
  am.mute = true;
  expect_near(evaluate({am, b}, j.skeleton, p)[0], {0, 2, 0}, 1e-5f);
  KeyposeSet bs = b;
  bs.solo = true;
  expect_near(evaluate({a, bs}, j.skeleton, p)[0], {0, 2, 0}, 1e-5f);
  KeyposeSet as = a;
  as.solo = true;
  expect_near(evaluate({as, bs}, j.skeleton, p)[0], {1, 2, 0}, 1e-5f);
  KeyposeSet bsm = bs;
  bsm.mute = true;  // soloed and muted: off, and the solo still silences the rest
  expect_near(evaluate({a, bsm}, j.skeleton, p)[0], {0, 0, 0}, 0.0f);
  std::vector<KeyposeSet> sets = {a, bs};
  EXPECT_FALSE(keypose_set_active(sets, 0));
  EXPECT_TRUE(keypose_set_active(sets, 1));
  EXPECT_FALSE(keypose_set_active(sets, 2));
}

TEST(Keyposes, InvalidSetsAreSkippedAndOutOfRangeVerticesIgnored) {
  OneJoint j;
  KeyposeSet bad = one_driver_set();
  bad.drivers[0].node = 5;
  set_key(bad, key_at({100}, 0, {1, 0, 0}));
  KeyposeSet far = one_driver_set();
  set_key(far, KeyposeKey{{100}, {1, 40}, {{0, 1, 0}, {9, 9, 9}}});
  auto out = evaluate({bad, far}, j.skeleton, j.pose(about_deg(100, {1, 0, 0})));
  expect_near(out[0], {0, 0, 0}, 0.0f);
  expect_near(out[1], {0, 1, 0}, 1e-6f);
}

TEST(Keyposes, EditingHelpers) {
  KeyposeSet s = one_driver_set();
  std::vector<glm::vec3> dense(5, glm::vec3(0.0f));
  dense[3] = {1, 2, 3};
  dense[1] = {0, 0, -1};
  KeyposeKey k = make_key({30}, dense);
  EXPECT_EQ(k.vertices, (std::vector<uint32_t>{1, 3}));
  EXPECT_EQ(dense_offsets(k, 5), dense);
  EXPECT_EQ(dense_offsets(k, 2).size(), 2u);
  set_key(s, k);
  set_key(s, key_at({-10}, 0, {1, 1, 1}));
  set_key(s, key_at({30}, 4, {7, 7, 7}));  // replaces the key at 30
  ASSERT_EQ(s.keys.size(), 2u);
  EXPECT_EQ(s.keys[1].vertices, (std::vector<uint32_t>{4}));
  const KeyposeSet before = s;
  set_key(s, key_at({80}, 0, {1, 1, 1}));
  EXPECT_TRUE(remove_key(s, std::vector<double>{80}));
  EXPECT_EQ(s, before);  // removing the key restores the earlier set exactly
  EXPECT_FALSE(remove_key(s, std::vector<double>{81}));
  std::vector<KeyposeSet> sets = {s};
  KeyposeSet other = s;
  other.name = "other";
  EXPECT_EQ(upsert_keypose_set(sets, other), 1u);
  other.mute = true;
  EXPECT_EQ(upsert_keypose_set(sets, other), 1u);
  EXPECT_TRUE(sets[1].mute);
  clear_vertex_data(sets);
  EXPECT_TRUE(sets[0].keys[0].vertices.empty());
  EXPECT_EQ(sets[0].keys.size(), 2u);
}

TEST(Keyposes, KeyingASculptKeepsTheShapeAtThatPose) {
  OneJoint j;
  for (KeyInterpolation interp : {KeyInterpolation::kLinear, KeyInterpolation::kSmooth}) {
    KeyposeSet s = one_driver_set();
    s.interpolation = interp;
    set_key(s, key_at({120}, 2, {0, 1, 0}));
    set_key(s, key_at({30}, 1, {0, 0, 1}));
    const Pose at70 = j.pose(about_deg(70, {1, 0, 0}));
    std::vector<glm::vec3> before = evaluate({s}, j.skeleton, at70);
    std::vector<glm::vec3> sculpt(4, glm::vec3(0.0f));
    sculpt[3] = {0.5f, 0, 0};
    sculpt[2] = {0, 0, -0.25f};
    KeyposeSet keyed = key_sculpt(s, driver_values(s, j.skeleton, at70), sculpt);
    ASSERT_EQ(keyed.keys.size(), 3u);
    std::vector<glm::vec3> after = evaluate({keyed}, j.skeleton, at70);
    for (size_t v = 0; v < 4; ++v)
      expect_near(after[v], before[v] + sculpt[v], 1e-5f, key_interpolation_name(interp));
    // the other keys are untouched
    expect_near(evaluate({keyed}, j.skeleton, j.pose(about_deg(120, {1, 0, 0})))[2], {0, 1, 0}, 1e-5f);
  }
  // the same in pose space
  KeyposeSet p = shoulder_set(RbfKernel::kGaussian);
  KeyposeSet keyed =
      key_sculpt(p, {30, 45}, std::vector<glm::vec3>{{0, 0, 0}, {1, 1, 1}, {0, 0, 0}, {0, 0, 0}});
  std::vector<glm::vec3> out(4, glm::vec3(0.0f)), was(4, glm::vec3(0.0f));
  add_keypose_set_offsets(keyed, std::vector<double>{30, 45}, out);
  add_keypose_set_offsets(p, std::vector<double>{30, 45}, was);
  expect_near(out[1], was[1] + glm::vec3(1, 1, 1), 1e-4f);
}

TEST(Keyposes, ValidationNamesTheSetKeyAndField) {
  auto message = [](const KeyposeSet& s) {
    Status v = validate_keypose_set(s, 3, 10);
    return v.ok() ? std::string("ok") : v.error().message;
  };
  KeyposeSet s = one_driver_set();
  set_key(s, key_at({10}, 2, {1, 0, 0}));
  EXPECT_EQ(message(s), "ok");
  KeyposeSet t = s;
  t.drivers.clear();
  EXPECT_EQ(message(t), "keypose set 'bulge': has no driver");
  t = s;
  t.drivers[0].node = 3;
  EXPECT_EQ(message(t), "keypose set 'bulge': driver 0 reads node 3, but the skeleton has 3 nodes");
  t = s;
  t.drivers[0].axis = {0, 0, 0};
  EXPECT_EQ(message(t), "keypose set 'bulge': driver 0 has a zero or non-finite axis");
  t = s;
  t.keys[0].values = {1, 2};
  EXPECT_EQ(message(t), "keypose set 'bulge': key 0 has 2 values for 1 drivers");
  t = s;
  t.keys[0].vertices = {10};
  EXPECT_EQ(message(t), "keypose set 'bulge': key 0 moves cage vertex 10, but the cage has 10 vertices");
  t = s;
  t.keys[0].vertices = {3, 2};
  t.keys[0].offsets.push_back({0, 0, 0});
  EXPECT_EQ(message(t), "keypose set 'bulge': key 0: vertices are not sorted and unique (at entry 1)");
  t = s;
  t.keys[0].offsets.clear();
  EXPECT_EQ(message(t), "keypose set 'bulge': key 0 has 0 offsets for 1 vertices");
  t = s;
  t.keys.push_back(t.keys[0]);
  EXPECT_EQ(message(t), "keypose set 'bulge': key 1 sits at the same driver values as key 0");
}

TEST(MirrorNames, Conventions) {
  EXPECT_EQ(mirror_name("forearm.L"), "forearm.R");
  EXPECT_EQ(mirror_name("forearm.R"), "forearm.L");
  EXPECT_EQ(mirror_name("hand_l"), "hand_r");
  EXPECT_EQ(mirror_name("hand_R"), "hand_L");
  EXPECT_EQ(mirror_name("mixamorig:LeftForeArm"), "mixamorig:RightForeArm");
  EXPECT_EQ(mirror_name("RightHand"), "LeftHand");
  EXPECT_EQ(mirror_name("upperarm_left"), "upperarm_right");
  EXPECT_EQ(mirror_name("L_toe"), "R_toe");
  EXPECT_EQ(mirror_name("Arm L"), "Arm R");
  EXPECT_EQ(mirror_name("spine"), "spine");
  EXPECT_EQ(mirror_name("L"), "L");  // a bare side letter is a name, not a side
  Character c = test::symmetric_character(true);
  EXPECT_EQ(mirror_node(c.skeleton, c.skeleton.find("hand.L")), c.skeleton.find("hand.R"));
  EXPECT_EQ(mirror_node(c.skeleton, c.skeleton.find("spine")), c.skeleton.find("spine"));
  EXPECT_EQ(mirror_node(c.skeleton, c.skeleton.find("tail.L")), -1);
}

// The rig's cage: pairs across x = 0 (0 <-> 1, 2 <-> 3) and one vertex on the plane (4).
std::vector<glm::vec3> symmetric_cage() {
  return {{0.8f, 0.1f, 0.05f},
          {-0.8f, 0.1f, 0.05f},
          {1.2f, -0.1f, 0.0f},
          {-1.2f, -0.1f, 0.0f},
          {0.0f, 0.3f, 0.0f}};
}

// The pose mirrored across x = 0: node n's relative rotation q becomes C q C^-1 on its mirror m,
// C = R_m^T X R_n (the rest world rotations, X the reflection).
Pose mirrored_pose(const Skeleton& sk, const Pose& pose) {
  auto rest = sk.global_transforms(sk.rest_pose());
  Pose out = sk.rest_pose();
  const glm::dmat3 x(glm::dvec3(-1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1));
  for (uint32_t n = 0; n < sk.size(); ++n) {
    int32_t m = mirror_node(sk, n);
    if (m < 0) continue;
    glm::dmat3 c = glm::transpose(glm::dmat3(glm::mat3(rest[m]))) * x * glm::dmat3(glm::mat3(rest[n]));
    glm::dmat3 q = glm::dmat3(
        glm::mat3_cast(glm::normalize(glm::inverse(sk.node(n).rest.rotation) * pose.local[n].rotation)));
    glm::dmat3 qm = c * q * glm::transpose(c);
    out.local[m].rotation = glm::normalize(sk.node(m).rest.rotation * glm::quat(glm::quat_cast(qm)));
  }
  return out;
}

TEST(MirrorKeyposes, MirroredSetOnTheMirroredPoseGivesTheMirroredOffsets) {
  Character c = test::symmetric_character();
  const Skeleton& sk = c.skeleton;
  const auto cage = symmetric_cage();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (DriverKind kind : {DriverKind::kRotation, DriverKind::kTwist, DriverKind::kSwing}) {
    for (glm::vec3 axis :
         {glm::vec3(1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, 0, 1), glm::vec3(0.6f, 0, 0.8f)}) {
      KeyposeSet s;
      s.name = "flex.L";
      s.drivers = {JointDriver{static_cast<uint32_t>(sk.find("hand.L")), kind, axis}};
      set_key(s, KeyposeKey{{40}, {0, 2, 4}, {{0.1f, 0.2f, 0.3f}, {-0.5f, 0, 1}, {0.25f, 0, 0}}});
      set_key(s, KeyposeKey{{-70}, {2}, {{0, 1, 0}}});
      if (kind == DriverKind::kSwing) s.keys.erase(s.keys.begin());  // swing reads >= 0
      auto m = mirror_keypose_set(s, sk, cage, 1e-4);
      ASSERT_TRUE(m.ok()) << m.error().message;
      EXPECT_TRUE(m->unmatched.empty());
      EXPECT_EQ(m->set.name, "flex.R");
      EXPECT_EQ(m->set.drivers[0].node, static_cast<uint32_t>(sk.find("hand.R")));
      ASSERT_TRUE(validate_keypose_set(m->set, sk.size(), cage.size()).ok());
      for (int trial = 0; trial < 5; ++trial) {
        Pose pose = sk.rest_pose();
        glm::dvec3 r(u(rng), u(rng), u(rng));
        test::rotate(sk, pose, "hand.L",
                     about_deg(30 + 60 * std::abs(r.x), glm::normalize(r + glm::dvec3(0, 0, 0.01))));
        Pose mp = mirrored_pose(sk, pose);
        auto left = evaluate({s}, sk, pose, cage.size());
        auto right = evaluate({m->set}, sk, mp, cage.size());
        const std::string what = std::string(driver_kind_name(kind)) + " axis " + std::to_string(axis.x) +
                                 "," + std::to_string(axis.y) + "," + std::to_string(axis.z);
        // 0 <-> 1, 2 <-> 3, 4 <-> 4, offsets with x negated
        const uint32_t pair[5] = {1, 0, 3, 2, 4};
        for (uint32_t v = 0; v < 5; ++v)
          expect_near(right[pair[v]], {-left[v].x, left[v].y, left[v].z}, 2e-4f, what);
      }
    }
  }
}

TEST(MirrorKeyposes, HingeAxesKeepTheirValues) {
  // the demo convention: local X is the bending axis on both sides, and a bend of +t on the left
  // mirrors to +t on the right, so a key at 120 stays at 120 about +X
  Character c = test::symmetric_character();
  KeyposeSet s;
  s.name = "biceps.L";
  s.drivers = {
      JointDriver{static_cast<uint32_t>(c.skeleton.find("hand.L")), DriverKind::kRotation, {1, 0, 0}}};
  set_key(s, key_at({120}, 0, {0.01f, 0.02f, 0.03f}));
  auto m = mirror_keypose_set(s, c.skeleton, symmetric_cage(), 1e-4);
  ASSERT_TRUE(m.ok());
  EXPECT_EQ(m->set.drivers[0].axis, glm::vec3(1, 0, 0));
  EXPECT_EQ(m->set.keys[0].values, std::vector<double>{120});
  EXPECT_EQ(m->set.keys[0].vertices, std::vector<uint32_t>{1});
  EXPECT_EQ(m->set.keys[0].offsets[0], glm::vec3(-0.01f, 0.02f, 0.03f));
  // about local Z (the arm's up/down swing in the rest plane) the reading changes sign instead
  s.drivers[0].axis = {0, 0, 1};
  m = mirror_keypose_set(s, c.skeleton, symmetric_cage(), 1e-4);
  ASSERT_TRUE(m.ok());
  EXPECT_EQ(m->set.drivers[0].axis, glm::vec3(0, 0, 1));
  EXPECT_EQ(m->set.keys[0].values, std::vector<double>{-120});
}

TEST(MirrorKeyposes, ReportsUnmatchedVerticesAndNodesWithoutAMirror) {
  Character c = test::symmetric_character(true);
  auto cage = symmetric_cage();
  cage[2].x = 1.25f;  // vertex 2 loses its counterpart
  KeyposeSet s;
  s.name = "tail";
  s.drivers = {
      JointDriver{static_cast<uint32_t>(c.skeleton.find("arm.L")), DriverKind::kRotation, {1, 0, 0}}};
  set_key(s, KeyposeKey{{40}, {0, 2}, {{1, 0, 0}, {0, 1, 0}}});
  auto m = mirror_keypose_set(s, c.skeleton, cage, 1e-3);
  ASSERT_TRUE(m.ok());
  EXPECT_EQ(m->unmatched, std::vector<uint32_t>{2});
  EXPECT_EQ(m->set.keys[0].vertices, std::vector<uint32_t>{1});
  EXPECT_EQ(m->set.name, "tail (mirrored)");  // driven by arm.R now: never the same name as the original
  s.drivers[0].node = static_cast<uint32_t>(c.skeleton.find("tail.L"));
  auto bad = mirror_keypose_set(s, c.skeleton, cage, 1e-3);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().message,
            "keypose set 'tail': driver node 'tail.L' has no mirror: no node is named 'tail.R'");
}

}  // namespace
}  // namespace cagewrap
