// Moving reference (rest) cage vertices without a full bind: which skin points the moved elements
// can reach. A point's registration depends only on the elements within its reach (Binding::reach:
// its threshold radius, or nearer its (K+1)-th nearest allowed element), so an element that moves
// while staying out of every point's reach, before and after, changes nothing. The points it can
// reach are registered again with Rebinder::move_rest; the result is a full bind's, bit for bit.
//
//   ReachIndex index = ReachIndex::create(binding, skin).value();  // once per binding
//   auto rebinder = Rebinder::create(skin, cage, moved_rest, params, labels);
//   auto points = index.affected_points(binding, cage, moved_rest, moved_vertices, edits);
//   rebinder->move_rest(binding, edits, *points);
//   index.refresh(binding, *points);                                // their reach changed
#pragma once

#include <array>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "core/deform/binding.h"
#include "core/base/result.h"

namespace cagewrap {
struct Cage;
struct PartLabels;
}  // namespace cagewrap

namespace cagewrap {

// The skin points of a binding in a hierarchy of boxes that know the largest reach of their points,
// so that the points an element can reach are found without visiting the whole skin.
class ReachIndex {
 public:
  // Errors: a binding without reach (read from a file: bind again), a skin of another size.
  static Result<ReachIndex> create(const Binding& binding, std::span<const glm::vec3> skin);

  // The points (ascending) whose registration can change when the cage vertices `moved` go from
  // binding.rest_cage to `new_rest` (same topology, `cage`'s elements): those within reach of an
  // element touching a moved vertex, or of one whose status (core/cage/cage.h classify_elements) changes,
  // in either place; the points that follow their nearest element (infinite reach); and those whose
  // edit includes such an element. A superset of the points that change, never a subset.
  // Errors name the vertex or the sizes that do not match.
  Result<std::vector<uint32_t>> affected_points(const Binding& binding, const Cage& cage,
                                                std::span<const glm::vec3> new_rest,
                                                std::span<const uint32_t> moved,
                                                std::span<const SetEdit> edits) const;

  // The reach of `points` changed in `binding` (Rebinder::update or move_rest): index it.
  void refresh(const Binding& binding, std::span<const uint32_t> points);

  // The points (ascending) within reach of any of `triangles` (corner positions; non-finite ones are
  // skipped), and the points that follow their nearest element when there is any triangle.
  std::vector<uint32_t> points_within_reach(std::span<const std::array<glm::dvec3, 3>> triangles) const;

 private:
  static constexpr uint32_t kLeaf = 32;  // points per leaf
  std::vector<glm::vec3> skin_;          // in leaf order
  std::vector<float> reach_;             // in leaf order
  std::vector<uint32_t> order_;          // leaf order -> point
  std::vector<uint32_t> slot_;           // point -> leaf order
  // a complete binary tree over the leaves: node 1 is the root, n's children 2n and 2n+1, leaf i is
  // node first_leaf_ + i
  uint32_t first_leaf_ = 1;
  std::vector<glm::dvec3> lo_, hi_;
  std::vector<float> max_reach_;  // of the finite reaches below; -1 for a node with none
  // Points with infinite reach (they follow their nearest element): affected by any change, so they
  // are listed once here rather than opening every box above them to the search. Ascending.
  std::vector<uint32_t> unbounded_;
  void refresh_leaf(uint32_t leaf);
};

// What rebind_moved_rest did.
struct RestRebindReport {
  size_t moved_vertices = 0;  // cage vertices that moved or changed part label
  size_t points = 0;          // skin points registered again
  double seconds = 0.0;       // wall time
  // a topology edit (core/rig/rig.h rebind_document: rebind_new_topology): elements of the new cage
  // that are not an old one where it stood, and old ones gone
  bool topology = false;
  size_t added_elements = 0, removed_elements = 0;
};

// The rest cage moved from binding.rest_cage to `new_rest` (same cage elements, parameters and set
// edits): re-registers, in place, only the skin points the change can reach (ReachIndex, once per
// call: O(P) plus the affected points). Afterwards `binding` equals bind_skin(skin, cage, new_rest,
// binding.params, edits, labels) bit for bit. `labels` / `previous_labels`: the part labels now and
// those the binding was made with (both null without separation); the skin points' labels must be
// the same, a cage vertex whose label changed counts as moved. A scale of 0 (h from the mean edge
// length) changes with any move and so every weight: fix BindParams::scale to binding.h first.
// Errors (bind again instead): another topology, a binding without reach, h that would change,
// point labels that differ.
Result<RestRebindReport> rebind_moved_rest(Binding& binding, std::span<const glm::vec3> skin, const Cage& cage,
                                           std::span<const glm::vec3> new_rest, std::span<const SetEdit> edits,
                                           const PartLabels* labels, const PartLabels* previous_labels);

// What rebind_new_topology did.
struct TopologyRebindReport {
  size_t kept_elements = 0;     // elements of the new cage standing where one of the old stood (rows kept)
  size_t removed_elements = 0;  // old elements with no such match
  size_t added_elements = 0;    // new elements with no such match
  size_t points = 0;            // skin points registered again
  double seconds = 0.0;
};

// The cage's topology changed since `binding` was made (an edit of core/document/topology_change.h:
// refine or flip some faces, merge or weld vertices): a new element whose corners stand exactly where
// an old element's stood (same positions in the same order, the same status and part labels) is the
// same element, and the rows of the points it alone drives are kept (their ids renumbered); only the
// points within reach of a removed or an added element, the points that follow their nearest element,
// and the points with a set edit (`edits` now or `previous_edits` at the bind: their element ids
// changed) are registered again. Afterwards `binding` equals bind_skin(skin, cage, new_rest,
// binding.params, edits, labels) bit for bit. `labels` / `previous_labels` as rebind_moved_rest.
// Errors (bind again instead): a binding without reach, a distance scale h that changes (a scale of
// 0: the mean edge length moves with the topology; fix BindParams::scale to binding.h first), skin
// labels that differ, kept elements whose order changes (ties between equally near elements are
// broken by id).
Result<TopologyRebindReport> rebind_new_topology(Binding& binding, std::span<const glm::vec3> skin, const Cage& cage,
                                                 std::span<const glm::vec3> new_rest, std::span<const SetEdit> edits,
                                                 std::span<const SetEdit> previous_edits, const PartLabels* labels,
                                                 const PartLabels* previous_labels);

}  // namespace cagewrap
