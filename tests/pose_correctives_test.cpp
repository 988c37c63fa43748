// Pose-driven correctives (core/export/pose_correctives.h): on a hinge whose residual is a known shape per side
// of its angle, the fit finds both ramps, predicts poses it did not see, and its weights are the documented
// linear function of the ramps (what an engine computes from the extras).
#include <cmath>

#include <gtest/gtest.h>
#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include "core/export/pose_correctives.h"

namespace cagewrap {
namespace {

TEST(PoseCorrectives, AHingeResidualIsPredictedOnPosesTheFitDidNotSee) {
  std::vector<SkeletonNode> nodes(2);
  nodes[0].name = "upper";
  nodes[1].name = "lower";
  nodes[1].parent = 0;
  nodes[1].rest.translation = {0, 1, 0};
  nodes[1].rest.rotation = glm::angleAxis(0.3f, glm::vec3(0, 0, 1));  // angles are read from the rest rotation
  const Skeleton sk = Skeleton::create(nodes, "hinge").value();
  const size_t np = 50;
  std::vector<glm::vec3> bend(np), stretch(np);
  for (size_t i = 0; i < np; ++i) {
    bend[i] = glm::vec3(std::sin(0.3 * i), 0.01 * i, std::cos(0.2 * i)) * 0.02f;
    stretch[i] = glm::vec3(0.0f, 0.015f * std::cos(0.5 * i), 0.0f);
  }
  std::vector<Pose> poses;
  std::vector<std::vector<glm::vec3>> residuals;
  std::vector<bool> fit;
  for (int deg = -60; deg <= 120; deg += 5) {
    Pose p = sk.rest_pose();
    p.local[1].rotation = nodes[1].rest.rotation * glm::angleAxis(float(glm::radians(double(deg))), glm::vec3(1, 0, 0));
    poses.push_back(p);
    std::vector<glm::vec3> r(np);
    const float up = float(std::max(0, deg)) / 120.0f, down = float(std::max(0, -deg)) / 60.0f;
    for (size_t i = 0; i < np; ++i) r[i] = up * bend[i] + down * stretch[i];
    residuals.push_back(r);
    fit.push_back(deg % 15 != 0 || deg == 120 || deg == -60);  // every third pose held out, the extremes kept
  }
  const std::vector<JointDriver> drivers = pose_corrective_drivers({}, std::vector<uint32_t>{0, 1});
  EXPECT_EQ(drivers.size(), 6u) << "three rotation components of each joint";
  const std::vector<std::vector<uint32_t>> point_nodes(np, std::vector<uint32_t>{0, 1});
  PoseCorrectiveFit out;
  size_t steps = 0;
  ASSERT_TRUE(fit_pose_correctives(sk, drivers, poses, residuals, fit, point_nodes, 2,
                                   [&](size_t, size_t) { return ++steps > 0; }, out));
  EXPECT_GT(steps, 0u);
  // the ramps: only the hinge's X moves, both ways, scaled to the largest angle fitted
  ASSERT_EQ(out.features.size(), 2u);
  EXPECT_EQ(out.features[0].name, "lower rotation x+");
  EXPECT_NEAR(out.features[0].scale, 120.0, 1e-3);
  EXPECT_EQ(out.features[1].name, "lower rotation x-");
  EXPECT_NEAR(out.features[1].scale, 60.0, 1e-3);
  EXPECT_EQ(out.rank, 2u);
  ASSERT_EQ(out.targets.size(), 2u);
  ASSERT_EQ(out.feature_weights.size(), 2u);
  // every sample's weights are the linear function of its ramps the extras give an engine, and the held-out
  // poses are predicted within the ridge's shrinkage
  double worst_held = 0.0, largest = 0.0;
  for (size_t s = 0; s < poses.size(); ++s) {
    for (size_t k = 0; k < 2; ++k) {
      double w = 0.0;
      for (size_t f = 0; f < 2; ++f) w += out.feature_weights[k][f] * pose_feature_value(out.features[f], sk, poses[s]);
      EXPECT_NEAR(out.weights[s][k], w, 1e-5) << "sample " << s << " target " << k;
    }
    for (size_t i = 0; i < np; ++i) {
      glm::vec3 x(0.0f);
      for (size_t k = 0; k < 2; ++k) x += out.weights[s][k] * out.targets[k][i];
      largest = std::max(largest, double(glm::length(residuals[s][i])));
      if (!fit[s]) worst_held = std::max(worst_held, double(glm::length(x - residuals[s][i])));
    }
  }
  EXPECT_LT(worst_held, 0.15 * largest) << "largest residual " << largest;
  // the extras name the features and carry the K x F weights, fully on at 1
  out.targets.clear();  // the extras need only the features and their weights
  const nlohmann::json extras = nlohmann::json::parse(pose_correctives_extras(sk, out));
  const nlohmann::json& pc = extras["cagewrap_pose_correctives"];
  EXPECT_EQ(extras["targetNames"].size(), 2u);
  EXPECT_EQ(pc["features"][0]["node_name"], "lower");
  EXPECT_EQ(pc["features"][1]["side"], -1);
  EXPECT_EQ(pc["weights"].size(), 2u);
  EXPECT_EQ(pc["weights"][0].size(), 2u);
  EXPECT_EQ(pc["full"], nlohmann::json::array({1.0, 1.0}));
  EXPECT_NEAR(pc["features"][0]["rest_rotation"][3].get<double>(), std::cos(0.15), 1e-6);
}

}  // namespace
}  // namespace cagewrap
