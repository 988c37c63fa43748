// Pose-driven corrective morph targets for baked-skin exports (issue 22, `--correctives pose-driven`): each
// target is driven by one joint angle, so an engine that drives morph weights from joint angles (Unreal's
// Pose Driver, a script in Godot, Unity or three.js) corrects animations the export never saw.
//
// A feature is a ramp on one driver (core/cage/keyposes.h: a joint angle in degrees relative to the node's
// rest rotation): f = clamp(side * angle / scale, 0, 1), side +1 or -1, scale the largest side * angle over
// the fitted poses (a feature is dropped below kMinFeatureDegrees). The drivers: every keypose set's
// drivers, and for every joint of the skin the three components of its rotation vector about the node's
// own rest X, Y and Z (kRotation drivers), duplicates removed.
//
// The fit: per skin point i with residuals r_i(s) (bind space, sample s) and candidate features C(i) (those
// on the nodes of the point's fitted joints and their children), ridge least squares
// min sum_s |r_i(s) - sum_{f in C(i)} T_{f,i} f(s)|^2 + lambda sum_f |T_{f,i}|^2 (lambda = kPoseRidge x the mean
// of the normal matrix's diagonal) predicts every sample's residual from the features: P(s) = F(s) T. The
// predictions over the fitted samples are reduced to their K principal components (K = max_targets; an SVD
// through their Gram matrix): the targets B_k, unit length, and each sample's weights w_k(s). Those weights are
// linear in the features (the components lie in the span of F's columns), W = argmin |F W - w|^2 (ridge
// 1e-9), so an engine gets target k's weight from the joint angles as sum_f W_fk f.
#pragma once

#include <functional>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "core/cage/keyposes.h"
#include "core/character/skeleton.h"

namespace cagewrap {

inline constexpr double kMinFeatureDegrees = 5.0;
// The ridge, relative to the mean of each point's normal matrix's diagonal. Chosen on the mannequin holding out
// one clip at a time (docs/algorithm-notes.md): 1e-3 fits the seen clips closer and doubles the worst vertex of
// a held-out run; 0.1 keeps held-out clips' worst vertices at or below the skeleton alone's.
inline constexpr double kPoseRidge = 0.1;

struct PoseFeature {
  JointDriver driver;
  int side = 1;        // +1 or -1
  double scale = 1.0;  // degrees at which the target is fully on
  std::string name;    // "forearm.L rotation x+"
};

// clamp(side * driver_value / scale, 0, 1)
double pose_feature_value(const PoseFeature& feature, const Skeleton& skeleton, const Pose& pose);

// The drivers features are made of: the keypose sets' (active or not) and three kRotation drivers (local X,
// Y, Z) for each of `joint_nodes`, without duplicates.
std::vector<JointDriver> pose_corrective_drivers(std::span<const KeyposeSet> sets, std::span<const uint32_t> joint_nodes);

struct PoseCorrectiveFit {
  std::vector<PoseFeature> features;               // #F: every feature made (both sides of each driver that moves)
  std::vector<std::vector<double>> feature_weights;  // #K x #F: target k's weight = sum_f W[k][f] * feature f
  std::vector<std::vector<glm::vec3>> targets;     // #K x #points, bind space
  std::vector<std::vector<float>> weights;         // #S x #K: each sample's weights, from its features
  size_t rank = 0;                                 // components of the fitted predictions
};

// poses (#S) with residuals (#S x #points); fit[s]: whether sample s is fitted (held-out samples are not,
// and do not set the scales). point_nodes[i]: the skeleton nodes whose drivers may explain point i.
// `step(done, total)` reports progress and returns false to cancel (then false is returned).
bool fit_pose_correctives(const Skeleton& skeleton, std::span<const JointDriver> drivers, std::span<const Pose> poses,
                          const std::vector<std::vector<glm::vec3>>& residuals, const std::vector<bool>& fit,
                          const std::vector<std::vector<uint32_t>>& point_nodes, size_t max_targets,
                          const std::function<bool(size_t, size_t)>& step, PoseCorrectiveFit& out);

// The mesh's glTF extras describing the targets (docs/pose-correctives.md): JSON text of
// {"targetNames": [...], "cagewrap_pose_correctives": {"version": 1, "features": [{"name", "node", "node_name",
// "kind", "axis", "rest_rotation", "side", "scale"}, ...], "weights": [[#F] x #K], "full": [#K ones]}}.
std::string pose_correctives_extras(const Skeleton& skeleton, const PoseCorrectiveFit& fit);

}  // namespace cagewrap
