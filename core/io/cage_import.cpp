#include "core/io/cage_import.h"

#include <algorithm>
#include <map>

#include "core/io/gltf_loader.h"
#include "core/geometry/mesh_io.h"

namespace cagewrap {

namespace {

bool ends_with(std::string s, const std::string& suffix) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

Result<PolyMesh> load_cage_mesh(const std::string& path) {
  if (!ends_with(path, ".gltf") && !ends_with(path, ".glb")) return load_mesh(path);
  auto ch = load_character(path);
  if (!ch) return ch.error();
  PolyMesh m;
  for (const auto& prim : ch->primitives) {
    const auto base = static_cast<uint32_t>(m.positions.size());
    m.positions.insert(m.positions.end(), prim.positions.begin(), prim.positions.end());
    for (const Tri& t : prim.triangles) m.add_face({t[0] + base, t[1] + base, t[2] + base});
  }
  if (m.num_faces() == 0) return Error{ErrorCode::kEmpty, path + ": the glTF file has no triangles to use as a cage"};
  return m;
}

CageProblems find_cage_problems(const Cage& cage, size_t max_lines) {
  CageProblems out;
  auto line = [&](std::string s) {
    if (out.lines.size() < max_lines) out.lines.push_back(std::move(s));
  };
  const PolyMesh& m = cage.polygons;
  const auto status = classify_elements(cage, m.positions);
  for (size_t e = 0; e < status.size(); ++e) {
    if (status[e] == ElementStatus::kValid) continue;
    ++out.bad_elements;
    line("element " + std::to_string(e) + " (face " + std::to_string(cage.element_face[e]) + "): " + element_status_name(status[e]) +
         " - skipped by the bind");
  }
  // polygon edges: how many faces use each, and in which directions
  struct Use {
    uint32_t forward = 0, backward = 0;
    uint32_t first_face = 0;
  };
  std::map<std::pair<uint32_t, uint32_t>, Use> edges;
  std::vector<bool> used(m.num_vertices(), false);
  for (size_t f = 0; f < m.num_faces(); ++f) {
    auto c = m.face(f);
    for (size_t i = 0; i < c.size(); ++i) {
      const uint32_t a = c[i], b = c[(i + 1) % c.size()];
      used[a] = true;
      if (a == b) continue;
      Use& u = edges[{std::min(a, b), std::max(a, b)}];
      if (u.forward + u.backward == 0) u.first_face = static_cast<uint32_t>(f);
      (a < b ? u.forward : u.backward)++;
    }
  }
  for (const auto& [e, u] : edges) {
    const std::string name = "edge " + std::to_string(e.first) + "-" + std::to_string(e.second);
    const uint32_t n = u.forward + u.backward;
    if (n == 1) {
      ++out.open_edges;
      line(name + " (face " + std::to_string(u.first_face) + "): open boundary, used by one face");
    } else if (n > 2) {
      ++out.non_manifold_edges;
      line(name + ": non-manifold, shared by " + std::to_string(n) + " faces");
    } else if (u.forward == 2 || u.backward == 2) {
      ++out.misoriented_edges;
      line(name + " (face " + std::to_string(u.first_face) + " and its neighbour): the two faces disagree on orientation");
    }
  }
  for (size_t v = 0; v < used.size(); ++v)
    if (!used[v]) {
      ++out.unused_vertices;
      line("vertex " + std::to_string(v) + ": in no face");
    }
  return out;
}

}  // namespace cagewrap
