// Polygon meshes as flat arrays: the skin and the cage both use this.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "core/base/result.h"

namespace cagewrap {

struct Aabb {
  glm::dvec3 lo{1e300};
  glm::dvec3 hi{-1e300};
  void extend(const glm::dvec3& p);
  double diagonal() const;
  glm::dvec3 center() const { return 0.5 * (lo + hi); }
  bool empty() const { return lo.x > hi.x; }
};

using Tri = std::array<uint32_t, 3>;

struct PolyMesh {
  std::vector<glm::vec3> positions;     // #V x 3
  std::vector<uint32_t> face_start{0};  // #F+1 offsets into face_vertices
  std::vector<uint32_t> face_vertices;  // concatenated polygon corners

  size_t num_vertices() const { return positions.size(); }
  size_t num_faces() const { return face_start.size() - 1; }
  std::span<const uint32_t> face(size_t f) const {
    return {face_vertices.data() + face_start[f], face_start[f + 1] - face_start[f]};
  }
  void add_face(std::span<const uint32_t> corners);
  void add_face(std::initializer_list<uint32_t> corners) { add_face(std::span(corners.begin(), corners.size())); }
  bool all_triangles() const;
};

Aabb bounding_box(std::span<const glm::vec3> points);

// Checks every coordinate is finite and every corner index is in range; names `what` in messages.
Status validate_mesh(const PolyMesh& mesh, const std::string& what);

// Newell's normal of a polygon (not normalized; its length is twice the area of a planar polygon).
glm::dvec3 newell_normal(std::span<const glm::vec3> positions, std::span<const uint32_t> corners);

// Triangulates every polygon (ear clipping in the polygon's best-fit plane, fan as a fallback).
// #T triangles and, for each, the polygon it came from.
struct Triangulation {
  std::vector<Tri> triangles;
  std::vector<uint32_t> source_face;
};
Triangulation triangulate(const PolyMesh& mesh);

// Mean length of the unique polygon edges (the default distance scale h).
double mean_edge_length(const PolyMesh& mesh);

// Polygon edges without the internal triangulation diagonals, each once (a < b).
std::vector<std::array<uint32_t, 2>> unique_edges(const PolyMesh& mesh);

}  // namespace cagewrap
