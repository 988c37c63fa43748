// Orbit camera: conventions, round trips, framing, pan/orbit/zoom invariants, presets.
#include "app/workspace/camera.h"

#include <cmath>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

namespace cagewrap {
namespace {

constexpr double kW = 1280, kH = 720;

void expect_near(const glm::dvec3& a, const glm::dvec3& b, double tol) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

std::vector<Camera> sample_cameras() {
  std::vector<Camera> cams;
  for (ProjectionMode mode : {ProjectionMode::kPerspective, ProjectionMode::kOrthographic})
    for (double yaw : {0.0, 0.7, -2.5, 3.0})
      for (double pitch : {0.0, 0.4, -1.2, 1.5707963267948966}) {
        Camera c;
        c.set_mode(mode);
        c.set_target({0.3, 1.1, -0.2});
        c.set_distance(3.5);
        c.set_angles(yaw, pitch);
        cams.push_back(c);
      }
  return cams;
}

TEST(Camera, DefaultLooksDownMinusZWithYUp) {
  Camera c;
  c.set_target({0, 0, 0});
  c.set_distance(5);
  expect_near(c.forward(), {0, 0, -1}, 1e-15);
  expect_near(c.up(), {0, 1, 0}, 1e-15);
  expect_near(c.right(), {1, 0, 0}, 1e-15);
  expect_near(c.eye(), {0, 0, 5}, 1e-15);
  // same matrix as glm::lookAt away from the poles
  c.set_angles(0.8, 0.3);
  const glm::dmat4 ref = glm::lookAt(c.eye(), c.target(), glm::dvec3(0, 1, 0));
  const glm::dmat4 v = c.view();
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) EXPECT_NEAR(v[i][j], ref[i][j], 1e-12);
}

TEST(Camera, FrameIsOrthonormalAndRightHandedEverywhere) {
  for (const Camera& c : sample_cameras()) {
    const glm::dvec3 r = c.right(), u = c.up(), f = c.forward();
    EXPECT_NEAR(glm::length(r), 1, 1e-12);
    EXPECT_NEAR(glm::length(u), 1, 1e-12);
    EXPECT_NEAR(glm::dot(r, u), 0, 1e-12);
    expect_near(glm::cross(r, u), -f, 1e-12);
    // the view matrix sends the eye to the origin and the target down -Z
    const glm::dvec4 t = c.view() * glm::dvec4(c.target(), 1.0);
    EXPECT_NEAR(t.x, 0, 1e-12);
    EXPECT_NEAR(t.y, 0, 1e-12);
    EXPECT_NEAR(t.z, -c.distance(), 1e-12);
  }
}

TEST(Camera, ProjectOfRayPointRoundTrips) {
  const double pixels[][2] = {{0.5, 0.5}, {640, 360}, {1279.5, 719.5}, {17.25, 600.75}, {1000, 3}};
  for (const Camera& c : sample_cameras()) {
    for (const auto& p : pixels) {
      const Ray ray = c.ray(p[0], p[1], kW, kH);
      EXPECT_NEAR(glm::length(ray.direction), 1.0, 1e-12);
      for (double t : {0.5, 3.5, 20.0}) {
        const ScreenPoint s = c.project(ray.at(t), kW, kH);
        EXPECT_NEAR(s.pixel.x, p[0], 1e-7);
        EXPECT_NEAR(s.pixel.y, p[1], 1e-7);
        EXPECT_TRUE(s.in_clip_range);
        EXPECT_GE(s.depth, 0.0);
        EXPECT_LE(s.depth, 1.0);
      }
    }
    // the centre pixel's ray passes through the target
    const Ray centre = c.ray(kW / 2, kH / 2, kW, kH);
    const glm::dvec3 to_target = c.target() - centre.origin;
    expect_near(glm::dvec3(centre.origin + glm::dot(to_target, centre.direction) * centre.direction),
                c.target(), 1e-9);
  }
}

TEST(Camera, RayThroughHitsThePointAtT) {
  for (const Camera& c : sample_cameras()) {
    const glm::dvec3 p(0.9, -0.4, 0.6);
    double t = 0;
    const Ray r = c.ray_through(p, &t);
    expect_near(r.at(t), p, 1e-12);
    const ScreenPoint s = c.project(p, kW, kH);
    const Ray r2 = c.ray(s.pixel.x, s.pixel.y, kW, kH);
    expect_near(r2.direction, r.direction, 1e-9);
  }
}

TEST(Camera, PointsBehindThePerspectiveCameraAreOutOfClipRange) {
  Camera c;
  c.set_target({0, 0, 0});
  c.set_distance(2);
  EXPECT_FALSE(c.project({0, 0, 3}, kW, kH).in_clip_range);      // behind the eye
  EXPECT_FALSE(c.project({0, 0, 1.995}, kW, kH).in_clip_range);  // before the near plane (0.02)
  EXPECT_TRUE(c.project({0, 0, 1.9}, kW, kH).in_clip_range);
  // nearer points have a smaller window depth
  EXPECT_LT(c.project({0, 0, 1}, kW, kH).depth, c.project({0, 0, -1}, kW, kH).depth);
  EXPECT_NEAR(c.project({0, 0, -1}, kW, kH).view_depth, 3.0, 1e-12);
}

TEST(Camera, OrthographicKeepsTheTargetPlaneSize) {
  Camera c;
  c.set_angles(0.3, 0.2);
  const glm::dvec3 p = c.target() + 0.4 * c.right() - 0.7 * c.up();
  const ScreenPoint persp = c.project(p, kW, kH);
  c.set_mode(ProjectionMode::kOrthographic);
  const ScreenPoint ortho = c.project(p, kW, kH);
  EXPECT_NEAR(persp.pixel.x, ortho.pixel.x, 1e-9);
  EXPECT_NEAR(persp.pixel.y, ortho.pixel.y, 1e-9);
  // in ortho every ray is parallel to the view direction
  expect_near(c.ray(3, 4, kW, kH).direction, c.forward(), 1e-15);
  expect_near(c.ray(1200, 700, kW, kH).direction, c.forward(), 1e-15);
}

TEST(Camera, FrameFitsAllCornersWithOneNearAnEdge) {
  const Aabb boxes[] = {
      [] {
        Aabb b;
        b.extend({-0.9, 0, -0.15});
        b.extend({0.9, 1.8, 0.2});
        return b;
      }(),  // a character
      [] {
        Aabb b;
        b.extend({10, 20, 30});
        b.extend({10.1, 25, 30.1});
        return b;
      }(),  // a tall pole
      [] {
        Aabb b;
        b.extend({-3, -1, -2});
        b.extend({3, -0.9, 2});
        return b;
      }(),  // a flat slab
  };
  for (Camera c : sample_cameras())
    for (const Aabb& box : boxes)
      for (double aspect : {16.0 / 9.0, 0.5}) {
        const double w = 800 * aspect, h = 800;
        c.frame(box, aspect);
        expect_near(c.target(), box.center(), 1e-12);
        double worst = 0;  // largest |NDC| over the corners, in the tighter dimension
        for (int i = 0; i < 8; ++i) {
          const glm::dvec3 corner((i & 1) ? box.hi.x : box.lo.x, (i & 2) ? box.hi.y : box.lo.y,
                                  (i & 4) ? box.hi.z : box.lo.z);
          const ScreenPoint s = c.project(corner, w, h);
          EXPECT_TRUE(s.in_clip_range);
          EXPECT_GE(s.pixel.x, 0);
          EXPECT_LE(s.pixel.x, w);
          EXPECT_GE(s.pixel.y, 0);
          EXPECT_LE(s.pixel.y, h);
          worst = std::max({worst, std::abs(s.pixel.x / w * 2 - 1), std::abs(s.pixel.y / h * 2 - 1)});
        }
        EXPECT_NEAR(worst, Camera::kFrameFill, 1e-6) << "the box should fill 80% of the viewport";
      }
}

TEST(Camera, PanMovesTheTargetProjectionByExactlyThePixelDelta) {
  for (Camera c : sample_cameras()) {
    const glm::dvec3 old_target = c.target();
    const double dx = 37.5, dy = -12.25;
    c.pan(dx, dy, kH);
    const ScreenPoint s = c.project(old_target, kW, kH);
    EXPECT_NEAR(s.pixel.x, kW / 2 + dx, 1e-8);
    EXPECT_NEAR(s.pixel.y, kH / 2 + dy, 1e-8);
    // orientation and distance unchanged
    EXPECT_NEAR(glm::length(c.eye() - c.target()), 3.5, 1e-12);
  }
}

TEST(Camera, OrbitPreservesDistanceAndStopsShortOfThePoles) {
  Camera c;
  c.set_target({1, 2, 3});
  c.set_distance(2.5);
  const double moves[][2] = {{100, 0}, {-30, 40}, {5000, 5000}, {-200, -90000}, {1, 1}};
  for (const auto& m : moves) {
    c.orbit(m[0], m[1]);
    EXPECT_NEAR(glm::length(c.eye() - c.target()), 2.5, 1e-12);
    EXPECT_LE(std::abs(c.pitch()), Camera::kMaxOrbitPitch + 1e-15);
    expect_near(c.target(), {1, 2, 3}, 0);
  }
  c.orbit(0, 1e6);
  EXPECT_DOUBLE_EQ(c.pitch(), Camera::kMaxOrbitPitch);
  // a preset on the pole stays there when orbiting further, and leaves it when orbiting back
  c.set_preset(ViewPreset::kTop);
  c.orbit(0, 10);
  EXPECT_DOUBLE_EQ(c.pitch(), 1.5707963267948966);
  c.orbit(0, -10);
  EXPECT_NEAR(c.pitch(), 1.5707963267948966 - 10 * Camera::kRadiansPerPixel, 1e-12);
}

TEST(Camera, DraggingRightTurnsTheModelRight) {
  Camera c;
  c.set_target({0, 0, 0});
  const glm::dvec3 nose(0, 0, 0.5);  // on the front of a model facing +Z
  const double before = c.project(nose, kW, kH).pixel.x;
  c.orbit(50, 0);
  EXPECT_GT(c.project(nose, kW, kH).pixel.x, before + 1);
  const glm::dvec3 crown(0, 0.5, 0);
  const double crown_y = c.project(crown, kW, kH).view_depth;
  c.orbit(0, 50);  // dragging down tips the top toward the viewer
  EXPECT_LT(c.project(crown, kW, kH).view_depth, crown_y);
}

TEST(Camera, ZoomIsMultiplicativeAndNeverPassesTheTarget) {
  Camera c;
  c.set_distance(4);
  c.zoom(1);
  EXPECT_NEAR(c.distance(), 4 / Camera::kZoomStep, 1e-12);
  c.zoom(-1);
  EXPECT_NEAR(c.distance(), 4, 1e-12);
  const glm::dvec3 side = c.eye() - c.target();
  for (int i = 0; i < 500; ++i) c.zoom(10);
  EXPECT_GE(c.distance(), Camera::kMinDistance);
  EXPECT_GT(glm::dot(c.eye() - c.target(), side), 0.0) << "the eye must stay on its side of the target";
  for (int i = 0; i < 500; ++i) c.zoom(-10);
  EXPECT_LE(c.distance(), Camera::kMaxDistance);
}

TEST(Camera, PresetsLookAlongTheAxes) {
  Camera c;
  struct Case {
    ViewPreset preset;
    glm::dvec3 forward, up;
  } cases[] = {
      {ViewPreset::kFront, {0, 0, -1}, {0, 1, 0}}, {ViewPreset::kBack, {0, 0, 1}, {0, 1, 0}},
      {ViewPreset::kRight, {-1, 0, 0}, {0, 1, 0}}, {ViewPreset::kLeft, {1, 0, 0}, {0, 1, 0}},
      {ViewPreset::kTop, {0, -1, 0}, {0, 0, -1}},  {ViewPreset::kBottom, {0, 1, 0}, {0, 0, 1}},
  };
  for (const Case& k : cases) {
    c.set_preset(k.preset);
    expect_near(c.forward(), k.forward, 1e-15);
    expect_near(c.up(), k.up, 1e-15);
    EXPECT_NEAR(glm::length(c.eye() - c.target()), c.distance(), 1e-12);
  }
}

}  // namespace
}  // namespace cagewrap
