// Editing contributing sets (paper section 5 and Figure 5: "by removing the control elements of the
// right thigh from the contributing control element sets for points of the left leg we can get the
// desired behavior"; algorithm.md section 5, step 4). The editor's set tools pick skin points (a
// selection or a brush, core/document/skin_brush.h) and cage polygons, and apply one of four modes; the
// result is a new edit list, an input of registration (bind_skin, Rebinder::update), never a patch
// of the table. Edits name control elements; the user picks polygons, whose elements
// (Cage::element_face) are meant.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/deform/binding.h"
#include "core/cage/cage.h"
#include "core/base/result.h"
#include "core/geometry/selection.h"

namespace cagewrap {

enum class SetEditMode : uint8_t {
  kRemove,  // the faces' elements leave the points' sets: excluded (and no longer included)
  kAdd,     // they join the sets: included whatever their weight (and no longer excluded)
  kOnly,    // they become the only elements the sets may hold (SetEdit::only)
  kReset,   // the points' rules are dropped: automatic sets again (faces are not needed)
};
const char* set_edit_mode_name(SetEditMode mode);  // "remove", "add", "only", "reset"
bool parse_set_edit_mode(const std::string& name, SetEditMode& out);

// The canonical form of an edit list, which registration reads the same way as the list given:
// one edit per point (the last given wins), sorted by point; each list sorted without repeats; an
// element both excluded and included is only included; `exclude` empty when `only`; an edit with no
// rule left (not `only`, both lists empty) dropped.
std::vector<SetEdit> canonical_set_edits(std::span<const SetEdit> edits);

// The control elements of the given polygons, ascending (faces out of range are ignored).
std::vector<uint32_t> face_elements(const Cage& cage, const IndexSet& faces);

// The centroid (mean of the corners) of each polygon, #F x 3: what face mirror maps are built on.
std::vector<glm::vec3> face_centroids(const PolyMesh& mesh);

// X-mirroring of an edit: the mirrored points take the mirrored faces' elements.
struct SetEditMirror {
  const MirrorMap* points = nullptr;  // over the skin's rest positions
  const MirrorMap* faces = nullptr;   // over face_centroids() of the rest cage
  bool enabled() const { return points && faces; }
};

struct SetEditResult {
  std::vector<SetEdit> edits;              // canonical
  std::vector<uint32_t> changed_points;    // ascending: the points whose rules changed (re-register these)
  std::vector<uint32_t> unmatched_points;  // selected points with no mirror counterpart
  std::vector<uint32_t> unmatched_faces;   // selected faces with no mirror counterpart
};

// Applies `mode` with the elements of `faces` to the sets of `points`, and with `mirror` also with
// the mirrored faces' elements to the mirrored points (a point in both gets both). `edits` may be
// in any form (it is made canonical first). Errors: a point (>= num_points) or face out of range,
// named; a mode other than kReset with no faces.
Result<SetEditResult> apply_set_edit(std::span<const SetEdit> edits, SetEditMode mode, const IndexSet& points,
                                     const IndexSet& faces, const Cage& cage, size_t num_points,
                                     const SetEditMirror& mirror = {});

// The same with the elements given by id (a parametric driver's samples, core/deform/patch_binding.h): each of
// `points` takes `elements` (any order, duplicates ignored). Errors: a point or element out of range, named;
// a mode other than kReset with no elements. No mirroring.
Result<SetEditResult> apply_element_set_edit(std::span<const SetEdit> edits, SetEditMode mode, const IndexSet& points,
                                             std::span<const uint32_t> elements, size_t num_points, size_t num_elements);

}  // namespace cagewrap
