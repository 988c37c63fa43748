// The editor's orbit camera (as in Maya and Blender): it circles a target at a distance, with yaw
// about the world Y axis and pitch above the horizon, perspective or orthographic. Headless view
// math: the GUI feeds it mouse deltas and reads matrices; picking reads rays and projections.
//
// Conventions: right-handed, Y up, the character faces +Z; OpenGL clip space (NDC z in [-1, 1]);
// pixel coordinates as GLFW gives the cursor: origin at the top-left corner of the viewport, x to
// the right, y down, continuous (the centre of the top-left pixel is (0.5, 0.5)). Matrices are in
// double precision; the renderer converts with glm::mat4(camera.view()).
#pragma once

#include <cstdint>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "core/geometry/mesh.h"
#include "core/geometry/ray.h"

namespace cagewrap {

enum class ProjectionMode : uint8_t { kPerspective, kOrthographic };

// Numpad-style views: front (1), back (ctrl 1), right (3), left (ctrl 3), top (7), bottom (ctrl 7).
// "Right" looks from +X toward -X (the character's left side faces it: it faces +Z).
enum class ViewPreset : uint8_t { kFront, kBack, kRight, kLeft, kTop, kBottom };


struct ScreenPoint {
  glm::dvec2 pixel{0.0};       // viewport pixels, origin top-left, y down
  double depth = 0.0;          // window depth in [0, 1] between the clip planes (what gl_FragCoord.z holds)
  double view_depth = 0.0;     // distance in front of the camera along its view direction (negative: behind)
  bool in_clip_range = false;  // in front of the camera and between the near and far planes
};

class Camera {
 public:
  static constexpr double kRadiansPerPixel = 0.005;       // orbit speed
  static constexpr double kMaxOrbitPitch = 1.5690509975;  // 89.9 degrees: orbit stops short of the poles
  static constexpr double kZoomStep = 1.15;               // distance factor per zoom step
  static constexpr double kMinDistance = 1e-5, kMaxDistance = 1e7;
  static constexpr double kFrameFill = 0.8;  // frame() fills this share of the viewport

  Camera() = default;

  // State.
  const glm::dvec3& target() const { return target_; }
  double distance() const { return distance_; }
  double yaw() const { return yaw_; }      // radians; 0 = looking from +Z toward -Z
  double pitch() const { return pitch_; }  // radians; > 0 = looking down from above
  double fov_y() const { return fov_y_; }  // vertical field of view, radians
  ProjectionMode mode() const { return mode_; }

  void set_target(const glm::dvec3& target) { target_ = target; }
  void set_distance(double distance);         // clamped to [kMinDistance, kMaxDistance]
  void set_angles(double yaw, double pitch);  // pitch clamped to [-pi/2, pi/2]
  void set_fov_y(double radians);             // clamped to [1, 170] degrees
  void set_mode(ProjectionMode mode) { mode_ = mode; }

  // Derived frame.
  glm::dvec3 eye() const;
  glm::dvec3 forward() const;  // unit view direction (from the eye toward the target)
  glm::dvec3 right() const;    // unit screen +x in world space
  glm::dvec3 up() const;       // unit screen up in world space
  double near_plane() const;   // distance of the near plane in front of the eye (negative in ortho)
  double far_plane() const;
  // World units per pixel at the target's depth for a viewport `viewport_height` pixels tall.
  double world_per_pixel(double viewport_height) const;

  // World -> eye (right-handed, camera looks down -Z).
  glm::dmat4 view() const;
  // Eye -> clip, OpenGL conventions. Orthographic keeps the apparent size of the target plane:
  // its half height is distance * tan(fov_y / 2).
  glm::dmat4 projection(double aspect) const;

  // Mouse navigation. dx, dy are pixel deltas (y down).
  // Grab-the-world orbit: dragging right turns the model to the right, dragging down tips its top
  // toward the viewer. The distance to the target is unchanged; pitch stops at kMaxOrbitPitch.
  void orbit(double dx, double dy);
  // Moves target and eye together so the point under the cursor (at the target's depth) follows it.
  void pan(double dx, double dy, double viewport_height);
  // Dolly: positive steps move toward the target, dividing the distance by kZoomStep per step;
  // never reaches or passes the target.
  void zoom(double steps);
  // Centres the box and sets the distance so the box's 8 corners fill kFrameFill of the viewport
  // (of its tighter dimension), keeping the view direction. An empty box frames the origin.
  void frame(const Aabb& box, double aspect);
  // Sets yaw and pitch to a preset view; keeps target, distance and projection mode.
  void set_preset(ViewPreset preset);

  // The world ray through a pixel (perspective: from the eye; orthographic: from the near plane,
  // along the view direction).
  Ray ray(double pixel_x, double pixel_y, double width, double height) const;
  // The ray from the camera through a world point, and the point's t along it (its distance from
  // the ray origin). Exact where ray(project(p)) would round.
  Ray ray_through(const glm::dvec3& world, double* t) const;
  // Where a world point lands on a width x height viewport.
  ScreenPoint project(const glm::dvec3& world, double width, double height) const;

 private:
  glm::dvec3 target_{0.0, 1.0, 0.0};
  double distance_ = 4.0;
  double yaw_ = 0.0;
  double pitch_ = 0.0;
  double fov_y_ = 0.7853981633974483;  // 45 degrees
  ProjectionMode mode_ = ProjectionMode::kPerspective;
};

}  // namespace cagewrap
