#include <cmath>
#include <numbers>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "core/io/gltf_loader.h"
#include "core/character/skinning.h"
#include "tests/gltf_samples.h"
#include "tests/test_assets.h"

namespace cagewrap {
namespace {

using nlohmann::json;
using test::GltfBuilder;
using test::write_two_joint_file;

void expect_near(const glm::vec3& a, const glm::vec3& b, float tol = 1e-5f) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

TEST(Skinning, TwoJointSkinAtAKnownPose) {
  auto c = load_character(write_two_joint_file("two_joint"));
  ASSERT_TRUE(c.ok()) << c.error().message;
  int32_t clip = c->find_clip("bend");
  ASSERT_EQ(clip, 0);
  // At rest (= bind here) LBS reproduces the raw positions.
  auto rest = skin_character(*c, sample_pose(*c, -1, 0));
  expect_near(rest[0], {0, 0.5f, 0});
  expect_near(rest[1], {0, 1.5f, 0});
  expect_near(rest[2], {0, 2, 0});
  // At t = 1, j1 is turned 90 degrees about z around (0,1,0): (0,1.5) -> (-0.5,1); (0,2) blends
  // (0,2) from j0 with (-1,1) from j1 -> (-0.5,1.5).
  auto bent = skin_character(*c, sample_pose(*c, clip, 1.0));
  expect_near(bent[0], {0, 0.5f, 0});
  expect_near(bent[1], {-0.5f, 1, 0});
  expect_near(bent[2], {-0.5f, 1.5f, 0});
  // Halfway through the clip the turn is 45 degrees.
  auto half = skin_character(*c, sample_pose(*c, clip, 0.5));
  const float r = 0.5f * std::sqrt(0.5f);
  expect_near(half[1], {-r, 1 + r, 0});
}

TEST(Skinning, BindPoseIsTheRawPositionDataWhateverTheRestPose) {
  auto c = load_character(write_two_joint_file("bind_pose", true));
  ASSERT_TRUE(c.ok()) << c.error().message;
  // The loader keeps POSITION as the bind pose; the inverse bind matrices define where it binds.
  expect_near(c->primitives[0].positions[1], {0, 1.5f, 0});
  // Rest pose puts j1 at (0,3,0): the j1 vertex moves up by 2 and the blended one by 1.
  auto rest = skin_character(*c, c->skeleton.rest_pose());
  expect_near(rest[0], {0, 0.5f, 0});
  expect_near(rest[1], {0, 3.5f, 0});
  expect_near(rest[2], {0, 3, 0});
  // Joint matrices built from the bind transforms (inverse of the IBMs) give the identity.
  std::vector<glm::mat4> globals(c->skeleton.size(), glm::mat4(1.0f));
  for (size_t j = 0; j < c->skins[0].joints.size(); ++j)
    globals[c->skins[0].joints[j]] = glm::inverse(c->skins[0].inverse_bind[j]);
  std::vector<glm::mat4> jm(2);
  joint_matrices(c->skins[0], globals, jm);
  std::vector<glm::vec3> out(3);
  skin_primitive(c->primitives[0], jm, glm::mat4(1.0f), {}, out);
  for (size_t v = 0; v < 3; ++v) expect_near(out[v], c->primitives[0].positions[v]);
}

TEST(Skinning, MannequinRunStaysInsideItsBoundsAndMovesContinuously) {
  auto path = test::shared_asset("mannequiny.glb");
  if (!path) GTEST_SKIP() << "shared assets folder (mannequiny.glb) not found; set CAGEWRAP_SHARED_ASSETS";
  auto c = load_character(*path);
  ASSERT_TRUE(c.ok()) << c.error().message;
  int32_t run = c->find_clip("run");
  ASSERT_GE(run, 0);
  // The bounding volume: the bind pose's bounding sphere (centre of its box, half its diagonal),
  // scaled by 1.5. (The per-axis box would not do: the T-posed bind pose is only 0.32 m deep and
  // the run strides over a metre front to back.)
  std::vector<glm::vec3> bind;
  for (const Primitive& p : c->primitives) bind.insert(bind.end(), p.positions.begin(), p.positions.end());
  Aabb box = bounding_box(bind);
  const glm::dvec3 center = box.center();
  const double diag = box.diagonal();
  const double radius = 1.5 * 0.5 * diag;
  const double duration = c->clips[run].duration;
  const double dt = 1.0 / 60.0;
  for (double t : {0.0, 0.25 * duration, 0.5 * duration, 0.8 * duration}) {
    auto a = skin_character(*c, sample_pose(*c, run, t));
    auto b = skin_character(*c, sample_pose(*c, run, t + dt));
    ASSERT_EQ(a.size(), bind.size());
    double max_step = 0, max_moved = 0;
    for (size_t v = 0; v < a.size(); ++v) {
      ASSERT_LE(glm::length(glm::dvec3(a[v]) - center), radius)
          << "vertex " << v << " at t=" << t << " leaves the bind pose's bounding sphere scaled by 1.5";
      max_step = std::max(max_step, double(glm::length(b[v] - a[v])));
      max_moved = std::max(max_moved, double(glm::length(a[v] - bind[v])));
    }
    // Neither collapsed nor blown up: the posed box is of the same order as the bind box.
    double posed_diag = bounding_box(a).diagonal();
    EXPECT_GT(posed_diag, 0.5 * diag) << "t=" << t;
    EXPECT_LT(posed_diag, 1.5 * diag) << "t=" << t;
    EXPECT_GT(max_moved, 0.01 * diag) << "the run clip should move the character at t=" << t;
  }
  // Continuity: over every pair of consecutive 60 Hz frames of the clip, split into 10 sub-steps,
  // no sub-step carries more than 20% of the frame's motion (a jump would sit in one sub-step),
  // and no vertex moves faster than 20 m/s (the run's hands and feet peak near 13 m/s).
  const int frames = static_cast<int>(std::ceil(duration * 60.0));
  std::vector<glm::vec3> prev = skin_character(*c, sample_pose(*c, run, 0.0));
  for (int f = 0; f < frames; ++f) {
    std::vector<glm::vec3> start = prev;
    double max_sub = 0;
    for (int k = 1; k <= 10; ++k) {
      auto cur = skin_character(*c, sample_pose(*c, run, (f + k / 10.0) / 60.0));
      for (size_t v = 0; v < cur.size(); ++v) max_sub = std::max(max_sub, double(glm::length(cur[v] - prev[v])));
      prev = std::move(cur);
    }
    double frame_step = 0;
    for (size_t v = 0; v < prev.size(); ++v) frame_step = std::max(frame_step, double(glm::length(prev[v] - start[v])));
    EXPECT_LE(max_sub, 0.2 * frame_step + 1e-5) << "frame " << f;
    EXPECT_LT(frame_step * 60.0, 20.0) << "frame " << f;
  }
}

}  // namespace
}  // namespace cagewrap
