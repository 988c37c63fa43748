#include "core/cage/cage_shells.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <unordered_map>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/geometry/element_bvh.h"
#include "core/geometry/triangle_bvh.h"
#include "core/geometry/weld.h"

namespace cagewrap {

namespace {
struct UnionFind {
  std::vector<uint32_t> root;
  explicit UnionFind(size_t n) : root(n) {
    for (size_t i = 0; i < n; ++i) root[i] = static_cast<uint32_t>(i);
  }
  uint32_t find(uint32_t x) {
    while (root[x] != x) x = root[x] = root[root[x]];
    return x;
  }
  void join(uint32_t a, uint32_t b) { root[find(a)] = find(b); }
};
}  // namespace

ShellOwnership cage_shell_ownership(std::span<const glm::vec3> cage_rest, std::span<const Tri> elements,
                                    std::span<const glm::vec3> skin, std::span<const Tri> skin_triangles,
                                    double share) {
  ShellOwnership out;
  const size_t nv = cage_rest.size();
  if (elements.empty() || nv == 0) return out;
  for (const Tri& t : elements)
    if (t[0] >= nv || t[1] >= nv || t[2] >= nv) return out;  // not this cage's elements
  UnionFind cage_pieces(nv);
  for (const Tri& t : elements) cage_pieces.join(t[0], t[1]), cage_pieces.join(t[0], t[2]);
  std::vector<uint32_t> shell_of_root(nv, kNoShell);
  std::vector<uint8_t> used(nv, 0);
  for (const Tri& t : elements) used[t[0]] = used[t[1]] = used[t[2]] = 1;
  std::vector<uint32_t> vertex_shell(nv, kNoShell);
  for (uint32_t v = 0; v < nv; ++v) {
    if (!used[v]) continue;
    uint32_t& id = shell_of_root[cage_pieces.find(v)];
    if (id == kNoShell) id = out.shells++;
    vertex_shell[v] = id;
  }
  if (out.shells <= 1) return out;
  out.vertex_shell = std::move(vertex_shell);
  const uint32_t shells = out.shells;
  std::vector<std::vector<Tri>> tris(shells);
  std::vector<std::vector<uint32_t>> ids(shells);
  for (uint32_t e = 0; e < elements.size(); ++e) {
    const uint32_t sh = out.vertex_shell[elements[e][0]];
    tris[sh].push_back(elements[e]);
    ids[sh].push_back(e);
  }
  // closed shells (every edge shared by exactly two of its elements) can hold points
  std::vector<uint8_t> closed(shells, 1);
  for (uint32_t sh = 0; sh < shells; ++sh) {
    std::unordered_map<uint64_t, int> edges;
    for (const Tri& t : tris[sh])
      for (int k = 0; k < 3; ++k) {
        uint32_t a = t[k], b = t[(k + 1) % 3];
        if (a > b) std::swap(a, b);
        ++edges[(uint64_t(a) << 32) | b];
      }
    for (const auto& [e, n] : edges)
      if (n != 2) closed[sh] = 0;
  }
  std::vector<std::unique_ptr<TriangleBvh>> inside(shells);
  std::vector<std::unique_ptr<ElementBvh>> near(shells);
  std::vector<Aabb> box(shells);
  for (uint32_t sh = 0; sh < shells; ++sh) {
    near[sh] = std::make_unique<ElementBvh>(cage_rest, elements, ids[sh]);
    if (closed[sh]) inside[sh] = std::make_unique<TriangleBvh>(cage_rest, tris[sh]);
    for (const Tri& t : tris[sh])
      for (uint32_t v : t) box[sh].extend(glm::dvec3(cage_rest[v]));
  }
  // the size of each closed shell (its enclosed volume): the tightest shell holding a piece owns it
  std::vector<double> volume(shells, INFINITY);
  for (uint32_t sh = 0; sh < shells; ++sh) {
    if (!closed[sh]) continue;
    double v6 = 0.0;
    for (const Tri& t : tris[sh])
      v6 += glm::dot(glm::dvec3(cage_rest[t[0]]), glm::cross(glm::dvec3(cage_rest[t[1]]), glm::dvec3(cage_rest[t[2]])));
    volume[sh] = std::abs(v6) / 6.0;
  }
  const size_t np = skin.size();
  out.point_shell.assign(np, kNoShell);
  std::vector<std::vector<uint32_t>> holding(np);  // the closed shells each point lies inside
  // an irrational-looking direction: a ray through an edge or a vertex is unlikely
  const glm::dvec3 dir = glm::normalize(glm::dvec3(0.5773, 0.5789, 0.5762));
  tbb::parallel_for(tbb::blocked_range<size_t>(0, np, 256), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const glm::dvec3 p(skin[i]);
      uint32_t& owner = out.point_shell[i];
      double deepest = -1.0;
      for (uint32_t sh = 0; sh < shells; ++sh) {
        if (!inside[sh] || ElementBvh::box_dist2(p, box[sh].lo, box[sh].hi) > 0) continue;
        if (inside[sh]->count_hits(Ray{p, dir}) % 2 == 0) continue;
        holding[i].push_back(sh);
        const double d = near[sh]->nearest_distance(p);
        if (d > deepest) deepest = d, owner = sh;
      }
      if (owner != kNoShell) continue;
      double nearest = INFINITY;
      for (uint32_t sh = 0; sh < shells; ++sh) {
        if (near[sh]->empty() || ElementBvh::box_dist2(p, box[sh].lo, box[sh].hi) >= nearest * nearest) continue;
        const double d = near[sh]->nearest_distance(p);
        if (d < nearest) nearest = d, owner = sh;
      }
    }
  });
  // pieces of the skin: through its triangles, coincident vertices (seams) welded
  Aabb skin_box;
  for (const glm::vec3& p : skin) skin_box.extend(glm::dvec3(p));
  const Weld weld = weld_vertices(skin, skin_box.empty() ? 0.0 : 1e-6 * skin_box.diagonal());
  UnionFind pieces(weld.positions.size());
  for (const Tri& t : skin_triangles)
    if (t[0] < np && t[1] < np && t[2] < np)
      pieces.join(weld.remap[t[0]], weld.remap[t[1]]), pieces.join(weld.remap[t[0]], weld.remap[t[2]]);
  std::unordered_map<uint32_t, std::unordered_map<uint32_t, uint32_t>> count;  // piece -> shell -> points inside
  std::unordered_map<uint32_t, uint32_t> size;
  for (size_t i = 0; i < np; ++i) {
    const uint32_t piece = pieces.find(weld.remap[i]);
    ++size[piece];
    for (uint32_t sh : holding[i]) ++count[piece][sh];
  }
  // a piece is owned by the tightest closed shell holding nearly all of it (its own wrap, rather
  // than the bigger shell of a neighbouring segment that also happens to enclose it)
  std::unordered_map<uint32_t, uint32_t> piece_owner;
  for (const auto& [piece, shells_of] : count) {
    uint32_t best = kNoShell;
    for (const auto& [sh, n] : shells_of)
      if (double(n) >= share * double(size[piece]) && (best == kNoShell || volume[sh] < volume[best] ||
                                                      (volume[sh] == volume[best] && sh < best)))
        best = sh;
    if (best != kNoShell) piece_owner[piece] = best;
  }
  out.piece_shell.assign(np, kNoShell);
  for (size_t i = 0; i < np; ++i) {
    auto it = piece_owner.find(pieces.find(weld.remap[i]));
    if (it != piece_owner.end()) out.piece_shell[i] = out.point_shell[i] = it->second;
  }
  return out;
}

}  // namespace cagewrap
