// The set-painting brush on the skin: the points within a radius of the hit point measured along the
// surface (graph distance over mesh edges, Dijkstra from the hit triangle's corners), so a stroke on
// the inner thigh does not jump across the gap to the other leg the way a sphere would. The radius is
// in world units: the editor converts its screen radius at the hit depth (camera.h).
#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <span>
#include <vector>

#include "core/geometry/mesh.h"
#include "core/base/result.h"

namespace cagewrap {

struct BrushPoints {
  std::vector<uint32_t> points;  // ascending
  std::vector<float> distance;   // #points: surface distance from the hit point, in [0, radius]
};

// Keeps the skin's edge graph, built once; each dab costs only the points it reaches.
class SkinBrush {
 public:
  SkinBrush() = default;
  // positions #V x 3 (the positions distances are measured on: rest or posed), triangles #T x 3.
  // Triangles with an index out of range are ignored.
  SkinBrush(std::span<const glm::vec3> positions, std::span<const Tri> triangles);

  size_t num_points() const { return positions_.size(); }
  size_t num_triangles() const { return triangles_.size(); }

  // Every point whose distance along mesh edges from `hit_point` is at most `radius`, where the
  // hit point (on triangle `triangle`) reaches that triangle's corners in a straight line. Errors: a
  // triangle out of range, a radius that is negative or not finite, a non-finite hit point.
  Result<BrushPoints> points_within(uint32_t triangle, const glm::dvec3& hit_point, double radius);

 private:
  std::vector<glm::vec3> positions_;
  std::vector<Tri> triangles_;
  std::vector<uint32_t> start_;      // #V+1 adjacency offsets
  std::vector<uint32_t> neighbour_;  // each undirected edge twice
  std::vector<float> length_;        // edge lengths, with neighbour_
  std::vector<double> dist_;         // #V scratch, infinity between calls
  std::vector<uint32_t> reached_;    // scratch: vertices whose dist_ was set
};

}  // namespace cagewrap
