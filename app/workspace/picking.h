// What is under the cursor: the ray casts and screen-space searches the editor's tools use
// (select a skin point, a cage vertex, a cage polygon, a joint; rectangle selection). Headless, so
// each answer can be tested on hand-built scenes. Pixels are viewport pixels as in camera.h
// (origin top-left, y down).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "app/workspace/camera.h"
#include "core/geometry/mesh.h"
#include "core/geometry/triangle_bvh.h"

namespace cagewrap {

// The viewport a pick happens in.
struct Viewport {
  double width = 1.0, height = 1.0;  // pixels
};

// Nearest triangle hit by the ray (t >= 0), through a hierarchy kept for repeated picks.
std::optional<TriangleHit> pick_triangle(const Ray& ray, const TriangleBvh& bvh);
// One-off: builds a hierarchy over positions (#V x 3) and triangles (#T x 3) for a single ray.
std::optional<TriangleHit> pick_triangle(const Ray& ray, std::span<const glm::vec3> positions,
                                         std::span<const Tri> triangles);

// Whether a world point is hidden behind `occluder` as seen by the camera: something is hit
// before it by more than a small tolerance (relative to the occluder's size), so a point lying
// on the occluding surface itself stays visible.
bool is_occluded(const Camera& camera, const glm::dvec3& point, const TriangleBvh& occluder);

// The vertex whose projection is nearest to `pixel` and within radius_px of it, among those in the
// clip range and, when an occluder is given, not hidden behind it. Ties go to the one nearer the
// camera, then the lower index.
std::optional<uint32_t> pick_vertex(const Camera& camera, Viewport viewport, glm::dvec2 pixel,
                                    std::span<const glm::vec3> positions, double radius_px,
                                    const TriangleBvh* occluder = nullptr);

// Indices (ascending) of the points whose projection lies in the rectangle spanned by two
// opposite corners (any order, edges inclusive), that are in the clip range and, when an occluder is
// given, not hidden behind it.
std::vector<uint32_t> box_select(const Camera& camera, Viewport viewport, glm::dvec2 corner_a,
                                 glm::dvec2 corner_b, std::span<const glm::vec3> positions,
                                 const TriangleBvh* occluder = nullptr);

// Joints are drawn over the mesh, so they are picked without occlusion: the joint whose projection
// is nearest to `pixel` within radius_px (ties: nearer the camera, then lower index).
std::optional<uint32_t> pick_joint(const Camera& camera, Viewport viewport, glm::dvec2 pixel,
                                   std::span<const glm::vec3> joint_positions, double radius_px);

struct FaceHit {
  uint32_t face = 0;  // the polygon of the PolyMesh
  TriangleHit hit;    // the internal triangle hit (hit.triangle indexes the triangulation)
};

// Picks polygons of a PolyMesh (the cage) through its internal triangulation: the user sees and
// selects polygons, never the triangles. Keep one per cage; refit when its vertices move.
class PolygonPicker {
 public:
  PolygonPicker() = default;
  explicit PolygonPicker(const PolyMesh& mesh);
  void refit(std::span<const glm::vec3> positions) { bvh_.refit(positions); }
  std::optional<FaceHit> pick(const Ray& ray) const;
  // The triangulated surface, usable as an occluder for pick_vertex and box_select.
  const TriangleBvh& bvh() const { return bvh_; }

 private:
  TriangleBvh bvh_;
  std::vector<uint32_t> source_face_;  // #T polygon of each internal triangle
};

// One-off form of PolygonPicker::pick.
std::optional<FaceHit> pick_polygon_face(const Ray& ray, const PolyMesh& mesh);

}  // namespace cagewrap
