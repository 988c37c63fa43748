#include "core/deform/rest_edit.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include <glm/common.hpp>

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

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

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
  std::vector<uint32_t> out;  // with repeats until the end (no table over the whole skin: the cost follows the region)
  auto mark = [&](uint32_t point) { out.push_back(point); };
  std::vector<uint32_t> stack;
  for (uint32_t e : changed) {
    const Tri& t = b.elements[e];
    for (std::span<const glm::vec3> place : {std::span<const glm::vec3>(b.rest_cage), new_rest}) {
      if (!finite(place[t[0]]) || !finite(place[t[1]]) || !finite(place[t[2]])) continue;  // drives nothing there
      const glm::dvec3 a(place[t[0]]), bb(place[t[1]]), c(place[t[2]]);
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
          if (within_reach(glm::dvec3(skin_[i]), reach_[i], a, bb, c)) mark(order_[i]);
      }
    }
  }
  // points that follow their nearest element: any change may change which one that is
  if (!changed.empty()) out.insert(out.end(), unbounded_.begin(), unbounded_.end());
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

}  // namespace cagewrap
