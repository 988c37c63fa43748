#include "core/document/set_queries.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <string>

#include "core/deform/registration.h"

namespace cagewrap {

namespace {

Status check_sets(const Binding& b) {
  if (!b.has_sets())
    return make_error(ErrorCode::kInvalidArgument,
                      "the binding has no contributing-set table (made by an older cagewrap); bind again");
  return Ok{};
}

Status check_cage(const Binding& b, const Cage& cage) {
  if (cage.num_elements() != b.elements.size() || cage.element_face.size() != b.elements.size())
    return make_error(ErrorCode::kTopologyMismatch,
                      "the binding was made for a cage of " + std::to_string(b.elements.size()) +
                          " elements, not this one (" + std::to_string(cage.num_elements()) +
                          "); bind again");
  return Ok{};
}

int64_t rigid_element_of(const Binding& b, uint32_t point) {
  auto it = std::lower_bound(b.rigid_points.begin(), b.rigid_points.end(), point);
  if (it == b.rigid_points.end() || *it != point) return -1;
  return b.rigid_element[static_cast<size_t>(it - b.rigid_points.begin())];
}

}  // namespace

Result<PointSet> point_set(const Binding& b, const Cage& cage, uint32_t point,
                           std::span<const SetEdit> edits) {
  if (auto s = check_sets(b); !s) return s.error();
  if (auto s = check_cage(b, cage); !s) return s.error();
  if (point >= b.num_points)
    return make_error(ErrorCode::kIndexOutOfRange, "skin point " + std::to_string(point) +
                                                       " is out of range: the skin has " +
                                                       std::to_string(b.num_points) + " points");
  const Binding::SetsView sets = b.sets();
  PointSet out;
  for (uint32_t i = sets.offsets[point]; i < sets.offsets[point + 1]; ++i)
    out.members.push_back({sets.ids[i], cage.element_face[sets.ids[i]], sets.weights[i]});
  std::stable_sort(out.members.begin(), out.members.end(), [](const SetMember& x, const SetMember& y) {
    return x.weight > y.weight || (x.weight == y.weight && x.element < y.element);
  });
  out.rigid_element = rigid_element_of(b, point);
  out.edited = std::any_of(edits.begin(), edits.end(), [&](const SetEdit& e) { return e.point == point; });
  return out;
}

Result<std::vector<float>> face_influence(const Binding& b, const Cage& cage, const IndexSet& faces) {
  if (auto s = check_sets(b); !s) return s.error();
  if (auto s = check_cage(b, cage); !s) return s.error();
  std::vector<uint8_t> chosen(b.elements.size(), 0);  // elements on the chosen polygons
  for (size_t e = 0; e < chosen.size(); ++e) chosen[e] = faces.contains(cage.element_face[e]);
  const Binding::SetsView sets = b.sets();
  std::vector<float> out(b.num_points, 0.f);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, b.num_points, 8192),
                    [&](const tbb::blocked_range<size_t>& r) {
                      for (size_t p = r.begin(); p != r.end(); ++p) {
                        float sum = 0.f;
                        for (uint32_t i = sets.offsets[p]; i < sets.offsets[p + 1]; ++i)
                          if (chosen[sets.ids[i]]) sum += sets.weights[i];
                        out[p] = std::min(sum, 1.f);
                      }
                    });
  for (size_t k = 0; k < b.rigid_points.size(); ++k)
    out[b.rigid_points[k]] = chosen[b.rigid_element[k]] ? 1.f : 0.f;
  return out;
}

Result<SetOverview> set_overview(const Binding& b, std::span<const glm::vec3> skin,
                                 std::span<const SetEdit> edits) {
  if (auto s = check_sets(b); !s) return s.error();
  if (skin.size() != b.num_points)
    return make_error(ErrorCode::kTopologyMismatch,
                      "the binding was made for " + std::to_string(b.num_points) +
                          " skin points but the skin has " + std::to_string(skin.size()));
  const Binding::SetsView sets = b.sets();
  SetOverview out;
  out.size.resize(b.num_points);
  out.flags.assign(b.num_points, 0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, b.num_points, 4096),
                    [&](const tbb::blocked_range<size_t>& r) {
                      for (size_t p = r.begin(); p != r.end(); ++p) {
                        const uint32_t n = sets.offsets[p + 1] - sets.offsets[p];
                        out.size[p] = static_cast<uint8_t>(std::min<uint32_t>(n, 255));
                        if (!well_bound(b, skin, static_cast<uint32_t>(p))) out.flags[p] |= kSetOutside;
                      }
                    });
  for (uint32_t p : b.rigid_points) out.flags[p] |= kSetEmpty;
  for (const SetEdit& e : edits)
    if (e.point < b.num_points) out.flags[e.point] |= kSetEdited;
  uint64_t total = 0;
  for (size_t p = 0; p < b.num_points; ++p) {
    const uint32_t n = sets.offsets[p + 1] - sets.offsets[p];
    total += n;
    out.max_size = std::max(out.max_size, n);
    out.empty += (out.flags[p] & kSetEmpty) != 0;
    out.edited += (out.flags[p] & kSetEdited) != 0;
    out.outside += (out.flags[p] & kSetOutside) != 0;
  }
  out.mean_size = b.num_points ? double(total) / b.num_points : 0.0;
  return out;
}

IndexSet edited_points(std::span<const SetEdit> edits) {
  std::vector<uint32_t> points;
  points.reserve(edits.size());
  for (const SetEdit& e : edits) points.push_back(e.point);
  return IndexSet(std::move(points));
}

}  // namespace cagewrap
