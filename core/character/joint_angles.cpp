#include "core/character/joint_angles.h"

#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "core/character/skinning.h"

namespace cagewrap {

glm::quat rotation_from_rest(const Skeleton& skeleton, const Pose& pose, uint32_t node) {
  return glm::normalize(glm::inverse(skeleton.node(node).rest.rotation) * pose.local[node].rotation);
}

SwingTwist swing_twist(const glm::quat& q_in, const glm::vec3& axis_in) {
  glm::dquat q = glm::normalize(glm::dquat(q_in));
  if (q.w < 0) q = -q;  // same rotation; keeps the twist angle in [-pi, pi]
  glm::dvec3 axis = glm::normalize(glm::dvec3(axis_in));
  glm::dvec3 v(q.x, q.y, q.z);
  double proj = glm::dot(v, axis);
  SwingTwist st;
  glm::dquat twist(q.w, axis.x * proj, axis.y * proj, axis.z * proj);
  double len = glm::length(twist);
  if (len < 1e-12) {
    // A half-turn swing about an axis perpendicular to `axis`: no defined twist.
    twist = glm::dquat(1, 0, 0, 0);
  } else {
    twist /= len;
  }
  glm::dquat swing = q * glm::conjugate(twist);
  st.twist = glm::quat(twist);
  st.swing = glm::quat(swing);
  st.twist_angle = 2.0 * std::atan2(glm::dot(glm::dvec3(twist.x, twist.y, twist.z), axis), twist.w);
  if (st.twist_angle > std::numbers::pi) st.twist_angle -= 2 * std::numbers::pi;
  if (st.twist_angle < -std::numbers::pi) st.twist_angle += 2 * std::numbers::pi;
  if (swing.w < 0) swing = -swing;
  glm::dvec3 sv(swing.x, swing.y, swing.z);
  double s = glm::length(sv);
  st.swing_angle = 2.0 * std::atan2(s, swing.w);
  if (s > 1e-12) st.swing_axis = glm::vec3(sv / s);
  return st;
}

double angle_about_axis(const glm::quat& q, const glm::vec3& axis) { return swing_twist(q, axis).twist_angle; }

double unwrap_angle(double previous, double angle) {
  const double two_pi = 2 * std::numbers::pi;
  return angle + two_pi * std::round((previous - angle) / two_pi);
}

void unwrap_angles(std::span<double> a) {
  for (size_t i = 1; i < a.size(); ++i) a[i] = unwrap_angle(a[i - 1], a[i]);
}

JointAngleReadout::JointAngleReadout(uint32_t node, glm::vec3 axis, Kind kind)
    : node_(node), axis_(glm::normalize(axis)), kind_(kind) {}

double JointAngleReadout::read(const Skeleton& skeleton, const Pose& pose) {
  SwingTwist st = swing_twist(rotation_from_rest(skeleton, pose, node_), axis_);
  double a = kind_ == Kind::kAboutAxis ? st.twist_angle : st.swing_angle;
  if (kind_ == Kind::kAboutAxis && has_previous_) a = unwrap_angle(previous_, a);
  previous_ = a;
  has_previous_ = true;
  return a;
}

std::vector<double> clip_joint_angles(const Character& c, int32_t clip, uint32_t node, glm::vec3 axis,
                                      size_t frames) {
  std::vector<double> out(frames);
  if (clip < 0 || clip >= static_cast<int32_t>(c.clips.size()) || node >= c.skeleton.size()) return {};
  const double duration = c.clips[clip].duration;
  JointAngleReadout readout(node, axis);
  for (size_t f = 0; f < frames; ++f) {
    double t = frames > 1 ? duration * double(f) / double(frames - 1) : 0.0;
    out[f] = readout.read(c.skeleton, sample_pose(c, clip, t));
  }
  return out;
}

}  // namespace cagewrap
