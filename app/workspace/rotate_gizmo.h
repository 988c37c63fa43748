// The rotation gizmo's geometry, headless: three rings about a joint's local axes and an outer ring
// about the view direction, which one the cursor is over, and what angle a drag means. The angle is
// measured where the mouse rays meet the ring's plane, so the grabbed point follows the cursor;
// when the plane is seen edge-on it falls back to the angle swept around the projected centre.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "app/workspace/camera.h"
#include "app/workspace/picking.h"

namespace cagewrap {

enum class RotateHandle : int8_t { kNone = -1, kX, kY, kZ, kView };

inline constexpr double kRotateRingPixels = 70.0;  // on-screen radius of the axis rings
inline constexpr double kRotateViewRingShare = 1.2;  // the view ring is this much larger

struct RotateGizmoLayout {
  bool visible = false;
  glm::dvec2 centre{0.0};                       // viewport pixels
  glm::dvec3 world_centre{0.0};
  double world_radius = 0.0;                    // ring radius in world units at the centre
  glm::dmat3 axes{1.0};                         // columns: the ring axes in world space (unit)
  std::array<std::vector<glm::dvec2>, 3> rings;  // closed polylines, viewport pixels
  std::array<std::vector<bool>, 3> front;        // per ring point: on the half facing the camera
  std::vector<glm::dvec2> view_ring;
};

// `axes`: columns are the joint's local X, Y, Z in world space (normalized here).
RotateGizmoLayout rotate_gizmo_layout(const Camera& camera, Viewport viewport, const glm::dvec3& centre,
                                      const glm::dmat3& axes, int segments = 72);

// The ring under `pixel` (within a few pixels; only the front half of the axis rings is grabbable).
RotateHandle rotate_gizmo_hit(const RotateGizmoLayout& layout, glm::dvec2 pixel);

// World axis a handle turns about (the view ring: toward the viewer).
glm::dvec3 rotate_handle_axis(const Camera& camera, const RotateGizmoLayout& layout, RotateHandle handle);

// The signed angle (radians, right-handed about the handle's world axis) of a drag from pixel
// `from` to `to`; nullopt for kNone.
std::optional<double> rotate_gizmo_angle(const Camera& camera, Viewport viewport, const RotateGizmoLayout& layout,
                                         RotateHandle handle, glm::dvec2 from, glm::dvec2 to);

// Rounds to multiples of `step` radians (> 0; otherwise unchanged).
double snap_angle(double angle, double step);

}  // namespace cagewrap
