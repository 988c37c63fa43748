// What the editor shows of the contributing sets (paper section 5, Figure 5): one point's set with
// its normalized weights, a heat map of how much chosen cage polygons drive each point, and
// whole-skin maps (set sizes; empty, user-edited and badly bound points). All read the binding's
// set table (Binding::sets()) in one pass; none re-registers anything.
#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <span>
#include <vector>

#include "core/deform/binding.h"
#include "core/cage/cage.h"
#include "core/base/result.h"
#include "core/geometry/selection.h"

namespace cagewrap {

struct SetMember {
  uint32_t element;  // control element (Cage::elements)
  uint32_t face;     // the polygon it belongs to (Cage::element_face)
  float weight;      // normalized weight u_k
};

struct PointSet {
  std::vector<SetMember> members;  // strongest first (ties: lower element id)
  // A point with an empty set follows this element rigidly (-1 when the set is not empty).
  int64_t rigid_element = -1;
  bool edited = false;  // the point has a SetEdit
};

// Errors: no set table (an extended binding loaded from a version 1 file; bind again), a point out
// of range, a cage that is not the bound one (element count).
Result<PointSet> point_set(const Binding& binding, const Cage& cage, uint32_t point,
                           std::span<const SetEdit> edits = {});

// Per point (#P), the share of its deformation the given polygons drive: the sum of u_k over its set
// members on those polygons, in [0, 1] (a point following an element rigidly: 1 when that element is
// on them, else 0). Same errors as point_set.
Result<std::vector<float>> face_influence(const Binding& binding, const Cage& cage, const IndexSet& faces);

enum SetFlag : uint8_t {
  kSetEmpty = 1,    // no contributing element: follows its nearest element rigidly
  kSetEdited = 2,   // the point has a SetEdit
  kSetOutside = 4,  // fails the cage-quality test: not close to, or projecting outside, every member
};

struct SetOverview {
  std::vector<uint8_t> size;   // #P members of each set (at most 255 shown; K is at most 64 plus inclusions)
  std::vector<uint8_t> flags;  // #P SetFlag bits
  uint32_t empty = 0, edited = 0, outside = 0;  // counts of each flag
  uint32_t max_size = 0;
  double mean_size = 0.0;
};

// Whole-skin maps in one pass over the table. `skin`: the bound rest skin (#P x 3); `edits`: the
// document's. outside == num_points - binding.quality_inside (the same test, core/deform/registration.h
// well_bound). Errors: no set table, a skin of another size.
Result<SetOverview> set_overview(const Binding& binding, std::span<const glm::vec3> skin,
                                 std::span<const SetEdit> edits = {});

// The points with a SetEdit (ascending), for selecting them.
IndexSet edited_points(std::span<const SetEdit> edits);

}  // namespace cagewrap
