#include "core/cage/cage.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_set>

#include <glm/geometric.hpp>

namespace cagewrap {

const char* element_status_name(ElementStatus s) {
  switch (s) {
    case ElementStatus::kValid: return "valid";
    case ElementStatus::kDegenerate: return "zero area";
    case ElementStatus::kNonFinite: return "non-finite";
    case ElementStatus::kDuplicate: return "duplicate";
  }
  return "?";
}

Result<Cage> make_cage(PolyMesh polygons, const std::string& what) {
  if (polygons.num_faces() == 0) return make_error(ErrorCode::kEmpty, what + ": cage has no faces");
  for (size_t f = 0; f < polygons.num_faces(); ++f)
    for (uint32_t c : polygons.face(f))
      if (c >= polygons.num_vertices())
        return make_error(ErrorCode::kIndexOutOfRange, what + ": face " + std::to_string(f) + " uses vertex " +
                                                           std::to_string(c) + " but the cage has only " +
                                                           std::to_string(polygons.num_vertices()) + " vertices");
  Cage cage;
  auto t = triangulate(polygons);
  cage.polygons = std::move(polygons);
  cage.elements = std::move(t.triangles);
  cage.element_face = std::move(t.source_face);
  return cage;
}

std::vector<ElementStatus> classify_elements(const Cage& cage, std::span<const glm::vec3> positions) {
  std::vector<ElementStatus> status(cage.num_elements(), ElementStatus::kValid);
  std::map<std::array<uint32_t, 3>, uint32_t> by_index;
  std::map<std::array<float, 9>, uint32_t> by_position;
  for (size_t e = 0; e < cage.num_elements(); ++e) {
    const Tri& t = cage.elements[e];
    glm::dvec3 a(positions[t[0]]), b(positions[t[1]]), c(positions[t[2]]);
    bool finite = true;
    for (int i = 0; i < 3; ++i)
      finite = finite && std::isfinite(a[i]) && std::isfinite(b[i]) && std::isfinite(c[i]);
    if (!finite) {
      status[e] = ElementStatus::kNonFinite;
      continue;
    }
    double longest2 = std::max({glm::dot(b - a, b - a), glm::dot(c - a, c - a), glm::dot(c - b, c - b)});
    double area2 = glm::length(glm::cross(b - a, c - a));
    if (longest2 == 0.0 || area2 <= kDegenerateRatio * longest2) {
      status[e] = ElementStatus::kDegenerate;
      continue;
    }
    std::array<uint32_t, 3> key = t;
    std::sort(key.begin(), key.end());
    if (!by_index.emplace(key, static_cast<uint32_t>(e)).second) {
      status[e] = ElementStatus::kDuplicate;
      continue;
    }
    std::array<std::array<float, 3>, 3> corners = {{{positions[t[0]].x, positions[t[0]].y, positions[t[0]].z},
                                                    {positions[t[1]].x, positions[t[1]].y, positions[t[1]].z},
                                                    {positions[t[2]].x, positions[t[2]].y, positions[t[2]].z}}};
    std::sort(corners.begin(), corners.end());
    std::array<float, 9> pkey;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) pkey[static_cast<size_t>(3 * i + j)] = corners[static_cast<size_t>(i)][static_cast<size_t>(j)];
    if (!by_position.emplace(pkey, static_cast<uint32_t>(e)).second) status[e] = ElementStatus::kDuplicate;
  }
  return status;
}

}  // namespace cagewrap
