// The move gizmo's geometry, headless: where its handles are on screen, which one the cursor is
// over, and what world displacement a drag from one pixel to another means. Axis drags follow the
// cursor along the axis (closest point between the mouse ray and the axis line), plane and screen
// drags keep the grabbed point under the cursor (ray-plane intersection), so a drag never drifts
// however the mouse moves and the editor and the tests share one answer.
#pragma once

#include <array>
#include <cstdint>
#include <optional>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "app/workspace/camera.h"
#include "app/workspace/picking.h"

namespace cagewrap {

enum class GizmoHandle : int8_t {
  kNone = -1,
  kX,
  kY,
  kZ,
  kPlaneYZ,  // moves in the plane normal to X
  kPlaneXZ,  // normal to Y
  kPlaneXY,  // normal to Z
  kScreen,   // the plane facing the camera
};

struct GizmoLayout {
  bool visible = false;
  glm::dvec2 centre{0.0};                        // viewport pixels
  std::array<glm::dvec2, 3> axis_end{};          // X, Y, Z handle tips
  std::array<std::array<glm::dvec2, 4>, 3> plane{};  // YZ, XZ, XY squares (corners in order)
  double world_length = 0.0;                     // world length of an axis at the centre's depth
};

inline constexpr double kGizmoAxisPixels = 80.0;  // on-screen length of an axis handle
inline constexpr double kGizmoPlaneShare = 0.3;   // plane squares span this share of the axes

// Handles for a gizmo at world point `centre`; invisible when the centre is behind the camera.
GizmoLayout gizmo_layout(const Camera& camera, Viewport viewport, const glm::dvec3& centre);

// The handle under `pixel` (within a few pixels of an axis, inside a plane square or the centre
// box), kNone otherwise. The centre box wins over planes, planes over axes.
GizmoHandle gizmo_hit(const GizmoLayout& layout, glm::dvec2 pixel);

// The world displacement of a drag of `handle` that started at pixel `from` and is now at `to`,
// for a gizmo at `centre` (where it was when the drag began). nullopt when the ray is parallel to
// the plane or axis (the drag then holds its last value).
std::optional<glm::dvec3> gizmo_drag(const Camera& camera, Viewport viewport, GizmoHandle handle,
                                     const glm::dvec3& centre, glm::dvec2 from, glm::dvec2 to);

// Rounds the displacement to multiples of `step` (> 0) along the handle's free directions.
glm::dvec3 snap_displacement(const glm::dvec3& d, double step);

}  // namespace cagewrap
