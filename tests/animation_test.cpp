#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "core/character/animation.h"
#include "core/io/gltf_loader.h"
#include "core/character/skinning.h"
#include "tests/gltf_samples.h"

namespace cagewrap {
namespace {

using nlohmann::json;
using test::GltfBuilder;
using test::write_interpolation_file;

float x_at(const Character& c, const std::string& clip, double t) {
  Pose pose = sample_pose(c, c.find_clip(clip), t);
  return pose.local[0].translation.x;
}

TEST(Animation, EachInterpolationModeGivesItsKnownValues) {
  auto c = load_character(write_interpolation_file("interp"));
  ASSERT_TRUE(c.ok()) << c.error().message;
  ASSERT_EQ(c->clips.size(), 4u);
  EXPECT_DOUBLE_EQ(c->clips[0].duration, 3.0);
  EXPECT_EQ(c->clips[0].samplers[0].interpolation, Interpolation::kStep);
  EXPECT_EQ(c->clips[2].samplers[0].interpolation, Interpolation::kCubicSpline);
  // STEP holds each key until the next.
  EXPECT_FLOAT_EQ(x_at(*c, "step", 0.0), 0.0f);
  EXPECT_FLOAT_EQ(x_at(*c, "step", 0.99), 0.0f);
  EXPECT_FLOAT_EQ(x_at(*c, "step", 1.0), 10.0f);
  EXPECT_FLOAT_EQ(x_at(*c, "step", 2.9), 10.0f);
  EXPECT_FLOAT_EQ(x_at(*c, "step", 3.0), 30.0f);
  // LINEAR interpolates between neighbouring keys, clamps outside.
  EXPECT_FLOAT_EQ(x_at(*c, "linear", 0.5), 5.0f);
  EXPECT_FLOAT_EQ(x_at(*c, "linear", 2.0), 20.0f);
  EXPECT_FLOAT_EQ(x_at(*c, "linear", 2.5), 25.0f);
  EXPECT_FLOAT_EQ(x_at(*c, "linear", -1.0), 0.0f);
  EXPECT_FLOAT_EQ(x_at(*c, "linear", 7.0), 30.0f);
  // CUBICSPLINE (Hermite): p(u) = h00 p0 + h10 dt m0 + h01 p1 + h11 dt m1 with dt = 2.
  // At u = 0.5: h00 = h01 = 0.5, h10 = 0.125, h11 = -0.125 -> 0 + 0.125*2*1 + 0.5 + 0 = 0.75.
  EXPECT_NEAR(x_at(*c, "cubic", 1.0), 0.75f, 1e-6);
  // At u = 0.25: h10 = 0.140625, h01 = 0.15625 -> 0.28125 + 0.15625 = 0.4375.
  EXPECT_NEAR(x_at(*c, "cubic", 0.5), 0.4375f, 1e-6);
  EXPECT_NEAR(x_at(*c, "cubic", 2.0), 1.0f, 1e-6);  // the value, not the 9s of the tangents
  EXPECT_NEAR(x_at(*c, "cubic", 0.0), 0.0f, 1e-6);
  // LINEAR rotation is a slerp: halfway is 45 degrees about z.
  Pose pose = sample_pose(*c, c->find_clip("turn"), 1.0);
  glm::quat q = pose.local[0].rotation;
  EXPECT_NEAR(q.z, std::sin(std::numbers::pi / 8), 1e-6);
  EXPECT_NEAR(q.w, std::cos(std::numbers::pi / 8), 1e-6);
  EXPECT_NEAR(q.x, 0.0f, 1e-7);
  // A quarter of the way: 22.5 degrees (a plain lerp would give a different angle).
  q = sample_pose(*c, c->find_clip("turn"), 0.5).local[0].rotation;
  EXPECT_NEAR(2 * std::atan2(q.z, q.w), std::numbers::pi / 8, 1e-6);
}

TEST(Animation, SlerpTakesTheShortestArc) {
  AnimationSampler s;
  s.interpolation = Interpolation::kLinear;
  s.components = 4;
  s.times = {0, 1};
  // 170 degrees about z, then 190 degrees stored as its negative-w twin of -170: the short way
  // passes through 180, not back through 0.
  auto q = [](double deg) {
    double h = deg * std::numbers::pi / 360;
    return std::array<float, 4>{0, 0, float(std::sin(h)), float(std::cos(h))};
  };
  auto a = q(170), b = q(190);
  for (auto& v : b) v = -v;
  s.values = {a[0], a[1], a[2], a[3], b[0], b[1], b[2], b[3]};
  float out[4];
  sample(s, 0.5, true, out);
  double angle = 2 * std::atan2(std::abs(out[2]), std::abs(out[3]));
  EXPECT_NEAR(angle * 180 / std::numbers::pi, 180.0, 1e-3);
}

TEST(Animation, ClipTimeLoopsOrClamps) {
  EXPECT_DOUBLE_EQ(clip_time(2.5, 2.0, true), 0.5);
  EXPECT_DOUBLE_EQ(clip_time(-0.5, 2.0, true), 1.5);
  EXPECT_DOUBLE_EQ(clip_time(4.0, 2.0, true), 0.0);
  EXPECT_DOUBLE_EQ(clip_time(2.5, 2.0, false), 2.0);
  EXPECT_DOUBLE_EQ(clip_time(-1.0, 2.0, false), 0.0);
  EXPECT_DOUBLE_EQ(clip_time(1.0, 0.0, true), 0.0);
}

TEST(Animation, PlayerPlaysLoopsAndScrubs) {
  ClipPlayer p(2.0);
  p.advance(0.5);
  EXPECT_DOUBLE_EQ(p.time(), 0.0);  // paused until played
  p.play();
  p.advance(0.5);
  EXPECT_DOUBLE_EQ(p.time(), 0.5);
  p.advance(2.0);
  EXPECT_DOUBLE_EQ(p.time(), 0.5);  // looped around
  EXPECT_TRUE(p.playing());
  p.scrub(1.75);
  EXPECT_DOUBLE_EQ(p.time(), 1.75);
  p.set_loop(false);
  p.advance(1.0);
  EXPECT_DOUBLE_EQ(p.time(), 2.0);  // stops at the end
  EXPECT_FALSE(p.playing());
  p.set_speed(-1.0);
  p.play();
  p.advance(0.5);
  EXPECT_DOUBLE_EQ(p.time(), 1.5);
}

TEST(Animation, BadSamplersNameTheAnimationAndSampler) {
  GltfBuilder b;
  b.set_scene({b.add_node({{"name", "n"}})});
  int times = b.add_floats({0, 1, 0.5f}, "SCALAR");
  int values = b.add_floats({0, 0, 0, 1, 1, 1, 2, 2, 2}, "VEC3");
  int short_values = b.add_floats({0, 0, 0, 1, 1, 1}, "VEC3");
  auto dir = test::temp_dir("bad_sampler");
  b.doc["animations"] = json::array({{{"name", "walk"},
                                      {"samplers", {{{"input", times}, {"output", values}}}},
                                      {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}}}}}});
  b.write_embedded(dir + "/decreasing.gltf");
  auto c = load_character(dir + "/decreasing.gltf");
  ASSERT_FALSE(c.ok());
  EXPECT_NE(c.error().message.find("animation 0 ('walk') sampler 0: key 2 time 0.5"), std::string::npos)
      << c.error().message;
  int good_times = b.add_floats({0, 1, 2}, "SCALAR");
  b.doc["animations"][0]["samplers"][0] = {{"input", good_times}, {"output", short_values}};
  b.write_embedded(dir + "/short.gltf");
  c = load_character(dir + "/short.gltf");
  ASSERT_FALSE(c.ok());
  EXPECT_NE(c.error().message.find("animation 0 ('walk') sampler 0 output holds 6 values, but 3 keys of 3 values need 9"),
            std::string::npos)
      << c.error().message;
  b.doc["animations"][0]["channels"][0]["target"]["node"] = 5;
  b.write_embedded(dir + "/node.gltf");
  c = load_character(dir + "/node.gltf");
  ASSERT_FALSE(c.ok());
  EXPECT_NE(c.error().message.find("animation 0 ('walk') channel 0 targets node 5, but the file has 1 nodes"),
            std::string::npos)
      << c.error().message;
}

}  // namespace
}  // namespace cagewrap
