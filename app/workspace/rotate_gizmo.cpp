#include "app/workspace/rotate_gizmo.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace cagewrap {

namespace {

constexpr double kPi = 3.14159265358979323846;

double distance_to_polyline(const std::vector<glm::dvec2>& pts, const std::vector<bool>* mask, glm::dvec2 p) {
  double best = 1e300;
  const size_t n = pts.size();
  for (size_t i = 0; i < n; ++i) {
    const size_t j = (i + 1) % n;
    if (mask && !((*mask)[i] && (*mask)[j])) continue;
    const glm::dvec2 a = pts[i], ab = pts[j] - a;
    const double len2 = glm::dot(ab, ab);
    const double t = len2 > 0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    best = std::min(best, glm::length(p - (a + t * ab)));
  }
  return best;
}

}  // namespace

RotateGizmoLayout rotate_gizmo_layout(const Camera& camera, Viewport vp, const glm::dvec3& centre, const glm::dmat3& axes,
                                      int segments) {
  RotateGizmoLayout g;
  const ScreenPoint sc = camera.project(centre, vp.width, vp.height);
  if (!sc.in_clip_range) return g;
  g.visible = true;
  g.centre = sc.pixel;
  g.world_centre = centre;
  const double depth_scale = camera.mode() == ProjectionMode::kPerspective ? sc.view_depth / camera.distance() : 1.0;
  g.world_radius = kRotateRingPixels * camera.world_per_pixel(vp.height) * depth_scale;
  for (int k = 0; k < 3; ++k) g.axes[k] = glm::normalize(axes[k]);
  const glm::dvec3 to_eye = camera.mode() == ProjectionMode::kPerspective ? glm::normalize(camera.eye() - centre) : -camera.forward();
  segments = std::max(segments, 8);
  for (int k = 0; k < 3; ++k) {
    const glm::dvec3 u = g.axes[(k + 1) % 3], v = g.axes[(k + 2) % 3];
    for (int s = 0; s < segments; ++s) {
      const double a = 2.0 * kPi * s / segments;
      const glm::dvec3 dir = std::cos(a) * u + std::sin(a) * v;
      g.rings[k].push_back(camera.project(centre + g.world_radius * dir, vp.width, vp.height).pixel);
      g.front[k].push_back(glm::dot(dir, to_eye) >= -0.05);
    }
  }
  for (int s = 0; s < segments; ++s) {
    const double a = 2.0 * kPi * s / segments;
    g.view_ring.push_back(g.centre + kRotateViewRingShare * kRotateRingPixels * glm::dvec2(std::cos(a), std::sin(a)));
  }
  return g;
}

RotateHandle rotate_gizmo_hit(const RotateGizmoLayout& g, glm::dvec2 p) {
  if (!g.visible) return RotateHandle::kNone;
  double best = 6.0;
  RotateHandle hit = RotateHandle::kNone;
  for (int k = 0; k < 3; ++k) {
    const double d = distance_to_polyline(g.rings[k], &g.front[k], p);
    if (d < best) best = d, hit = static_cast<RotateHandle>(k);
  }
  if (hit == RotateHandle::kNone && distance_to_polyline(g.view_ring, nullptr, p) < 6.0) hit = RotateHandle::kView;
  return hit;
}

glm::dvec3 rotate_handle_axis(const Camera& camera, const RotateGizmoLayout& g, RotateHandle h) {
  if (h == RotateHandle::kView) return -camera.forward();
  if (h == RotateHandle::kNone) return glm::dvec3(0.0);
  return g.axes[static_cast<int>(h)];
}

std::optional<double> rotate_gizmo_angle(const Camera& camera, Viewport vp, const RotateGizmoLayout& g, RotateHandle h,
                                         glm::dvec2 from, glm::dvec2 to) {
  if (h == RotateHandle::kNone || !g.visible) return std::nullopt;
  const glm::dvec3 axis = rotate_handle_axis(camera, g, h);
  const glm::dvec3 centre = g.world_centre;
  const Ray r0 = camera.ray(from.x, from.y, vp.width, vp.height), r1 = camera.ray(to.x, to.y, vp.width, vp.height);
  const double facing = std::abs(glm::dot(r0.direction, axis));
  if (facing > 0.08) {  // the plane is not edge-on: intersect it
    auto hit = [&](const Ray& r) { return r.at(glm::dot(centre - r.origin, axis) / glm::dot(r.direction, axis)); };
    const glm::dvec3 a = hit(r0) - centre, b = hit(r1) - centre;
    const glm::dvec3 pa = a - glm::dot(a, axis) * axis, pb = b - glm::dot(b, axis) * axis;
    if (glm::length(pa) > 1e-12 && glm::length(pb) > 1e-12)
      return std::atan2(glm::dot(glm::cross(pa, pb), axis), glm::dot(pa, pb));
  }
  // edge-on: the angle swept around the projected centre, signed by which way the axis faces
  const glm::dvec2 a = from - g.centre, b = to - g.centre;
  if (glm::length(a) < 1e-9 || glm::length(b) < 1e-9) return 0.0;
  const double screen = std::atan2(a.x * b.y - a.y * b.x, glm::dot(a, b));  // y down: clockwise positive
  return glm::dot(axis, camera.forward()) > 0 ? screen : -screen;
}

double snap_angle(double angle, double step) {
  if (!(step > 0.0)) return angle;
  return std::round(angle / step) * step;
}

}  // namespace cagewrap
