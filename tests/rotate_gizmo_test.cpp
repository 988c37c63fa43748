// Tests for app/workspace/rotate_gizmo.h: rings are hit on their front half, a drag along a ring gives the
// angle the grabbed point swept (checked by rotating the grabbed point and projecting it), the view
// ring turns about the view direction, edge-on rings still turn, snapping.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include "app/workspace/rotate_gizmo.h"

namespace cagewrap {
namespace {

constexpr Viewport kView{800, 600};
constexpr double kPi = 3.14159265358979323846;

Camera oblique() {
  Camera c;
  c.set_target({0, 0, 0});
  c.set_distance(5.0);
  c.set_angles(0.5, 0.35);
  return c;
}

glm::dmat3 tilted_axes() {
  glm::dquat q = glm::angleAxis(0.4, glm::normalize(glm::dvec3(1, 2, 0.5)));
  return glm::mat3_cast(q);
}

// The point of ring k at angle a (radians from the ring's first axis).
glm::dvec3 ring_point(const RotateGizmoLayout& g, int k, double a) {
  return g.world_centre + g.world_radius * (std::cos(a) * g.axes[(k + 1) % 3] + std::sin(a) * g.axes[(k + 2) % 3]);
}

TEST(RotateGizmo, RingsAreHitOnTheirFrontHalf) {
  Camera c = oblique();
  RotateGizmoLayout g = rotate_gizmo_layout(c, kView, glm::dvec3(0.1, 0.2, 0.0), tilted_axes());
  ASSERT_TRUE(g.visible);
  const glm::dvec3 to_eye = glm::normalize(c.eye() - g.world_centre);
  const size_t n = g.rings[0].size();
  for (int k = 0; k < 3; ++k) {
    // the ring points nearest to and farthest from the viewer (middles of the front and back halves)
    size_t front = 0, back = 0;
    for (size_t i = 0; i < n; ++i) {
      const double facing = glm::dot(ring_point(g, k, 2 * kPi * i / n) - g.world_centre, to_eye);
      if (facing > glm::dot(ring_point(g, k, 2 * kPi * front / n) - g.world_centre, to_eye)) front = i;
      if (facing < glm::dot(ring_point(g, k, 2 * kPi * back / n) - g.world_centre, to_eye)) back = i;
    }
    EXPECT_NE(rotate_gizmo_hit(g, g.rings[k][front]), RotateHandle::kNone) << "ring " << k;  // another ring may cross there
    if (glm::length(g.rings[k][front] - g.rings[k][back]) > 15.0) {  // not edge-on
      EXPECT_NE(rotate_gizmo_hit(g, g.rings[k][back]), static_cast<RotateHandle>(k)) << "the back half of ring " << k << " is not grabbable";
    }
  }
  EXPECT_EQ(rotate_gizmo_hit(g, g.view_ring[5]), RotateHandle::kView);
  EXPECT_EQ(rotate_gizmo_hit(g, g.centre + glm::dvec2(300, 200)), RotateHandle::kNone);
}

TEST(RotateGizmo, DragAngleIsTheAngleTheGrabbedPointSwept) {
  Camera c = oblique();
  RotateGizmoLayout g = rotate_gizmo_layout(c, kView, glm::dvec3(-0.2, 0.1, 0.3), tilted_axes());
  for (int k = 0; k < 3; ++k) {
    const glm::dvec3 axis = g.axes[k];
    if (std::abs(glm::dot(glm::normalize(c.eye() - g.world_centre), axis)) < 0.2) continue;  // nearly edge-on
    for (double sweep : {0.3, -0.7, 1.2}) {
      const glm::dvec3 p0 = ring_point(g, k, 0.4), p1 = ring_point(g, k, 0.4 + sweep);
      const glm::dvec2 from = c.project(p0, kView.width, kView.height).pixel, to = c.project(p1, kView.width, kView.height).pixel;
      auto angle = rotate_gizmo_angle(c, kView, g, static_cast<RotateHandle>(k), from, to);
      ASSERT_TRUE(angle.has_value());
      EXPECT_NEAR(*angle, sweep, 1e-6) << "ring " << k;
    }
  }
}

TEST(RotateGizmo, ViewRingTurnsAboutTheViewDirection) {
  Camera c = oblique();
  RotateGizmoLayout g = rotate_gizmo_layout(c, kView, glm::dvec3(0.0), glm::dmat3(1.0));
  EXPECT_NEAR(glm::length(rotate_handle_axis(c, g, RotateHandle::kView) + c.forward()), 0.0, 1e-12);
  // a quarter turn counter-clockwise on screen (y down: from right to top) turns +90 degrees
  // about the axis toward the viewer
  const glm::dvec2 from = g.centre + glm::dvec2(50, 0), to = g.centre + glm::dvec2(0, -50);
  auto angle = rotate_gizmo_angle(c, kView, g, RotateHandle::kView, from, to);
  ASSERT_TRUE(angle.has_value());
  EXPECT_NEAR(*angle, kPi / 2, 1e-3);
}

TEST(RotateGizmo, EdgeOnRingStillTurnsAndNoneGivesNothing) {
  Camera c;  // front view: looking down -Z, so the X ring (normal X) is edge-on
  c.set_target({0, 0, 0});
  c.set_angles(0.0, 0.0);
  RotateGizmoLayout g = rotate_gizmo_layout(c, kView, glm::dvec3(0.0), glm::dmat3(1.0));
  auto a = rotate_gizmo_angle(c, kView, g, RotateHandle::kX, g.centre + glm::dvec2(0, -40), g.centre + glm::dvec2(-40, 0));
  ASSERT_TRUE(a.has_value());
  EXPECT_GT(std::abs(*a), 0.5);
  EXPECT_FALSE(rotate_gizmo_angle(c, kView, g, RotateHandle::kNone, {1, 1}, {2, 2}).has_value());
}

TEST(RotateGizmo, SnapAngle) {
  const double step = kPi / 12;  // 15 degrees
  EXPECT_NEAR(snap_angle(0.3, step), step, 1e-12);
  EXPECT_NEAR(snap_angle(0.4, step), 2 * step, 1e-12);
  EXPECT_NEAR(snap_angle(-0.2, step), -step, 1e-12);
  EXPECT_EQ(snap_angle(0.3, 0.0), 0.3);
}

}  // namespace
}  // namespace cagewrap
