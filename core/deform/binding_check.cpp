#include "core/deform/binding_check.h"

#include <string>

#include "core/base/digits.h"

namespace cagewrap {

Status validate_binding(const Binding& b) {
  auto parse_error = [](std::string m) { return Status(make_error(ErrorCode::kParse, std::move(m))); };
  auto n = [](size_t v) { return group_digits(v); };
  // offsets: one per point plus one, from 0, monotone, ending at the entry count
  if (b.offsets.size() != size_t(b.num_points) + 1)
    return parse_error("the binding's offset table does not match the point count (" + n(b.offsets.size()) +
                       " offsets for " + n(b.num_points) + " points)");
  if (b.offsets.front() != 0)
    return parse_error("the binding's offset table starts at " + n(b.offsets.front()) + ", not 0");
  for (size_t i = 1; i < b.offsets.size(); ++i)
    if (b.offsets[i] < b.offsets[i - 1])
      return parse_error("the binding's offset table is not monotone (offset " + n(i) + " is " + n(b.offsets[i]) +
                         ", offset " + n(i - 1) + " is " + n(b.offsets[i - 1]) + ")");
  if (b.offsets.back() != b.ids.size())
    return parse_error("the binding's offset table ends at " + n(b.offsets.back()) + " but there are " +
                       n(b.ids.size()) + " entries");
  if (b.weights.size() != b.ids.size())
    return parse_error("the binding has " + n(b.weights.size()) + " weights for " + n(b.ids.size()) + " entries");
  if (b.params.variant == Variant::kClamped && b.bary.size() != 2 * b.ids.size())
    return parse_error("the binding has " + n(b.bary.size()) + " anchor coordinates for " + n(b.ids.size()) +
                       " entries (2 each)");
  if (b.rest_cage.size() != b.num_cage_vertices)
    return parse_error("the binding's rest cage has " + n(b.rest_cage.size()) + " vertices but the header says " +
                       n(b.num_cage_vertices));
  if (b.element_status.size() != b.elements.size())
    return parse_error("the binding has " + n(b.element_status.size()) + " element statuses for " +
                       n(b.elements.size()) + " elements");
  if (b.rigid_element.size() != b.rigid_points.size() || b.rigid_bary.size() != 2 * b.rigid_points.size())
    return parse_error("the binding's fallback tables disagree (" + n(b.rigid_points.size()) + " points, " +
                       n(b.rigid_element.size()) + " elements, " + n(b.rigid_bary.size()) + " anchor coordinates)");
  // every index within its table
  auto out_of_range = [](std::string m) { return Status(make_error(ErrorCode::kIndexOutOfRange, std::move(m))); };
  for (size_t e = 0; e < b.elements.size(); ++e)
    for (size_t k = 0; k < 3; ++k)
      if (b.elements[e][k] >= b.num_cage_vertices)
        return out_of_range("the binding's element " + n(e) + " has corner " + n(k) + " at cage vertex " +
                            n(b.elements[e][k]) + " but the cage has " + n(b.num_cage_vertices) + " vertices");
  const bool extended = b.params.variant == Variant::kExtended;
  const bool samples = b.num_samples > 0;
  if (samples && (b.params.variant != Variant::kBasic || !b.elements.empty() || !b.rigid_points.empty()))
    return parse_error("a sample-driven binding must be of the basic variant, with no cage elements or fallback points");
  const size_t id_limit = samples ? b.num_samples : extended ? b.num_cage_vertices : b.elements.size();
  const char* id_name = samples ? "sample " : extended ? "cage vertex " : "element ";
  const char* limit_name = samples ? " samples" : extended ? " vertices" : " elements";
  for (size_t p = 0; p < b.num_points; ++p)
    for (size_t i = b.offsets[p]; i < b.offsets[p + 1]; ++i)
      if (b.ids[i] >= id_limit)
        return out_of_range("the binding's entry " + n(i) + " (of skin point " + n(p) + ") names " + id_name +
                            n(b.ids[i]) + " but the " + (samples ? "driver" : "cage") + " has " + n(id_limit) +
                            limit_name);
  // the contributing sets kept beside the extended stencil (absent in version 1 files)
  if (!b.set_offsets.empty() || !b.set_ids.empty() || !b.set_weights.empty()) {
    if (!extended) return parse_error("the binding holds a separate set table, which only the extended variant has");
    if (b.set_offsets.size() != size_t(b.num_points) + 1 || b.set_offsets.front() != 0 ||
        b.set_offsets.back() != b.set_ids.size() || b.set_weights.size() != b.set_ids.size())
      return parse_error("the binding's set table does not match the point count (" + n(b.set_offsets.size()) +
                         " offsets, " + n(b.set_ids.size()) + " members, " + n(b.set_weights.size()) + " weights for " +
                         n(b.num_points) + " points)");
    for (size_t i = 1; i < b.set_offsets.size(); ++i)
      if (b.set_offsets[i] < b.set_offsets[i - 1])
        return parse_error("the binding's set table is not monotone (offset " + n(i) + ")");
    for (size_t i = 0; i < b.set_ids.size(); ++i)
      if (b.set_ids[i] >= b.elements.size())
        return out_of_range("the binding's set member " + n(i) + " names element " + n(b.set_ids[i]) +
                            " but the cage has " + n(b.elements.size()) + " elements");
  }
  if (!b.separated.empty() && b.separated.size() != b.num_points)
    return parse_error("the binding's separation report has " + n(b.separated.size()) + " entries for " +
                       n(b.num_points) + " points");
  for (size_t i = 0; i < b.rigid_points.size(); ++i) {
    if (b.rigid_points[i] >= b.num_points)
      return out_of_range("the binding's fallback entry " + n(i) + " names skin point " + n(b.rigid_points[i]) +
                          " but the skin has " + n(b.num_points) + " points");
    if (b.rigid_element[i] >= b.elements.size())
      return out_of_range("the binding's fallback entry " + n(i) + " (skin point " + n(b.rigid_points[i]) +
                          ") names element " + n(b.rigid_element[i]) + " but the cage has " + n(b.elements.size()) +
                          " elements");
  }
  return Ok{};
}

}  // namespace cagewrap
