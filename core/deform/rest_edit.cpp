#include "core/deform/rest_edit.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <chrono>
#include <limits>
#include <unordered_map>

#include <glm/common.hpp>
#include <tbb/parallel_for.h>

#include "core/cage/cage.h"
#include "core/geometry/geometry.h"
#include "core/deform/registration.h"

namespace cagewrap {

namespace {

// Squared distance between two boxes (0 when they overlap).
double box_box_dist2(const glm::dvec3& alo, const glm::dvec3& ahi, const glm::dvec3& blo, const glm::dvec3& bhi) {
  double d2 = 0.0;
  for (int i = 0; i < 3; ++i) {
    const double gap = std::max({blo[i] - ahi[i], alo[i] - bhi[i], 0.0});
    d2 += gap * gap;
  }
  return d2;
}

// A reach as the boxes above it count it: infinite reaches are kept apart (ReachIndex::unbounded_).
float boxed(float reach) { return std::isinf(reach) ? -1.f : reach; }

// The point lies within its reach of the triangle (a small relative margin: more points, never fewer).
bool within_reach(const glm::dvec3& p, float reach, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  if (std::isinf(reach)) return true;
  const double r = double(reach) * (1 + 1e-6) + 1e-12;
  return closest_point_on_triangle(p, a, b, c).dist2 <= r * r;
}

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

Result<ReachIndex> ReachIndex::create(const Binding& b, std::span<const glm::vec3> skin) {
  if (skin.size() != b.num_points)
    return make_error(ErrorCode::kTopologyMismatch, "the binding has " + std::to_string(b.num_points) +
                                                        " points but the skin has " + std::to_string(skin.size()));
  if (b.reach.size() != b.num_points)
    return make_error(ErrorCode::kInvalidArgument,
                      "the binding carries no per-point reach (it was read from a file); bind again to edit the rest cage");
  ReachIndex x;
  x.order_ = morton_order(skin);
  const size_t n = skin.size();
  x.slot_.resize(n);
  x.skin_.resize(n);
  x.reach_.resize(n);
  for (size_t i = 0; i < n; ++i) {
    x.slot_[x.order_[i]] = static_cast<uint32_t>(i);
    x.skin_[i] = skin[x.order_[i]];
    x.reach_[i] = b.reach[x.order_[i]];
    if (std::isinf(b.reach[i])) x.unbounded_.push_back(static_cast<uint32_t>(i));
  }
  const size_t leaves = (n + kLeaf - 1) / kLeaf;
  while (x.first_leaf_ < leaves) x.first_leaf_ *= 2;
  x.lo_.assign(2 * size_t(x.first_leaf_), glm::dvec3(1e300));
  x.hi_.assign(2 * size_t(x.first_leaf_), glm::dvec3(-1e300));
  x.max_reach_.assign(2 * size_t(x.first_leaf_), -1.f);
  for (uint32_t l = 0; l < leaves; ++l) {
    const uint32_t node = x.first_leaf_ + l;
    for (size_t i = size_t(l) * kLeaf; i < std::min(n, size_t(l + 1) * kLeaf); ++i) {
      x.lo_[node] = glm::min(x.lo_[node], glm::dvec3(x.skin_[i]));
      x.hi_[node] = glm::max(x.hi_[node], glm::dvec3(x.skin_[i]));
      x.max_reach_[node] = std::max(x.max_reach_[node], boxed(x.reach_[i]));
    }
  }
  for (uint32_t node = x.first_leaf_ - 1; node >= 1; --node) {
    x.lo_[node] = glm::min(x.lo_[2 * node], x.lo_[2 * node + 1]);
    x.hi_[node] = glm::max(x.hi_[2 * node], x.hi_[2 * node + 1]);
    x.max_reach_[node] = std::max(x.max_reach_[2 * node], x.max_reach_[2 * node + 1]);
  }
  return x;
}

void ReachIndex::refresh_leaf(uint32_t leaf) {
  uint32_t node = first_leaf_ + leaf;
  float m = -1.f;
  for (size_t i = size_t(leaf) * kLeaf; i < std::min(reach_.size(), size_t(leaf + 1) * kLeaf); ++i)
    m = std::max(m, boxed(reach_[i]));
  max_reach_[node] = m;
  for (node /= 2; node >= 1; node /= 2) {
    const float up = std::max(max_reach_[2 * node], max_reach_[2 * node + 1]);
    if (up == max_reach_[node]) break;
    max_reach_[node] = up;
  }
}

void ReachIndex::refresh(const Binding& b, std::span<const uint32_t> points) {
  std::vector<uint32_t> leaves;
  for (uint32_t p : points) {
    if (p >= slot_.size() || p >= b.reach.size()) continue;
    const auto at = std::lower_bound(unbounded_.begin(), unbounded_.end(), p);
    const bool listed = at != unbounded_.end() && *at == p;
    if (std::isinf(b.reach[p]) && !listed) unbounded_.insert(at, p);
    if (!std::isinf(b.reach[p]) && listed) unbounded_.erase(at);
    reach_[slot_[p]] = b.reach[p];
    leaves.push_back(slot_[p] / kLeaf);
  }
  std::sort(leaves.begin(), leaves.end());
  leaves.erase(std::unique(leaves.begin(), leaves.end()), leaves.end());
  for (uint32_t l : leaves) refresh_leaf(l);
}

Result<std::vector<uint32_t>> ReachIndex::affected_points(const Binding& b, const Cage& cage,
                                                          std::span<const glm::vec3> new_rest,
                                                          std::span<const uint32_t> moved,
                                                          std::span<const SetEdit> edits) const {
  const size_t nv = b.rest_cage.size();
  if (b.num_points != slot_.size())
    return make_error(ErrorCode::kTopologyMismatch, "the binding has " + std::to_string(b.num_points) +
                                                        " points but the index was made for " +
                                                        std::to_string(slot_.size()));
  if (new_rest.size() != nv || cage.num_vertices() != nv || cage.elements != b.elements)
    return make_error(ErrorCode::kTopologyMismatch,
                      "the moved cage has " + std::to_string(new_rest.size()) + " positions and " +
                          std::to_string(cage.num_elements()) + " elements but the binding's has " +
                          std::to_string(nv) + " vertices and " + std::to_string(b.elements.size()) +
                          " elements (rest edits keep the topology)");
  std::vector<uint8_t> is_moved(nv, 0);
  for (uint32_t v : moved) {
    if (v >= nv)
      return make_error(ErrorCode::kIndexOutOfRange, "moved cage vertex " + std::to_string(v) +
                                                         " does not exist: the cage has " + std::to_string(nv));
    is_moved[v] = 1;
  }
  // the changed elements: a moved corner, or a status that changes (a duplicate of a moved one)
  const std::vector<ElementStatus> status = classify_elements(cage, new_rest);
  std::vector<uint32_t> changed;
  for (uint32_t e = 0; e < b.elements.size(); ++e) {
    const Tri& t = b.elements[e];
    if (is_moved[t[0]] || is_moved[t[1]] || is_moved[t[2]] || status[e] != b.element_status[e]) changed.push_back(e);
  }
  // each changed element where it was and where it is
  std::vector<std::array<glm::dvec3, 3>> triangles;
  for (uint32_t e : changed) {
    const Tri& t = b.elements[e];
    for (std::span<const glm::vec3> place : {std::span<const glm::vec3>(b.rest_cage), new_rest})
      triangles.push_back({glm::dvec3(place[t[0]]), glm::dvec3(place[t[1]]), glm::dvec3(place[t[2]])});
  }
  std::vector<uint32_t> out = points_within_reach(triangles);
  auto mark = [&](uint32_t point) { out.push_back(point); };
  // inclusions act whatever the distance
  for (const SetEdit& edit : edits) {
    if (edit.point >= slot_.size()) continue;  // Rebinder::move_rest reports it
    for (uint32_t e : edit.include)
      if (std::binary_search(changed.begin(), changed.end(), e)) mark(edit.point);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::vector<uint32_t> ReachIndex::points_within_reach(std::span<const std::array<glm::dvec3, 3>> triangles) const {
  std::vector<uint32_t> out;  // with repeats until the end (no table over the whole skin: the cost follows the region)
  std::vector<uint32_t> stack;
  for (const auto& [a, bb, c] : triangles) {
    if (!finite(a) || !finite(bb) || !finite(c)) continue;  // drives nothing there
    const glm::dvec3 lo = glm::min(a, glm::min(bb, c)), hi = glm::max(a, glm::max(bb, c));
    stack.assign(1, 1u);
    while (!stack.empty()) {
      const uint32_t node = stack.back();
      stack.pop_back();
      const float r = max_reach_[node];
      if (r < 0) continue;
      const double rr = double(r) * (1 + 1e-6) + 1e-12;
      if (box_box_dist2(lo_[node], hi_[node], lo, hi) > rr * rr) continue;
      if (node < first_leaf_) {
        stack.push_back(2 * node);
        stack.push_back(2 * node + 1);
        continue;
      }
      const size_t leaf = node - first_leaf_;
      for (size_t i = leaf * kLeaf; i < std::min(skin_.size(), (leaf + 1) * kLeaf); ++i)
        if (within_reach(glm::dvec3(skin_[i]), reach_[i], a, bb, c)) out.push_back(order_[i]);
    }
  }
  // points that follow their nearest element: any change may change which one that is
  if (!triangles.empty()) out.insert(out.end(), unbounded_.begin(), unbounded_.end());
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

Result<RestRebindReport> rebind_moved_rest(Binding& binding, std::span<const glm::vec3> skin, const Cage& cage,
                                           std::span<const glm::vec3> new_rest, std::span<const SetEdit> edits,
                                           const PartLabels* labels, const PartLabels* previous_labels) {
  const bool now = labels && !labels->empty(), before = previous_labels && !previous_labels->empty();
  if (now != before || (now && (labels->point != previous_labels->point || labels->parent != previous_labels->parent)))
    return make_error(ErrorCode::kInvalidArgument, "the skin's part labels changed since the bind; bind again");
  if (new_rest.size() != binding.rest_cage.size() || binding.elements != cage.elements)
    return make_error(ErrorCode::kTopologyMismatch, "the binding was made for a cage of another topology; bind again");
  RestRebindReport report;
  std::vector<uint32_t> moved;
  for (uint32_t v = 0; v < new_rest.size(); ++v) {
    const bool relabelled = now && (v >= labels->cage_vertex.size() || v >= previous_labels->cage_vertex.size() ||
                                    labels->cage_vertex[v] != previous_labels->cage_vertex[v]);
    if (relabelled || std::memcmp(&new_rest[v], &binding.rest_cage[v], sizeof(glm::vec3)) != 0) moved.push_back(v);
  }
  report.moved_vertices = moved.size();
  if (moved.empty()) return report;
  auto index = ReachIndex::create(binding, skin);
  if (!index) return index.error();
  auto points = index->affected_points(binding, cage, new_rest, moved, edits);
  if (!points) return points.error();
  auto rebinder = Rebinder::create(skin, cage, new_rest, binding.params, now ? labels : nullptr);
  if (!rebinder) return rebinder.error();
  if (auto s = rebinder->move_rest(binding, edits, *points); !s) return s.error();
  report.points = points->size();
  return report;
}

namespace {
// Bitwise key of a position (exact matches only).
struct PositionKey {
  uint32_t x, y, z;
  bool operator==(const PositionKey&) const = default;
};
PositionKey key_of(const glm::vec3& v) {
  PositionKey k;
  std::memcpy(&k.x, &v.x, 4);
  std::memcpy(&k.y, &v.y, 4);
  std::memcpy(&k.z, &v.z, 4);
  return k;
}
struct KeyHash {
  size_t operator()(const PositionKey& k) const {
    return (size_t(k.x) * 0x9E3779B97F4A7C15ull) ^ (size_t(k.y) * 0xC2B2AE3D27D4EB4Full) ^ (size_t(k.z) * 0x165667B19E3779F9ull);
  }
  size_t operator()(const Tri& t) const {
    return (size_t(t[0]) * 0x9E3779B97F4A7C15ull) ^ (size_t(t[1]) * 0xC2B2AE3D27D4EB4Full) ^ (size_t(t[2]) * 0x165667B19E3779F9ull);
  }
};
constexpr uint32_t kNone = UINT32_MAX;

// A cage vertex's part label and shell (both kNone without labels).
std::pair<uint32_t, uint32_t> vertex_labels(const PartLabels* l, size_t v) {
  if (!l || l->empty()) return {kNone, kNone};
  return {v < l->cage_vertex.size() ? l->cage_vertex[v] : kNone, v < l->vertex_shell.size() ? l->vertex_shell[v] : kNone};
}
}  // namespace

Result<TopologyRebindReport> rebind_new_topology(Binding& binding, std::span<const glm::vec3> skin, const Cage& cage,
                                                 std::span<const glm::vec3> new_rest, std::span<const SetEdit> edits,
                                                 std::span<const SetEdit> previous_edits, const PartLabels* labels,
                                                 const PartLabels* previous_labels) {
  const auto t0 = std::chrono::steady_clock::now();
  const Binding& b = binding;
  const bool now = labels && !labels->empty(), before = previous_labels && !previous_labels->empty();
  if (now != before ||
      (now && (labels->point != previous_labels->point || labels->parent != previous_labels->parent ||
               labels->point_shell != previous_labels->point_shell || labels->related != previous_labels->related ||
               labels->length != previous_labels->length || labels->head != previous_labels->head)))
    return make_error(ErrorCode::kInvalidArgument, "the skin's part labels changed since the bind; bind again");
  if (b.num_samples > 0 || b.num_points != skin.size() || b.reach.size() != b.num_points || !b.has_sets())
    return make_error(ErrorCode::kInvalidArgument,
                      "the binding was not made by this bind of this skin (or was read from a file); bind again");
  if (new_rest.size() != cage.num_vertices())
    return make_error(ErrorCode::kTopologyMismatch, "the cage has " + std::to_string(cage.num_vertices()) +
                                                        " vertices but " + std::to_string(new_rest.size()) +
                                                        " positions were given");
  // the registration on the new cage (its h, its hierarchy): it fills in the points registered again
  auto rebinder = Rebinder::create(skin, cage, new_rest, b.params, now ? labels : nullptr);
  if (!rebinder) return rebinder.error();
  const double h = rebinder->h();
  if (h != b.h)
    return make_error(ErrorCode::kInvalidArgument,
                      "the new cage changes the distance scale h (" + std::to_string(b.h) + " -> " + std::to_string(h) +
                          ", the mean cage edge length) and so every weight; bind again, or give a fixed scale to keep "
                          "topology edits local");

  // vertices standing exactly where an old one stood (a position two old vertices share matches neither)
  std::unordered_map<PositionKey, uint32_t, KeyHash> old_at;
  for (uint32_t v = 0; v < b.rest_cage.size(); ++v) {
    auto [it, fresh] = old_at.emplace(key_of(b.rest_cage[v]), v);
    if (!fresh) it->second = kNone;
  }
  std::vector<uint32_t> vertex_from(new_rest.size(), kNone);  // new -> old
  for (uint32_t v = 0; v < new_rest.size(); ++v) {
    auto it = old_at.find(key_of(new_rest[v]));
    if (it == old_at.end() || it->second == kNone) continue;
    if (vertex_labels(labels, v) != vertex_labels(previous_labels, it->second)) continue;  // relabelled: changed
    vertex_from[v] = it->second;
  }
  std::vector<uint32_t> vertex_to(b.rest_cage.size(), kNone);  // old -> new
  for (uint32_t v = 0; v < vertex_from.size(); ++v)
    if (vertex_from[v] != kNone) vertex_to[vertex_from[v]] = v;
  // elements: the same corners in the same order, and the same status
  std::unordered_map<Tri, uint32_t, KeyHash> old_element;
  for (uint32_t e = 0; e < b.elements.size(); ++e) old_element.emplace(b.elements[e], e);
  const std::vector<ElementStatus> status = classify_elements(cage, new_rest);
  std::vector<uint32_t> element_to(b.elements.size(), kNone);  // old -> new
  TopologyRebindReport report;
  uint32_t last_old = 0;
  bool first = true;
  for (uint32_t e = 0; e < cage.num_elements(); ++e) {
    const Tri& t = cage.elements[e];
    const Tri from{vertex_from[t[0]], vertex_from[t[1]], vertex_from[t[2]]};
    if (from[0] == kNone || from[1] == kNone || from[2] == kNone) continue;
    auto it = old_element.find(from);
    if (it == old_element.end() || element_to[it->second] != kNone || b.element_status[it->second] != status[e]) continue;
    if (!first && it->second <= last_old)
      return make_error(ErrorCode::kInvalidArgument,
                        "the topology edit reordered the cage's elements (element " + std::to_string(e) +
                            " was " + std::to_string(it->second) + "); bind again");
    first = false;
    last_old = it->second;
    element_to[it->second] = e;
    ++report.kept_elements;
  }
  // the removed elements where they were, the added ones where they are
  std::vector<std::array<glm::dvec3, 3>> triangles;
  std::vector<uint8_t> kept_new(cage.num_elements(), 0);
  for (uint32_t e = 0; e < b.elements.size(); ++e) {
    if (element_to[e] != kNone) {
      kept_new[element_to[e]] = 1;
      continue;
    }
    ++report.removed_elements;
    const Tri& t = b.elements[e];
    triangles.push_back({glm::dvec3(b.rest_cage[t[0]]), glm::dvec3(b.rest_cage[t[1]]), glm::dvec3(b.rest_cage[t[2]])});
  }
  for (uint32_t e = 0; e < cage.num_elements(); ++e) {
    if (kept_new[e]) continue;
    ++report.added_elements;
    const Tri& t = cage.elements[e];
    triangles.push_back({glm::dvec3(new_rest[t[0]]), glm::dvec3(new_rest[t[1]]), glm::dvec3(new_rest[t[2]])});
  }
  auto index = ReachIndex::create(b, skin);
  if (!index) return index.error();
  std::vector<uint32_t> points = index->points_within_reach(triangles);
  points.insert(points.end(), b.rigid_points.begin(), b.rigid_points.end());  // whatever changed
  for (std::span<const SetEdit> list : {edits, previous_edits})
    for (const SetEdit& e : list)
      if (e.point < b.num_points) points.push_back(e.point);  // Rebinder::update names the others
  // a kept row must name kept elements and vertices only (within reach of nothing changed, it does)
  const Binding::SetsView sets = b.sets();
  const bool extended = b.params.variant == Variant::kExtended;
  for (uint32_t p = 0; p < b.num_points; ++p) {
    bool ok = true;
    for (uint32_t e : sets.of(p)) ok = ok && element_to[e] != kNone;
    if (extended)
      for (uint32_t j = b.offsets[p]; j < b.offsets[p + 1]; ++j) ok = ok && vertex_to[b.ids[j]] != kNone;
    if (!ok) points.push_back(p);
  }
  std::sort(points.begin(), points.end());
  points.erase(std::unique(points.begin(), points.end()), points.end());
  std::vector<uint8_t> again(b.num_points, 0);
  for (uint32_t p : points) again[p] = 1;

  // the binding on the new cage: kept rows renumbered, the others empty (update() fills them)
  Binding nb;
  nb.params = b.params;
  nb.h = b.h;
  nb.origin = b.origin;
  nb.num_points = b.num_points;
  nb.num_cage_vertices = static_cast<uint32_t>(cage.num_vertices());
  nb.rest_cage.assign(new_rest.begin(), new_rest.end());
  nb.elements = cage.elements;
  nb.element_status = status;
  for (uint32_t e = 0; e < status.size(); ++e)
    if (status[e] != ElementStatus::kValid) nb.invalid_elements.push_back(e);
  const bool clamped = b.params.variant == Variant::kClamped;
  nb.offsets.assign(size_t(b.num_points) + 1, 0);
  if (extended) nb.set_offsets.assign(size_t(b.num_points) + 1, 0);
  nb.quality_inside = b.quality_inside;
  nb.total_set_size = b.total_set_size;
  for (uint32_t p = 0; p < b.num_points; ++p) {
    const uint32_t rows = again[p] ? 0 : b.offsets[p + 1] - b.offsets[p];
    nb.offsets[p + 1] = nb.offsets[p] + rows;
    if (extended) nb.set_offsets[p + 1] = nb.set_offsets[p] + (again[p] ? 0 : b.set_offsets[p + 1] - b.set_offsets[p]);
    if (again[p]) {
      nb.quality_inside -= well_bound(b, skin, p);
      nb.total_set_size -= sets.of(p).size();
    } else {
      nb.max_set_size = std::max(nb.max_set_size, static_cast<uint32_t>(sets.of(p).size()));
    }
  }
  nb.ids.resize(nb.offsets.back());
  nb.weights.resize(nb.offsets.back());
  if (clamped) nb.bary.resize(2 * size_t(nb.offsets.back()));
  if (extended) {
    nb.set_ids.resize(nb.set_offsets.back());
    nb.set_weights.resize(nb.set_offsets.back());
  }
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, b.num_points, 4096), [&](const tbb::blocked_range<uint32_t>& r) {
    for (uint32_t p = r.begin(); p != r.end(); ++p) {
      if (again[p]) continue;
      for (uint32_t j = b.offsets[p], k = nb.offsets[p]; j < b.offsets[p + 1]; ++j, ++k) {
        nb.ids[k] = extended ? vertex_to[b.ids[j]] : element_to[b.ids[j]];
        nb.weights[k] = b.weights[j];
        if (clamped) nb.bary[2 * size_t(k)] = b.bary[2 * size_t(j)], nb.bary[2 * size_t(k) + 1] = b.bary[2 * size_t(j) + 1];
      }
      if (extended)
        for (uint32_t j = b.set_offsets[p], k = nb.set_offsets[p]; j < b.set_offsets[p + 1]; ++j, ++k) {
          nb.set_ids[k] = element_to[b.set_ids[j]];
          nb.set_weights[k] = b.set_weights[j];
        }
    }
  });
  // the fallback points follow their nearest element: every one is registered again
  nb.separation_applied = b.separation_applied;
  nb.separated = b.separated;
  nb.total_separated = b.total_separated;
  nb.separated_points = b.separated_points;
  nb.reach = b.reach;
  nb.seconds = b.seconds;

  if (auto s = rebinder->update(nb, edits, points); !s) return s.error();
  binding = std::move(nb);
  report.points = points.size();
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return report;
}

}  // namespace cagewrap
