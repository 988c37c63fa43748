#include "app/workspace/move_gizmo.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace cagewrap {

namespace {

glm::dvec3 unit_axis(int a) {
  glm::dvec3 e(0.0);
  e[a] = 1.0;
  return e;
}

// Where the ray meets the plane through `point` with normal `n`; nullopt when nearly parallel.
std::optional<glm::dvec3> ray_plane(const Ray& ray, const glm::dvec3& point, const glm::dvec3& n) {
  const double denom = glm::dot(ray.direction, n);
  if (std::abs(denom) < 1e-6) return std::nullopt;
  const double t = glm::dot(point - ray.origin, n) / denom;
  return ray.at(t);
}

// Parameter s of the point on the line point + s * dir closest to the ray; nullopt when parallel.
std::optional<double> ray_line(const Ray& ray, const glm::dvec3& point, const glm::dvec3& dir) {
  const glm::dvec3 w = point - ray.origin;
  const double b = glm::dot(dir, ray.direction);
  const double denom = 1.0 - b * b;  // both unit length
  if (denom < 1e-8) return std::nullopt;
  return (b * glm::dot(w, ray.direction) - glm::dot(w, dir)) / denom;
}

bool inside_quad(const std::array<glm::dvec2, 4>& q, glm::dvec2 p) {
  // convex quad: p is inside when it lies on the same side of every edge
  int sign = 0;
  for (int i = 0; i < 4; ++i) {
    const glm::dvec2 a = q[i], b = q[(i + 1) % 4];
    const double c = (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
    const int s = c > 0 ? 1 : (c < 0 ? -1 : 0);
    if (s == 0) continue;
    if (sign == 0) sign = s;
    else if (s != sign) return false;
  }
  return sign != 0;
}

}  // namespace

GizmoLayout gizmo_layout(const Camera& camera, Viewport viewport, const glm::dvec3& centre) {
  GizmoLayout g;
  const ScreenPoint sc = camera.project(centre, viewport.width, viewport.height);
  if (!sc.in_clip_range) return g;
  g.visible = true;
  g.centre = sc.pixel;
  // constant on-screen size: world length at the centre's depth
  const double depth_scale = camera.mode() == ProjectionMode::kPerspective ? sc.view_depth / camera.distance() : 1.0;
  g.world_length = kGizmoAxisPixels * camera.world_per_pixel(viewport.height) * depth_scale;
  for (int a = 0; a < 3; ++a)
    g.axis_end[a] = camera.project(centre + g.world_length * unit_axis(a), viewport.width, viewport.height).pixel;
  for (int p = 0; p < 3; ++p) {  // plane normal to axis p spans the other two
    const glm::dvec3 u = unit_axis((p + 1) % 3) * (kGizmoPlaneShare * g.world_length);
    const glm::dvec3 v = unit_axis((p + 2) % 3) * (kGizmoPlaneShare * g.world_length);
    const glm::dvec3 corners[4] = {centre + 0.5 * (u + v), centre + u + 0.5 * v, centre + u + v, centre + 0.5 * u + v};
    for (int k = 0; k < 4; ++k) g.plane[p][k] = camera.project(corners[k], viewport.width, viewport.height).pixel;
  }
  return g;
}

GizmoHandle gizmo_hit(const GizmoLayout& g, glm::dvec2 m) {
  if (!g.visible) return GizmoHandle::kNone;
  if (std::abs(m.x - g.centre.x) <= 7 && std::abs(m.y - g.centre.y) <= 7) return GizmoHandle::kScreen;
  for (int p = 0; p < 3; ++p)
    if (inside_quad(g.plane[p], m)) return static_cast<GizmoHandle>(3 + p);
  double best = 6.0;
  GizmoHandle hit = GizmoHandle::kNone;
  for (int a = 0; a < 3; ++a) {
    const glm::dvec2 ab = g.axis_end[a] - g.centre;
    const double len2 = glm::dot(ab, ab);
    if (len2 < 1.0) continue;  // pointing at the viewer: use a plane or the centre
    const double t = std::clamp(glm::dot(m - g.centre, ab) / len2, 0.0, 1.0);
    const double d = glm::length(m - (g.centre + t * ab));
    if (t > 0.15 && d < best) {
      best = d;
      hit = static_cast<GizmoHandle>(a);
    }
  }
  return hit;
}

std::optional<glm::dvec3> gizmo_drag(const Camera& camera, Viewport vp, GizmoHandle handle, const glm::dvec3& centre,
                                     glm::dvec2 from, glm::dvec2 to) {
  const Ray r0 = camera.ray(from.x, from.y, vp.width, vp.height);
  const Ray r1 = camera.ray(to.x, to.y, vp.width, vp.height);
  const int h = static_cast<int>(handle);
  if (h >= 0 && h < 3) {
    const glm::dvec3 dir = unit_axis(h);
    auto s0 = ray_line(r0, centre, dir), s1 = ray_line(r1, centre, dir);
    if (!s0 || !s1) return std::nullopt;
    return (*s1 - *s0) * dir;
  }
  glm::dvec3 n;
  if (h >= 3 && h < 6) n = unit_axis(h - 3);
  else if (handle == GizmoHandle::kScreen) n = camera.forward();
  else return std::nullopt;
  auto p0 = ray_plane(r0, centre, n), p1 = ray_plane(r1, centre, n);
  if (!p0 || !p1) return std::nullopt;
  glm::dvec3 d = *p1 - *p0;
  if (h >= 3 && h < 6) d[h - 3] = 0.0;  // exactly in the plane
  return d;
}

glm::dvec3 snap_displacement(const glm::dvec3& d, double step) {
  if (!(step > 0.0)) return d;
  return glm::round(d / step) * step;
}

}  // namespace cagewrap
