// What a topology edit of the cage (weld, flip, subdivide, refine) did, so that everything stored per
// cage vertex or per control element can follow it: the rest cage itself, the driver offsets, the
// user's contributing-set edits (algorithm.md section 5, step 4) and, later, skeleton attachments and
// keyposes. Every edit in core/document/cage_edit.h and core/document/cage_subdivide.h returns a CageEdit: the new cage
// and a CageTopologyChange from the old one; apply_topology_change() carries a Document across it.
//
// Vertices: each new vertex is an affine combination of old vertices (weights sum to one): a copy
// (one parent, weight 1), an edge midpoint (1/2, 1/2), a Loop stencil, the centroid of merged vertices.
// Elements: each new control element (a triangle of make_cage(new polygons)) lists the old elements
// it overlaps, found in the parent polygon's own surface (not from the new positions, so Loop's
// smoothing does not confuse it). An old element's children are the new elements listing it.
#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <span>
#include <string>
#include <vector>

#include "core/deform/binding.h"
#include "core/cage/cage.h"
#include "core/document/document.h"
#include "core/base/result.h"

namespace cagewrap {

struct CageTopologyChange {
  uint32_t old_vertices = 0;  // #V of the cage before
  uint32_t old_faces = 0;     // #F polygons before
  uint32_t old_elements = 0;  // #E control elements before

  // Per new vertex v: old parents vertex_parents[vertex_offsets[v] .. vertex_offsets[v+1]) (sorted
  // ids) with weights that sum to one.
  std::vector<uint32_t> vertex_offsets{0};  // #V'+1
  std::vector<uint32_t> vertex_parents;     // #entries, old vertex ids
  std::vector<double> vertex_weights;       // #entries

  std::vector<uint32_t> face_parent;  // #F' the old polygon each new polygon lies in

  // Per new element e: the old elements it overlaps, sorted; never empty.
  std::vector<uint32_t> element_offsets{0};  // #E'+1
  std::vector<uint32_t> element_parents;     // #entries, old element ids

  std::vector<uint32_t> dropped_faces;  // old polygons with no new polygon (collapsed by a merge), sorted

  size_t num_vertices() const { return vertex_offsets.size() - 1; }
  size_t num_faces() const { return face_parent.size(); }
  size_t num_elements() const { return element_offsets.size() - 1; }
  std::span<const uint32_t> parents_of_vertex(size_t v) const {
    return {vertex_parents.data() + vertex_offsets[v], vertex_offsets[v + 1] - vertex_offsets[v]};
  }
  std::span<const double> weights_of_vertex(size_t v) const {
    return {vertex_weights.data() + vertex_offsets[v], vertex_offsets[v + 1] - vertex_offsets[v]};
  }
  std::span<const uint32_t> parents_of_element(size_t e) const {
    return {element_parents.data() + element_offsets[e], element_offsets[e + 1] - element_offsets[e]};
  }
};

// The result of every cage topology edit.
struct CageEdit {
  Cage cage;                          // the new cage (polygons, and make_cage's elements)
  CageTopologyChange change;          // from the input cage to `cage`
  std::vector<std::string> warnings;  // e.g. "face 12 collapsed and was dropped"
};

// The change that does nothing to `cage`.
CageTopologyChange identity_change(const Cage& cage);

// `first` then `second` (second.old_* must equal first's new sizes: checked, aborts otherwise).
CageTopologyChange compose(const CageTopologyChange& first, const CageTopologyChange& second);

// Checks that `change` goes from `before` to `after` (sizes, parent ids in range, vertex weights sum
// to one); errors name the first mismatch.
Status check_change(const CageTopologyChange& change, const Cage& before, const Cage& after);

// The old vertex with the largest weight among new vertex v's parents (ties: the lowest old id).
uint32_t dominant_parent(const CageTopologyChange& change, size_t v);

// Children of each old element: ids[offsets[k] .. offsets[k+1]) are the new elements listing k.
struct ElementChildren {
  std::vector<uint32_t> offsets;  // #E_old + 1
  std::vector<uint32_t> ids;      // sorted per old element
  std::span<const uint32_t> of(size_t k) const {
    return {ids.data() + offsets[k], offsets[k + 1] - offsets[k]};
  }
};
ElementChildren element_children(const CageTopologyChange& change);

// Per-vertex attributes (old_values has change.old_vertices entries: checked, aborts otherwise).
// Continuous quantities (driver offsets, keypose offsets): the weighted sum of the parents' values.
std::vector<glm::vec3> interpolate_vertex_attribute(const CageTopologyChange& change,
                                                    std::span<const glm::vec3> old_values);
std::vector<double> interpolate_vertex_attribute(const CageTopologyChange& change,
                                                 std::span<const double> old_values);
// Labels (a cage vertex's joint): the value of the dominant parent.
std::vector<uint32_t> carry_vertex_labels(const CageTopologyChange& change,
                                          std::span<const uint32_t> old_labels);

// Set edits across the change: an edit naming old element k names all of k's children instead (for a
// merge, the surviving elements; an element with no child drops out). Edits left with no element are
// removed, except `only` edits (an `only` edit left with no element still empties the point's set).
// Errors: an edit naming an element the old cage does not have.
Result<std::vector<SetEdit>> carry_set_edits(const CageTopologyChange& change,
                                             std::span<const SetEdit> edits);

// The document with `edit.cage` as its rest cage, its driver offsets and keypose offsets
// interpolated (they live in joint bind space: interpolating them is exact when the parents follow
// the same joint, an approximation otherwise), its set edits carried, and its attachment overrides
// passed to each new vertex from its dominant parent (so are the simulation's pins; its masses and
// stiffnesses are interpolated). Errors: no cage in the document, or a change that does not
// start from the document's cage or end at edit.cage (kTopologyMismatch).
Result<Document> apply_topology_change(const Document& doc, const CageEdit& edit);

// ---- for the operations that build changes ----

// make_cage(polygons), then set_element_parents and set_dropped_faces: the CageEdit an operation
// returns. `change` has its vertex rows and face parents set.
Result<CageEdit> make_cage_edit(const Cage& before, PolyMesh polygons, CageTopologyChange change,
                                std::span<const glm::dvec3> corner_domain, std::vector<std::string> warnings);

// Fills change.element_offsets / element_parents for `after` = make_cage(new polygons).
// change.face_parent must be set. corner_domain: one point per corner of after.polygons (in
// face_vertices order): where that corner lies in its parent polygon, in the old cage's rest space
// (a subdivision's linear position, an old corner for a merge or a flip). Each new element's parents
// are the old elements of its parent polygon that its domain triangle overlaps with positive area
// (measured in the old polygon's best-fit plane); a degenerate one takes the old element nearest its
// centroid.
void set_element_parents(const Cage& before, const Cage& after, std::span<const glm::dvec3> corner_domain,
                         CageTopologyChange& change);
// Fills change.dropped_faces from change.face_parent.
void set_dropped_faces(CageTopologyChange& change);

// A selection as flags (#count): 1 for each id given. Errors: no id ("no faces given to flip", with
// `what` = "face" and `verb` = "flip"), an id out of range ("vertex 40 out of range: the cage has 30
// vertices"; `what` is "vertex" or "face").
Result<std::vector<uint8_t>> selection_mask(std::span<const uint32_t> ids, size_t count, const char* what,
                                            const char* verb);

}  // namespace cagewrap
