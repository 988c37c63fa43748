#include <cmath>
#include <numbers>

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include "core/io/gltf_loader.h"
#include "core/character/joint_angles.h"
#include "core/character/skinning.h"
#include "tests/gltf_builder.h"

namespace cagewrap {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

glm::quat about(double degrees, glm::vec3 axis) { return glm::angleAxis(float(degrees * kDeg), glm::normalize(axis)); }

TEST(JointAngles, SwingTwistSplitsAKnownRotation) {
  // twist 50 degrees about y, then swing 30 degrees about x: q = swing * twist.
  glm::quat q = about(30, {1, 0, 0}) * about(50, {0, 1, 0});
  SwingTwist st = swing_twist(q, {0, 1, 0});
  EXPECT_NEAR(st.twist_angle / kDeg, 50.0, 1e-4);
  EXPECT_NEAR(st.swing_angle / kDeg, 30.0, 1e-4);
  EXPECT_NEAR(st.swing_axis.x, 1.0f, 1e-5);
  // The parts recompose to q (up to sign).
  glm::quat r = st.swing * st.twist;
  EXPECT_NEAR(std::abs(glm::dot(r, q)), 1.0f, 1e-6);
  // The swing moves the axis, the twist leaves it in place.
  glm::vec3 moved = st.twist * glm::vec3(0, 1, 0);
  EXPECT_NEAR(moved.y, 1.0f, 1e-6);
  // Negative angles and the q / -q ambiguity.
  EXPECT_NEAR(angle_about_axis(about(-120, {0, 0, 1}), {0, 0, 1}) / kDeg, -120.0, 1e-4);
  glm::quat neg = -about(-120, {0, 0, 1});
  EXPECT_NEAR(angle_about_axis(neg, {0, 0, 1}) / kDeg, -120.0, 1e-4);
  // About an axis the rotation does not turn: zero.
  EXPECT_NEAR(angle_about_axis(about(70, {1, 0, 0}), {0, 1, 0}), 0.0, 1e-6);
}

TEST(JointAngles, UnwrapKeepsCurvesContinuousPast180) {
  EXPECT_NEAR(unwrap_angle(170 * kDeg, -170 * kDeg) / kDeg, 190.0, 1e-9);
  EXPECT_NEAR(unwrap_angle(-175 * kDeg, 175 * kDeg) / kDeg, -185.0, 1e-9);
  EXPECT_NEAR(unwrap_angle(10 * kDeg, 20 * kDeg) / kDeg, 20.0, 1e-9);
  std::vector<double> a = {160 * kDeg, 179 * kDeg, -178 * kDeg, -150 * kDeg, 170 * kDeg};
  unwrap_angles(a);
  EXPECT_NEAR(a[2] / kDeg, 182.0, 1e-9);
  EXPECT_NEAR(a[3] / kDeg, 210.0, 1e-9);
  EXPECT_NEAR(a[4] / kDeg, 170.0, 1e-9);
}

TEST(JointAngles, ClipTurningPastHalfATurnReadsContinuously) {
  // A joint with a non-trivial rest rotation (30 degrees about x) turns about its local z from 0 to
  // 300 degrees, keyed every 20 degrees.
  test::GltfBuilder b;
  glm::quat rest = about(30, {1, 0, 0});
  b.set_scene({b.add_node({{"name", "elbow"}, {"rotation", {rest.x, rest.y, rest.z, rest.w}}})});
  std::vector<float> times, values;
  for (int k = 0; k <= 15; ++k) {
    times.push_back(k * 0.1f);
    glm::quat q = rest * about(20.0 * k, {0, 0, 1});
    values.insert(values.end(), {q.x, q.y, q.z, q.w});
  }
  int in = b.add_floats(times, "SCALAR", true);
  int out = b.add_floats(values, "VEC4");
  b.doc["animations"].push_back({{"name", "spin"},
                                 {"samplers", {{{"input", in}, {"output", out}}}},
                                 {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "rotation"}}}}}}});
  auto dir = test::temp_dir("angles");
  b.write_embedded(dir + "/spin.gltf");
  auto c = load_character(dir + "/spin.gltf");
  ASSERT_TRUE(c.ok()) << c.error().message;
  auto angles = clip_joint_angles(*c, 0, 0, {0, 0, 1}, 61);
  ASSERT_EQ(angles.size(), 61u);
  EXPECT_NEAR(angles.front() / kDeg, 0.0, 1e-3);
  EXPECT_NEAR(angles[30] / kDeg, 150.0, 1e-3);
  EXPECT_NEAR(angles.back() / kDeg, 300.0, 1e-3);
  for (size_t i = 1; i < angles.size(); ++i)
    EXPECT_NEAR((angles[i] - angles[i - 1]) / kDeg, 5.0, 1e-3) << "frame " << i;
  // The swing read-out about z stays zero: the turn is pure twist.
  JointAngleReadout swing(0, {0, 0, 1}, JointAngleReadout::Kind::kSwing);
  EXPECT_NEAR(swing.read(c->skeleton, sample_pose(*c, 0, 0.77)), 0.0, 1e-5);
}

}  // namespace
}  // namespace cagewrap
