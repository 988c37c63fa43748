// Joint angle read-outs that a keypose can be driven by: the rotation of a joint relative to its
// rest orientation, its angle about a chosen joint-local axis, and its swing/twist decomposition
// (the twist is the rotation about the axis, the swing the remaining rotation that moves the axis;
// q = swing * twist). Angles are unwrapped over time so a clip that turns past +-180 degrees
// reads as one continuous curve.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include "core/character/character.h"
#include "core/character/skeleton.h"

namespace cagewrap {

// The node's local rotation relative to its rest rotation, in the rest joint frame:
// inverse(rest.rotation) * pose.rotation.
glm::quat rotation_from_rest(const Skeleton& skeleton, const Pose& pose, uint32_t node);

struct SwingTwist {
  glm::quat swing{1.0f, 0.0f, 0.0f, 0.0f};
  glm::quat twist{1.0f, 0.0f, 0.0f, 0.0f};
  double twist_angle = 0.0;  // radians about the axis, in [-pi, pi]
  double swing_angle = 0.0;  // radians, in [0, pi]: how far the axis itself was turned
  glm::vec3 swing_axis{1.0f, 0.0f, 0.0f};  // unit axis of the swing, perpendicular to `axis`
};

// Decomposes q = swing * twist about the unit `axis`.
SwingTwist swing_twist(const glm::quat& q, const glm::vec3& axis);

// The rotation angle of q about the unit `axis` (its twist angle), radians in [-pi, pi].
double angle_about_axis(const glm::quat& q, const glm::vec3& axis);

// The angle equal to `angle` modulo 2 pi that is closest to `previous`.
double unwrap_angle(double previous, double angle);
// Unwraps a sequence in place so consecutive values differ by at most pi.
void unwrap_angles(std::span<double> angles);

// Reads one joint angle frame after frame, continuous across +-180 degrees.
class JointAngleReadout {
 public:
  enum class Kind { kAboutAxis, kSwing };
  JointAngleReadout(uint32_t node, glm::vec3 axis, Kind kind = Kind::kAboutAxis);
  // Radians; the first read is in [-pi, pi], later reads continue from the previous one.
  double read(const Skeleton& skeleton, const Pose& pose);
  void reset() { has_previous_ = false; }
  uint32_t node() const { return node_; }

 private:
  uint32_t node_;
  glm::vec3 axis_;
  Kind kind_;
  bool has_previous_ = false;
  double previous_ = 0.0;
};

// The angle of `node` about its local `axis` relative to rest, sampled over clip `clip` at
// `frames` evenly spaced times from 0 to its duration (inclusive), unwrapped (#frames).
std::vector<double> clip_joint_angles(const Character& character, int32_t clip, uint32_t node, glm::vec3 axis,
                                      size_t frames);

}  // namespace cagewrap
