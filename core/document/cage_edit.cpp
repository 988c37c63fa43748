#include "core/document/cage_edit.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>

#include "core/geometry/weld.h"

namespace cagewrap {

namespace {

std::string format_number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

// Merges vertex clusters: remap (#V) gives each old vertex its new id (0..count-1).
Result<CageEdit> merge_clusters(const Cage& cage, std::span<const uint32_t> remap, uint32_t count) {
  const PolyMesh& old = cage.polygons;
  CageTopologyChange change = identity_change(cage);
  // vertices: each new vertex is the centroid of its cluster
  std::vector<std::vector<uint32_t>> members(count);
  for (uint32_t v = 0; v < remap.size(); ++v) members[remap[v]].push_back(v);
  PolyMesh out;
  out.positions.resize(count);
  change.vertex_offsets.assign(1, 0);
  change.vertex_parents.clear();
  change.vertex_weights.clear();
  for (uint32_t n = 0; n < count; ++n) {
    glm::dvec3 sum(0.0);
    const double w = 1.0 / static_cast<double>(members[n].size());
    for (uint32_t v : members[n]) {
      sum += glm::dvec3(old.positions[v]);
      change.vertex_parents.push_back(v);
      change.vertex_weights.push_back(w);
    }
    out.positions[n] = glm::vec3(sum * w);
    change.vertex_offsets.push_back(static_cast<uint32_t>(change.vertex_parents.size()));
  }
  // faces
  change.face_parent.clear();
  std::vector<glm::dvec3> domain;
  std::vector<std::string> warnings;
  std::map<std::vector<uint32_t>, uint32_t> seen;  // sorted corners -> old face
  std::vector<uint32_t> corners, old_corners, key;
  for (uint32_t f = 0; f < old.num_faces(); ++f) {
    corners.clear();
    old_corners.clear();
    for (uint32_t c : old.face(f)) {
      if (!corners.empty() && corners.back() == remap[c]) continue;
      corners.push_back(remap[c]);
      old_corners.push_back(c);
    }
    while (corners.size() > 1 && corners.back() == corners.front()) {
      corners.pop_back();
      old_corners.pop_back();
    }
    const std::string name = "face " + std::to_string(f);
    if (corners.size() < 3) {
      warnings.push_back(name + " collapsed (" + std::to_string(corners.size()) +
                         " distinct corners left) and was dropped");
      continue;
    }
    key = corners;
    std::sort(key.begin(), key.end());
    if (std::adjacent_find(key.begin(), key.end()) != key.end()) {
      warnings.push_back(name + " passes through a merged vertex twice and was dropped");
      continue;
    }
    auto [it, fresh] = seen.emplace(key, f);
    if (!fresh) {
      warnings.push_back(name + " now has the same corners as face " + std::to_string(it->second) +
                         " and was dropped");
      continue;
    }
    out.add_face(corners);
    change.face_parent.push_back(f);
    for (uint32_t c : old_corners) domain.emplace_back(old.positions[c]);
  }
  if (out.num_faces() == 0)
    return make_error(ErrorCode::kEmpty, "merging the vertices collapses every face of the cage");
  return make_cage_edit(cage, std::move(out), std::move(change), domain, std::move(warnings));
}

}  // namespace

Result<CageEdit> merge_vertices(const Cage& cage, std::span<const uint32_t> vertices) {
  if (auto s = validate_mesh(cage.polygons, "cage"); !s) return s.error();
  auto mask = selection_mask(vertices, cage.num_vertices(), "vertex", "merge");
  if (!mask) return mask.error();
  const std::vector<uint8_t>& merged = *mask;
  const uint32_t target = *std::min_element(vertices.begin(), vertices.end());
  std::vector<uint32_t> remap(cage.num_vertices());
  uint32_t count = 0;
  for (uint32_t v = 0; v < remap.size(); ++v) remap[v] = merged[v] && v != target ? remap[target] : count++;
  return merge_clusters(cage, remap, count);
}

Result<CageEdit> weld_cage_vertices(const Cage& cage, double distance) {
  if (!(distance > 0) || !std::isfinite(distance))
    return make_error(ErrorCode::kInvalidArgument,
                      "the weld distance must be positive and finite, not " + format_number(distance));
  if (auto s = validate_mesh(cage.polygons, "cage"); !s) return s.error();
  Weld w = weld_vertices(cage.polygons.positions, distance);
  return merge_clusters(cage, w.remap, static_cast<uint32_t>(w.positions.size()));
}

Result<CageEdit> flip_faces(const Cage& cage, std::span<const uint32_t> faces) {
  if (auto s = validate_mesh(cage.polygons, "cage"); !s) return s.error();
  auto flip = selection_mask(faces, cage.polygons.num_faces(), "face", "flip");
  if (!flip) return flip.error();
  const PolyMesh& old = cage.polygons;
  PolyMesh out;
  out.positions = old.positions;
  std::vector<glm::dvec3> domain;
  domain.reserve(old.face_vertices.size());
  std::vector<uint32_t> corners;
  for (size_t f = 0; f < old.num_faces(); ++f) {
    auto c = old.face(f);
    corners.assign(c.begin(), c.end());
    if ((*flip)[f]) std::reverse(corners.begin() + 1, corners.end());
    out.add_face(corners);
    for (uint32_t v : corners) domain.emplace_back(old.positions[v]);
  }
  return make_cage_edit(cage, std::move(out), identity_change(cage), domain, {});
}

Result<CageEdit> flip_all_faces(const Cage& cage) {
  std::vector<uint32_t> all(cage.polygons.num_faces());
  for (uint32_t f = 0; f < all.size(); ++f) all[f] = f;
  return flip_faces(cage, all);
}

Result<CageEdit> triangulate_cage(const Cage& cage) {
  if (auto s = validate_mesh(cage.polygons, "cage"); !s) return s.error();
  PolyMesh out;
  out.positions = cage.polygons.positions;
  for (const Tri& t : cage.elements) out.add_face(t);
  auto made = make_cage(std::move(out), "triangulated cage");
  if (!made) return made.error();
  CageEdit edit{std::move(made).value(), identity_change(cage), {}};
  edit.change.face_parent = cage.element_face;  // elements map one to one (identity_change)
  set_dropped_faces(edit.change);
  return edit;
}

}  // namespace cagewrap
