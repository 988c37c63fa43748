#include "app/workspace/camera.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/vec4.hpp>

namespace cagewrap {

namespace {
constexpr double kHalfPi = 1.5707963267948966;
constexpr double kPi = 3.141592653589793;
// Clip planes scale with the distance so depth precision follows the zoom.
constexpr double kNearRatio = 0.01, kFarRatio = 1000.0;
}  // namespace

void Camera::set_distance(double distance) {
  distance_ = std::clamp(std::isfinite(distance) ? distance : kMaxDistance, kMinDistance, kMaxDistance);
}

void Camera::set_angles(double yaw, double pitch) {
  yaw_ = std::remainder(yaw, 2 * kPi);
  pitch_ = std::clamp(pitch, -kHalfPi, kHalfPi);
}

void Camera::set_fov_y(double radians) {
  fov_y_ = std::clamp(radians, glm::radians(1.0), glm::radians(170.0));
}

// Orientation R = Ry(yaw) * Rx(-pitch): camera -Z is the view direction, +Y screen up, +X right.
glm::dvec3 Camera::forward() const {
  const double cp = std::cos(pitch_), sp = std::sin(pitch_), cy = std::cos(yaw_), sy = std::sin(yaw_);
  return {-cp * sy, -sp, -cp * cy};
}

glm::dvec3 Camera::right() const {
  return {std::cos(yaw_), 0.0, -std::sin(yaw_)};
}

glm::dvec3 Camera::up() const {
  const double cp = std::cos(pitch_), sp = std::sin(pitch_), cy = std::cos(yaw_), sy = std::sin(yaw_);
  return {-sp * sy, cp, -sp * cy};
}

glm::dvec3 Camera::eye() const {
  return target_ - distance_ * forward();
}

double Camera::near_plane() const {
  return mode_ == ProjectionMode::kPerspective ? kNearRatio * distance_ : -kFarRatio * distance_;
}

double Camera::far_plane() const {
  return kFarRatio * distance_;
}

double Camera::world_per_pixel(double viewport_height) const {
  return 2.0 * distance_ * std::tan(0.5 * fov_y_) / std::max(viewport_height, 1.0);
}

glm::dmat4 Camera::view() const {
  const glm::dvec3 r = right(), u = up(), b = -forward(), e = eye();
  glm::dmat4 m(1.0);
  for (int i = 0; i < 3; ++i) {
    m[i][0] = r[i];
    m[i][1] = u[i];
    m[i][2] = b[i];
  }
  m[3][0] = -glm::dot(r, e);
  m[3][1] = -glm::dot(u, e);
  m[3][2] = -glm::dot(b, e);
  return m;
}

glm::dmat4 Camera::projection(double aspect) const {
  aspect = aspect > 0 && std::isfinite(aspect) ? aspect : 1.0;
  if (mode_ == ProjectionMode::kPerspective)
    return glm::perspective(fov_y_, aspect, near_plane(), far_plane());
  const double hh = distance_ * std::tan(0.5 * fov_y_), hw = hh * aspect;
  return glm::ortho(-hw, hw, -hh, hh, near_plane(), far_plane());
}

void Camera::orbit(double dx, double dy) {
  const double pitch = pitch_ + dy * kRadiansPerPixel;
  // a preset may sit exactly on a pole; orbiting only moves away from it
  const double lo = std::min(-kMaxOrbitPitch, pitch_), hi = std::max(kMaxOrbitPitch, pitch_);
  set_angles(yaw_ - dx * kRadiansPerPixel, std::clamp(pitch, lo, hi));
}

void Camera::pan(double dx, double dy, double viewport_height) {
  const double s = world_per_pixel(viewport_height);
  target_ -= s * (dx * right() - dy * up());
}

void Camera::zoom(double steps) {
  set_distance(distance_ * std::pow(kZoomStep, -steps));
}

void Camera::frame(const Aabb& box, double aspect) {
  aspect = aspect > 0 && std::isfinite(aspect) ? aspect : 1.0;
  if (box.empty()) {
    target_ = glm::dvec3(0.0);
    return;
  }
  target_ = box.center();
  const double t = std::tan(0.5 * fov_y_) * kFrameFill;
  const glm::dvec3 r = right(), u = up(), b = -forward();
  double needed = 0.0, front = 0.0;
  for (int i = 0; i < 8; ++i) {
    const glm::dvec3 corner((i & 1) ? box.hi.x : box.lo.x, (i & 2) ? box.hi.y : box.lo.y,
                            (i & 4) ? box.hi.z : box.lo.z);
    const glm::dvec3 c = corner - target_;
    const double cx = std::abs(glm::dot(c, r)), cy = std::abs(glm::dot(c, u)), cz = glm::dot(c, b);
    // perspective: corner at depth D - cz must satisfy |cy| <= fill * tan * (D - cz), same for x
    const double extent = std::max(cy / t, cx / (t * aspect));
    if (mode_ == ProjectionMode::kPerspective) {
      needed = std::max(needed, cz + extent);
      front = std::max(front, cz);
    } else {
      needed = std::max(needed, extent);
    }
  }
  // keep the whole box in front of the near plane even when it is flat toward the viewer
  const double radius = 0.5 * box.diagonal();
  if (mode_ == ProjectionMode::kPerspective) needed = std::max(needed, front + 0.05 * radius);
  set_distance(needed > 0 ? needed : 1.0);
}

void Camera::set_preset(ViewPreset preset) {
  switch (preset) {
    case ViewPreset::kFront:
      set_angles(0.0, 0.0);
      break;
    case ViewPreset::kBack:
      set_angles(kPi, 0.0);
      break;
    case ViewPreset::kRight:
      set_angles(kHalfPi, 0.0);
      break;
    case ViewPreset::kLeft:
      set_angles(-kHalfPi, 0.0);
      break;
    case ViewPreset::kTop:
      set_angles(0.0, kHalfPi);
      break;
    case ViewPreset::kBottom:
      set_angles(0.0, -kHalfPi);
      break;
  }
}

Ray Camera::ray(double pixel_x, double pixel_y, double width, double height) const {
  width = std::max(width, 1.0);
  height = std::max(height, 1.0);
  const double aspect = width / height;
  const double nx = 2.0 * pixel_x / width - 1.0, ny = 1.0 - 2.0 * pixel_y / height;
  const double th = std::tan(0.5 * fov_y_);
  const glm::dvec3 f = forward();
  if (mode_ == ProjectionMode::kPerspective) {
    const glm::dvec3 d = f + (nx * th * aspect) * right() + (ny * th) * up();
    return {eye(), glm::normalize(d)};
  }
  const double hh = distance_ * th;
  const glm::dvec3 origin = eye() + (nx * hh * aspect) * right() + (ny * hh) * up() + near_plane() * f;
  return {origin, f};
}

Ray Camera::ray_through(const glm::dvec3& world, double* t) const {
  const glm::dvec3 e = eye(), f = forward();
  if (mode_ == ProjectionMode::kPerspective) {
    const glm::dvec3 d = world - e;
    const double len = glm::length(d);
    if (t) *t = len;
    return {e, len > 0 ? d / len : f};
  }
  const double along = glm::dot(world - e, f);
  if (t) *t = along - near_plane();
  return {world - (along - near_plane()) * f, f};
}

ScreenPoint Camera::project(const glm::dvec3& world, double width, double height) const {
  width = std::max(width, 1.0);
  height = std::max(height, 1.0);
  const glm::dvec4 eye_p = view() * glm::dvec4(world, 1.0);
  const glm::dvec4 clip = projection(width / height) * eye_p;
  ScreenPoint s;
  s.view_depth = -eye_p.z;
  const double w = clip.w != 0.0 ? clip.w : 1e-300;
  const glm::dvec3 ndc = glm::dvec3(clip) / w;
  s.pixel = {0.5 * (ndc.x + 1.0) * width, 0.5 * (1.0 - ndc.y) * height};
  s.depth = 0.5 * (ndc.z + 1.0);
  s.in_clip_range = s.view_depth >= near_plane() && s.view_depth <= far_plane();
  return s;
}

}  // namespace cagewrap
