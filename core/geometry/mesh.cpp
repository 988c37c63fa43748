#include "core/geometry/mesh.h"

#include <algorithm>
#include <cmath>
#include <unordered_set>

#include <glm/geometric.hpp>

namespace cagewrap {

void Aabb::extend(const glm::dvec3& p) {
  lo = glm::min(lo, p);
  hi = glm::max(hi, p);
}

double Aabb::diagonal() const { return empty() ? 0.0 : glm::length(hi - lo); }

void PolyMesh::add_face(std::span<const uint32_t> corners) {
  face_vertices.insert(face_vertices.end(), corners.begin(), corners.end());
  face_start.push_back(static_cast<uint32_t>(face_vertices.size()));
}

bool PolyMesh::all_triangles() const {
  for (size_t f = 0; f < num_faces(); ++f)
    if (face_start[f + 1] - face_start[f] != 3) return false;
  return true;
}

Aabb bounding_box(std::span<const glm::vec3> points) {
  Aabb box;
  for (const auto& p : points) box.extend(glm::dvec3(p));
  return box;
}

Status validate_mesh(const PolyMesh& mesh, const std::string& what) {
  if (mesh.positions.empty()) return make_error(ErrorCode::kEmpty, what + ": has no vertices");
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    const auto& p = mesh.positions[v];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      return make_error(ErrorCode::kNonFinite, what + ": vertex " + std::to_string(v) +
                                                   " has a non-finite coordinate");
  }
  if (mesh.face_start.empty() || mesh.face_start.back() != mesh.face_vertices.size())
    return make_error(ErrorCode::kParse, what + ": face table is inconsistent");
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    auto corners = mesh.face(f);
    if (corners.size() < 3)
      return make_error(ErrorCode::kParse,
                        what + ": face " + std::to_string(f) + " has fewer than 3 corners");
    for (uint32_t c : corners)
      if (c >= mesh.positions.size())
        return make_error(ErrorCode::kIndexOutOfRange,
                          what + ": face " + std::to_string(f) + " uses vertex " + std::to_string(c) +
                              " but there are only " + std::to_string(mesh.positions.size()) +
                              " vertices");
  }
  return Ok{};
}

glm::dvec3 newell_normal(std::span<const glm::vec3> positions, std::span<const uint32_t> corners) {
  const size_t n = corners.size();
  glm::dvec3 normal(0.0);
  for (size_t i = 0; i < n; ++i) {
    glm::dvec3 a(positions[corners[i]]), b(positions[corners[(i + 1) % n]]);
    normal += glm::dvec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
  }
  return normal;
}

namespace {

// Ear clipping of one polygon projected on its Newell plane; false when it finds no ear.
bool ear_clip(const PolyMesh& mesh, std::span<const uint32_t> corners, std::vector<Tri>& out) {
  const size_t n = corners.size();
  glm::dvec3 normal = newell_normal(mesh.positions, corners);
  if (glm::length(normal) == 0.0) return false;
  normal = glm::normalize(normal);
  glm::dvec3 u = std::abs(normal.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  u = glm::normalize(glm::cross(normal, u));
  glm::dvec3 v = glm::cross(normal, u);
  std::vector<std::array<double, 2>> p(n);
  for (size_t i = 0; i < n; ++i) {
    glm::dvec3 q(mesh.positions[corners[i]]);
    p[i] = {glm::dot(q, u), glm::dot(q, v)};
  }
  auto cross2 = [&](size_t a, size_t b, size_t c) {
    return (p[b][0] - p[a][0]) * (p[c][1] - p[a][1]) - (p[b][1] - p[a][1]) * (p[c][0] - p[a][0]);
  };
  std::vector<size_t> ring(n);
  for (size_t i = 0; i < n; ++i) ring[i] = i;
  std::vector<Tri> tris;
  while (ring.size() > 3) {
    bool clipped = false;
    for (size_t i = 0; i < ring.size() && !clipped; ++i) {
      size_t a = ring[(i + ring.size() - 1) % ring.size()], b = ring[i], c = ring[(i + 1) % ring.size()];
      if (cross2(a, b, c) <= 0) continue;  // reflex or flat corner
      bool contains = false;
      for (size_t j : ring) {
        if (j == a || j == b || j == c) continue;
        if (cross2(a, b, j) >= 0 && cross2(b, c, j) >= 0 && cross2(c, a, j) >= 0) {
          contains = true;
          break;
        }
      }
      if (contains) continue;
      tris.push_back({corners[a], corners[b], corners[c]});
      ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(i));
      clipped = true;
    }
    if (!clipped) return false;
  }
  tris.push_back({corners[ring[0]], corners[ring[1]], corners[ring[2]]});
  out.insert(out.end(), tris.begin(), tris.end());
  return true;
}

}  // namespace

Triangulation triangulate(const PolyMesh& mesh) {
  Triangulation t;
  t.triangles.reserve(mesh.face_vertices.size());
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    auto corners = mesh.face(f);
    if (corners.size() == 3) {
      t.triangles.push_back({corners[0], corners[1], corners[2]});
    } else if (corners.size() > 3 && !ear_clip(mesh, corners, t.triangles)) {
      for (size_t i = 1; i + 1 < corners.size(); ++i)
        t.triangles.push_back({corners[0], corners[i], corners[i + 1]});
    }
    t.source_face.resize(t.triangles.size(), static_cast<uint32_t>(f));
  }
  return t;
}

std::vector<std::array<uint32_t, 2>> unique_edges(const PolyMesh& mesh) {
  std::vector<std::array<uint32_t, 2>> edges;
  edges.reserve(mesh.face_vertices.size());
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    auto c = mesh.face(f);
    for (size_t i = 0; i < c.size(); ++i) {
      uint32_t a = c[i], b = c[(i + 1) % c.size()];
      if (a == b) continue;
      edges.push_back({std::min(a, b), std::max(a, b)});
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return edges;
}

double mean_edge_length(const PolyMesh& mesh) {
  auto edges = unique_edges(mesh);
  double sum = 0.0;
  size_t count = 0;
  for (auto [a, b] : edges) {
    double len = glm::length(glm::dvec3(mesh.positions[a]) - glm::dvec3(mesh.positions[b]));
    if (std::isfinite(len)) {
      sum += len;
      ++count;
    }
  }
  return count ? sum / static_cast<double>(count) : 0.0;
}

}  // namespace cagewrap
