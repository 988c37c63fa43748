#include "core/document/cage_subdivide.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <unordered_map>

#include "core/document/cage_edit.h"

namespace cagewrap {

namespace {

// The polygon edges of a mesh, each once, with the faces around them.
struct EdgeTable {
  std::vector<uint32_t> corner_edge;          // per corner (face_vertices index): edge to the next corner
  std::vector<std::array<uint32_t, 2>> ends;  // #E, a < b, in order of first use
  std::vector<uint32_t> face_offsets, faces;  // edge -> faces using it (CSR)
  size_t num_edges() const { return ends.size(); }
  std::span<const uint32_t> faces_of(size_t e) const {
    return {faces.data() + face_offsets[e], face_offsets[e + 1] - face_offsets[e]};
  }
};

EdgeTable build_edges(const PolyMesh& m) {
  EdgeTable t;
  t.corner_edge.resize(m.face_vertices.size());
  std::unordered_map<uint64_t, uint32_t> index;
  index.reserve(m.face_vertices.size());
  std::vector<uint32_t> count;
  for (size_t f = 0; f < m.num_faces(); ++f) {
    auto c = m.face(f);
    for (size_t i = 0; i < c.size(); ++i) {
      const uint32_t a = std::min(c[i], c[(i + 1) % c.size()]), b = std::max(c[i], c[(i + 1) % c.size()]);
      auto [it, fresh] = index.emplace((uint64_t(a) << 32) | b, static_cast<uint32_t>(t.ends.size()));
      if (fresh) {
        t.ends.push_back({a, b});
        count.push_back(0);
      }
      ++count[it->second];
      t.corner_edge[m.face_start[f] + i] = it->second;
    }
  }
  t.face_offsets.assign(t.ends.size() + 1, 0);
  for (size_t e = 0; e < t.ends.size(); ++e) t.face_offsets[e + 1] = t.face_offsets[e] + count[e];
  t.faces.resize(t.face_offsets.back());
  std::vector<uint32_t> fill(t.face_offsets.begin(), t.face_offsets.end() - 1);
  for (size_t f = 0; f < m.num_faces(); ++f)
    for (uint32_t k = m.face_start[f]; k < m.face_start[f + 1]; ++k)
      t.faces[fill[t.corner_edge[k]]++] = uint32_t(f);
  return t;
}

enum class Split : uint8_t { kKeep, kRed, kGreen, kHalf };

// What a face that is not (yet) red becomes, given which of its edges are split.
Split conforming_split(size_t n, std::span<const uint8_t> split_edge) {
  size_t k = 0;
  for (uint8_t s : split_edge) k += s;
  if (k == 0) return Split::kKeep;
  if (n == 3) return k == 1 ? Split::kGreen : Split::kRed;
  if (n == 4) {
    if (k == 1) return Split::kGreen;
    if (k == 2 && ((split_edge[0] && split_edge[2]) || (split_edge[1] && split_edge[3]))) return Split::kHalf;
    return Split::kRed;
  }
  return Split::kRed;
}

// Splits the `red` faces (#F flags) and whatever closure needs, linearly. mid_of_edge (#E) gets the
// new vertex of each split edge (UINT32_MAX for the others).
Result<CageEdit> split_faces(const Cage& cage, const EdgeTable& edges, std::vector<uint8_t> red,
                             std::vector<uint32_t>& mid_of_edge) {
  const PolyMesh& old = cage.polygons;
  const size_t nf = old.num_faces();
  // closure: a face turns red when its split edges allow no conforming template; its edges split
  std::vector<uint8_t> split(edges.num_edges(), 0);
  std::vector<uint32_t> queue;
  std::vector<uint8_t> flags;
  auto face_flags = [&](size_t f) {
    flags.clear();
    for (uint32_t k = old.face_start[f]; k < old.face_start[f + 1]; ++k)
      flags.push_back(split[edges.corner_edge[k]]);
    return std::span<const uint8_t>(flags);
  };
  auto make_red = [&](size_t f) {
    red[f] = 1;
    for (uint32_t k = old.face_start[f]; k < old.face_start[f + 1]; ++k) {
      const uint32_t e = edges.corner_edge[k];
      if (split[e]) continue;
      split[e] = 1;
      for (uint32_t g : edges.faces_of(e))
        if (!red[g]) queue.push_back(g);
    }
  };
  for (size_t f = 0; f < nf; ++f)
    if (red[f]) make_red(f);
  while (!queue.empty()) {
    const uint32_t g = queue.back();
    queue.pop_back();
    if (!red[g] && conforming_split(old.face(g).size(), face_flags(g)) == Split::kRed) make_red(g);
  }

  // vertices: the old ones, then one per split edge, then one per red non-triangle (its centroid)
  CageTopologyChange change = identity_change(cage);
  std::vector<glm::dvec3> lin(old.positions.begin(), old.positions.end());  // exact linear positions
  mid_of_edge.assign(edges.num_edges(), UINT32_MAX);
  for (size_t e = 0; e < edges.num_edges(); ++e) {
    if (!split[e]) continue;
    const auto [a, b] = edges.ends[e];
    mid_of_edge[e] = static_cast<uint32_t>(lin.size());
    lin.push_back(0.5 * (glm::dvec3(old.positions[a]) + glm::dvec3(old.positions[b])));
    change.vertex_parents.insert(change.vertex_parents.end(), {a, b});
    change.vertex_weights.insert(change.vertex_weights.end(), {0.5, 0.5});
    change.vertex_offsets.push_back(static_cast<uint32_t>(change.vertex_parents.size()));
  }
  PolyMesh out;
  change.face_parent.clear();
  std::vector<uint32_t> c, m, sorted;  // corners, midpoints of edge i (c[i] -> c[i+1])
  for (size_t f = 0; f < nf; ++f) {
    auto corners = old.face(f);
    const size_t n = corners.size();
    c.assign(corners.begin(), corners.end());
    m.resize(n);
    for (size_t i = 0; i < n; ++i) m[i] = mid_of_edge[edges.corner_edge[old.face_start[f] + i]];
    const Split kind = red[f] ? Split::kRed : conforming_split(n, face_flags(f));
    auto at = [n](size_t i) { return i % n; };
    size_t first_split = 0;
    while (first_split < n && m[first_split] == UINT32_MAX) ++first_split;
    if (kind == Split::kKeep) {
      out.add_face(c);
    } else if (kind == Split::kRed && n == 3) {
      out.add_face({c[0], m[0], m[2]});
      out.add_face({m[0], c[1], m[1]});
      out.add_face({m[2], m[1], c[2]});
      out.add_face({m[0], m[1], m[2]});
    } else if (kind == Split::kRed) {
      const uint32_t z = static_cast<uint32_t>(lin.size());
      glm::dvec3 sum(0.0);
      for (uint32_t v : c) sum += glm::dvec3(old.positions[v]);
      lin.push_back(sum / double(n));
      sorted = c;
      std::sort(sorted.begin(), sorted.end());
      for (size_t i = 0; i < n;) {  // repeated corners (degenerate polygons) add up their weights
        size_t j = i;
        while (j < n && sorted[j] == sorted[i]) ++j;
        change.vertex_parents.push_back(sorted[i]);
        change.vertex_weights.push_back(double(j - i) / double(n));
        i = j;
      }
      change.vertex_offsets.push_back(static_cast<uint32_t>(change.vertex_parents.size()));
      for (size_t i = 0; i < n; ++i) out.add_face({c[i], m[i], z, m[at(i + n - 1)]});
    } else if (kind == Split::kGreen && n == 3) {
      const size_t i = first_split;
      out.add_face({c[i], m[i], c[at(i + 2)]});
      out.add_face({m[i], c[at(i + 1)], c[at(i + 2)]});
    } else if (kind == Split::kGreen) {  // quad, one split edge
      const size_t i = first_split;
      out.add_face({c[i], m[i], c[at(i + 3)]});
      out.add_face({m[i], c[at(i + 1)], c[at(i + 2)]});
      out.add_face({m[i], c[at(i + 2)], c[at(i + 3)]});
    } else {  // kHalf: quad, edges i and i + 2 split
      const size_t i = first_split;
      out.add_face({c[i], m[i], m[at(i + 2)], c[at(i + 3)]});
      out.add_face({m[i], c[at(i + 1)], c[at(i + 2)], m[at(i + 2)]});
    }
    change.face_parent.resize(out.num_faces(), static_cast<uint32_t>(f));
  }
  out.positions.reserve(lin.size());
  for (const auto& p : lin) out.positions.emplace_back(p);
  std::vector<glm::dvec3> domain;
  domain.reserve(out.face_vertices.size());
  for (uint32_t v : out.face_vertices) domain.push_back(lin[v]);
  return make_cage_edit(cage, std::move(out), std::move(change), domain, {});
}

Status check_levels(uint32_t levels) {
  if (levels < 1 || levels > kMaxSubdivisionLevels)
    return make_error(ErrorCode::kInvalidArgument, "subdivision levels must be 1 to " +
                                                       std::to_string(kMaxSubdivisionLevels) + ", not " +
                                                       std::to_string(levels));
  return Ok{};
}

// One Loop step on a cage whose polygons are all triangles.
Result<CageEdit> loop_step(const Cage& cage) {
  const PolyMesh& old = cage.polygons;
  const EdgeTable edges = build_edges(old);
  std::vector<uint32_t> mid_of_edge;
  auto split = split_faces(cage, edges, std::vector<uint8_t>(old.num_faces(), 1), mid_of_edge);
  if (!split) return split;
  CageEdit edit = std::move(split).value();

  // per vertex: neighbours and crease neighbours; per edge: the corners opposite it
  const size_t nv = old.num_vertices();
  std::vector<std::vector<uint32_t>> ring(nv), crease(nv);
  for (size_t e = 0; e < edges.num_edges(); ++e) {
    const auto [a, b] = edges.ends[e];
    if (a == b) continue;
    ring[a].push_back(b);
    ring[b].push_back(a);
    if (edges.faces_of(e).size() != 2) {
      crease[a].push_back(b);
      crease[b].push_back(a);
    }
  }
  std::vector<std::array<uint32_t, 2>> opposite(edges.num_edges(), {UINT32_MAX, UINT32_MAX});
  for (size_t f = 0; f < old.num_faces(); ++f)
    for (size_t i = 0; i < 3; ++i) {
      auto& o = opposite[edges.corner_edge[old.face_start[f] + i]];
      (o[0] == UINT32_MAX ? o[0] : o[1]) = old.face(f)[(i + 2) % 3];
    }

  std::vector<std::vector<std::pair<uint32_t, double>>> rows(edit.cage.num_vertices());
  for (uint32_t v = 0; v < nv; ++v) {
    auto& row = rows[v];
    if (crease[v].empty() && !ring[v].empty()) {
      const double n = double(ring[v].size());
      const double t = 3.0 / 8.0 + 0.25 * std::cos(2.0 * std::numbers::pi / n);
      const double beta = (5.0 / 8.0 - t * t) / n;
      row.emplace_back(v, 1.0 - n * beta);
      for (uint32_t u : ring[v]) row.emplace_back(u, beta);
    } else if (crease[v].size() == 2) {
      row = {{v, 0.75}, {crease[v][0], 0.125}, {crease[v][1], 0.125}};
    } else {
      row = {{v, 1.0}};  // corner, or unused
    }
  }
  for (size_t e = 0; e < edges.num_edges(); ++e) {
    const auto [a, b] = edges.ends[e];
    auto& row = rows[mid_of_edge[e]];
    if (edges.faces_of(e).size() == 2) {
      row = {{a, 0.375}, {b, 0.375}, {opposite[e][0], 0.125}, {opposite[e][1], 0.125}};
    } else {
      row = {{a, 0.5}, {b, 0.5}};
    }
  }
  CageTopologyChange& ch = edit.change;
  ch.vertex_offsets.assign(1, 0);
  ch.vertex_parents.clear();
  ch.vertex_weights.clear();
  auto& pos = edit.cage.polygons.positions;
  for (size_t v = 0; v < rows.size(); ++v) {
    auto& row = rows[v];
    std::sort(row.begin(), row.end());
    glm::dvec3 p(0.0);
    for (size_t i = 0; i < row.size(); ++i) {
      p += row[i].second * glm::dvec3(old.positions[row[i].first]);
      if (!ch.vertex_parents.empty() && ch.vertex_offsets.back() < ch.vertex_parents.size() &&
          ch.vertex_parents.back() == row[i].first) {
        ch.vertex_weights.back() += row[i].second;  // the same parent twice (degenerate input)
        continue;
      }
      ch.vertex_parents.push_back(row[i].first);
      ch.vertex_weights.push_back(row[i].second);
    }
    ch.vertex_offsets.push_back(static_cast<uint32_t>(ch.vertex_parents.size()));
    pos[v] = glm::vec3(p);
  }
  return edit;
}

}  // namespace

Result<CageEdit> subdivide_linear(const Cage& cage, uint32_t levels) {
  if (auto s = check_levels(levels); !s) return s.error();
  if (auto s = validate_mesh(cage.polygons, "cage"); !s) return s.error();
  CageEdit result{cage, identity_change(cage), {}};
  for (uint32_t l = 0; l < levels; ++l) {
    std::vector<uint32_t> mids;
    auto step = split_faces(result.cage, build_edges(result.cage.polygons),
                            std::vector<uint8_t>(result.cage.polygons.num_faces(), 1), mids);
    if (!step) return step;
    result.change = compose(result.change, step->change);
    result.cage = std::move(step->cage);
  }
  return result;
}

Result<CageEdit> subdivide_loop(const Cage& cage, uint32_t levels, LoopNonTriangles non_triangles) {
  if (auto s = check_levels(levels); !s) return s.error();
  if (auto s = validate_mesh(cage.polygons, "cage"); !s) return s.error();
  CageEdit result{cage, identity_change(cage), {}};
  if (!cage.polygons.all_triangles()) {
    size_t polygons = 0, first = SIZE_MAX;
    for (size_t f = 0; f < cage.polygons.num_faces(); ++f)
      if (cage.polygons.face(f).size() != 3) {
        ++polygons;
        first = std::min(first, f);
      }
    if (non_triangles == LoopNonTriangles::kReject)
      return make_error(ErrorCode::kInvalidArgument, "face " + std::to_string(first) +
                                                         " is not a triangle (" +
                                                         std::to_string(cage.polygons.face(first).size()) +
                                                         " corners); Loop subdivision needs triangles");
    auto t = triangulate_cage(cage);
    if (!t) return t;
    result = std::move(t).value();
    result.warnings.push_back(std::to_string(polygons) + " faces that are not triangles (the first: face " +
                              std::to_string(first) + ") were split into their control elements first");
  }
  for (uint32_t l = 0; l < levels; ++l) {
    auto step = loop_step(result.cage);
    if (!step) return step;
    result.change = compose(result.change, step->change);
    result.cage = std::move(step->cage);
  }
  return result;
}

Result<CageEdit> refine_faces(const Cage& cage, std::span<const uint32_t> faces) {
  if (auto s = validate_mesh(cage.polygons, "cage"); !s) return s.error();
  auto red = selection_mask(faces, cage.polygons.num_faces(), "face", "refine");
  if (!red) return red.error();
  std::vector<uint32_t> mids;
  return split_faces(cage, build_edges(cage.polygons), std::move(red).value(), mids);
}

}  // namespace cagewrap
