#include "app/workspace/picking.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

namespace cagewrap {

namespace {
// Occlusion tolerance: relative to the occluder's bounding-box diagonal.
constexpr double kOcclusionTolerance = 1e-4;

// Projects many points with one matrix (Camera::project recomputes its matrices per call).
class Projector {
 public:
  Projector(const Camera& camera, Viewport viewport)
      : w_(std::max(viewport.width, 1.0)),
        h_(std::max(viewport.height, 1.0)),
        view_(camera.view()),
        proj_(camera.projection(w_ / h_)),
        near_(camera.near_plane()),
        far_(camera.far_plane()) {}

  // False when the point is outside the clip range; else its pixel and view depth.
  bool project(const glm::vec3& p, glm::dvec2& pixel, double& view_depth) const {
    const glm::dvec4 e = view_ * glm::dvec4(glm::dvec3(p), 1.0);
    view_depth = -e.z;
    if (!(view_depth >= near_ && view_depth <= far_)) return false;
    const glm::dvec4 c = proj_ * e;
    pixel = {0.5 * (c.x / c.w + 1.0) * w_, 0.5 * (1.0 - c.y / c.w) * h_};
    return true;
  }

 private:
  double w_, h_;
  glm::dmat4 view_, proj_;
  double near_, far_;
};

struct Candidate {
  double dist2, depth;
  uint32_t index;
  bool operator<(const Candidate& o) const {
    if (dist2 != o.dist2) return dist2 < o.dist2;
    if (depth != o.depth) return depth < o.depth;
    return index < o.index;
  }
};

std::optional<uint32_t> nearest_on_screen(const Camera& camera, Viewport viewport, glm::dvec2 pixel,
                                          std::span<const glm::vec3> positions, double radius_px,
                                          const TriangleBvh* occluder) {
  const Projector proj(camera, viewport);
  const double r2 = radius_px * radius_px;
  std::vector<Candidate> cands;
  for (size_t i = 0; i < positions.size(); ++i) {
    glm::dvec2 px;
    double depth;
    if (!proj.project(positions[i], px, depth)) continue;
    const glm::dvec2 d = px - pixel;
    const double d2 = glm::dot(d, d);
    if (d2 <= r2) cands.push_back({d2, depth, static_cast<uint32_t>(i)});
  }
  std::sort(cands.begin(), cands.end());
  // occlusion rays only for the candidates, nearest first
  for (const Candidate& c : cands)
    if (!occluder || !is_occluded(camera, glm::dvec3(positions[c.index]), *occluder)) return c.index;
  return std::nullopt;
}
}  // namespace

std::optional<TriangleHit> pick_triangle(const Ray& ray, const TriangleBvh& bvh) {
  return bvh.intersect(ray);
}

std::optional<TriangleHit> pick_triangle(const Ray& ray, std::span<const glm::vec3> positions,
                                         std::span<const Tri> triangles) {
  return TriangleBvh(positions, triangles).intersect(ray);
}

bool is_occluded(const Camera& camera, const glm::dvec3& point, const TriangleBvh& occluder) {
  double t = 0.0;
  const Ray ray = camera.ray_through(point, &t);
  const double tolerance = kOcclusionTolerance * occluder.bounds().diagonal() + 1e-9 * std::abs(t);
  return t - tolerance > 0.0 && occluder.any_hit(ray, 0.0, t - tolerance);
}

std::optional<uint32_t> pick_vertex(const Camera& camera, Viewport viewport, glm::dvec2 pixel,
                                    std::span<const glm::vec3> positions, double radius_px,
                                    const TriangleBvh* occluder) {
  return nearest_on_screen(camera, viewport, pixel, positions, radius_px, occluder);
}

std::optional<uint32_t> pick_joint(const Camera& camera, Viewport viewport, glm::dvec2 pixel,
                                   std::span<const glm::vec3> joint_positions, double radius_px) {
  return nearest_on_screen(camera, viewport, pixel, joint_positions, radius_px, nullptr);
}

std::vector<uint32_t> box_select(const Camera& camera, Viewport viewport, glm::dvec2 corner_a,
                                 glm::dvec2 corner_b, std::span<const glm::vec3> positions,
                                 const TriangleBvh* occluder) {
  const Projector proj(camera, viewport);
  const glm::dvec2 lo = glm::min(corner_a, corner_b), hi = glm::max(corner_a, corner_b);
  std::vector<uint32_t> out;
  for (size_t i = 0; i < positions.size(); ++i) {
    glm::dvec2 px;
    double depth;
    if (!proj.project(positions[i], px, depth)) continue;
    if (px.x < lo.x || px.x > hi.x || px.y < lo.y || px.y > hi.y) continue;
    if (occluder && is_occluded(camera, glm::dvec3(positions[i]), *occluder)) continue;
    out.push_back(static_cast<uint32_t>(i));
  }
  return out;
}

PolygonPicker::PolygonPicker(const PolyMesh& mesh) {
  Triangulation tri = triangulate(mesh);
  bvh_ = TriangleBvh(mesh.positions, tri.triangles);
  source_face_ = std::move(tri.source_face);
}

std::optional<FaceHit> PolygonPicker::pick(const Ray& ray) const {
  auto hit = bvh_.intersect(ray);
  if (!hit) return std::nullopt;
  return FaceHit{source_face_[hit->triangle], *hit};
}

std::optional<FaceHit> pick_polygon_face(const Ray& ray, const PolyMesh& mesh) {
  return PolygonPicker(mesh).pick(ray);
}

}  // namespace cagewrap
