// Tests for app/workspace/move_gizmo.h: handle hits on a known view, axis drags stay on the axis and follow
// the cursor, plane and screen drags keep the grabbed point under the cursor, snapping.
#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include "app/workspace/move_gizmo.h"

namespace cagewrap {
namespace {

constexpr Viewport kView{800, 600};

Camera oblique() {
  Camera c;
  c.set_target({0, 0, 0});
  c.set_distance(5.0);
  c.set_angles(0.6, 0.4);
  return c;
}

TEST(MoveGizmo, LayoutIsCentredOnTheProjectedPointAndHasTheStatedScreenSize) {
  Camera c = oblique();
  const glm::dvec3 centre(0.2, 0.1, -0.3);
  GizmoLayout g = gizmo_layout(c, kView, centre);
  ASSERT_TRUE(g.visible);
  EXPECT_NEAR(glm::length(g.centre - c.project(centre, kView.width, kView.height).pixel), 0.0, 1e-9);
  // an axis seen side-on is about kGizmoAxisPixels long; none is longer
  double longest = 0;
  for (const auto& e : g.axis_end) longest = std::max(longest, glm::length(e - g.centre));
  EXPECT_LE(longest, kGizmoAxisPixels * 1.2);
  EXPECT_GE(longest, kGizmoAxisPixels * 0.6);
}

TEST(MoveGizmo, BehindTheCameraIsInvisibleAndHitsNothing) {
  Camera c = oblique();
  GizmoLayout g = gizmo_layout(c, kView, c.eye() - 3.0 * c.forward());
  EXPECT_FALSE(g.visible);
  EXPECT_EQ(gizmo_hit(g, g.centre), GizmoHandle::kNone);
}

TEST(MoveGizmo, HitFindsEachHandle) {
  Camera c = oblique();
  GizmoLayout g = gizmo_layout(c, kView, glm::dvec3(0.0));
  EXPECT_EQ(gizmo_hit(g, g.centre), GizmoHandle::kScreen);
  for (int a = 0; a < 3; ++a) {
    const glm::dvec2 near_tip = g.centre + 0.9 * (g.axis_end[a] - g.centre);
    EXPECT_EQ(gizmo_hit(g, near_tip), static_cast<GizmoHandle>(a)) << "axis " << a;
  }
  for (int p = 0; p < 3; ++p) {
    glm::dvec2 mid(0.0);
    for (const auto& q : g.plane[p]) mid += 0.25 * q;
    EXPECT_EQ(gizmo_hit(g, mid), static_cast<GizmoHandle>(3 + p)) << "plane " << p;
  }
  EXPECT_EQ(gizmo_hit(g, g.centre + glm::dvec2(300, 250)), GizmoHandle::kNone);
}

TEST(MoveGizmo, AxisDragMovesOnlyAlongTheAxisAndFollowsTheCursor) {
  Camera c = oblique();
  const glm::dvec3 centre(0.1, 0.2, 0.3);
  GizmoLayout g = gizmo_layout(c, kView, centre);
  for (int a = 0; a < 3; ++a) {
    const glm::dvec2 from = g.centre + 0.5 * (g.axis_end[a] - g.centre);
    // move the mouse along the projected axis by its full length, plus a perpendicular wobble
    const glm::dvec2 along = g.axis_end[a] - g.centre;
    const glm::dvec2 perp(-along.y, along.x);
    auto d = gizmo_drag(c, kView, static_cast<GizmoHandle>(a), centre, from, from + along + 0.2 * perp);
    ASSERT_TRUE(d.has_value());
    for (int k = 0; k < 3; ++k) {
      if (k != a) {
        EXPECT_EQ((*d)[k], 0.0);
      }
    }
    // without the wobble the axis moves by one world length: the tip lands where the mouse went
    auto straight = gizmo_drag(c, kView, static_cast<GizmoHandle>(a), centre, g.centre, g.axis_end[a]);
    ASSERT_TRUE(straight.has_value());
    EXPECT_NEAR((*straight)[a], g.world_length, 1e-6 * g.world_length);
  }
}

TEST(MoveGizmo, PlaneAndScreenDragsKeepTheGrabbedPointUnderTheCursor) {
  Camera c = oblique();
  const glm::dvec3 centre(-0.2, 0.4, 0.1);
  GizmoLayout g = gizmo_layout(c, kView, centre);
  const glm::dvec2 to = g.centre + glm::dvec2(37, -21);
  for (GizmoHandle h : {GizmoHandle::kPlaneYZ, GizmoHandle::kPlaneXZ, GizmoHandle::kPlaneXY, GizmoHandle::kScreen}) {
    auto d = gizmo_drag(c, kView, h, centre, g.centre, to);
    ASSERT_TRUE(d.has_value());
    const glm::dvec2 landed = c.project(centre + *d, kView.width, kView.height).pixel;
    EXPECT_NEAR(glm::length(landed - to), 0.0, 1e-6) << "handle " << int(h);
    const int p = static_cast<int>(h) - 3;
    if (p >= 0 && p < 3) {
      EXPECT_EQ((*d)[p], 0.0);
    }
  }
  auto s = gizmo_drag(c, kView, GizmoHandle::kScreen, centre, g.centre, to);
  EXPECT_NEAR(glm::dot(*s, c.forward()), 0.0, 1e-9);  // screen drags keep the depth
}

TEST(MoveGizmo, DragAlongAnAxisPointingAtTheViewerHoldsStill) {
  Camera c;  // front view: looks along -Z
  c.set_target({0, 0, 0});
  c.set_angles(0.0, 0.0);
  auto d = gizmo_drag(c, kView, GizmoHandle::kZ, glm::dvec3(0.0), {400, 300}, {450, 320});
  EXPECT_FALSE(d.has_value());
  auto p = gizmo_drag(c, kView, GizmoHandle::kPlaneYZ, glm::dvec3(0.0), {400, 300}, {450, 320});  // plane seen edge-on
  EXPECT_FALSE(p.has_value());
}

TEST(MoveGizmo, SnapRoundsEachComponent) {
  EXPECT_EQ(snap_displacement({0.26, -0.74, 0.0}, 0.5), glm::dvec3(0.5, -0.5, 0.0));
  EXPECT_EQ(snap_displacement({0.26, -0.74, 0.01}, 0.0), glm::dvec3(0.26, -0.74, 0.01));
}

}  // namespace
}  // namespace cagewrap
