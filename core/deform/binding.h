// The registration result of the surface-oriented deformer, as a flat stencil table.
//
// This work is based on:
//   K. Singh and E. Kokkevis, "Skinning Characters using Surface-Oriented Free-Form Deformations",
//   Graphics Interface 2000 (see ../shared/docs/algorithm.md for every formula and decision).
//
// Storage. Eq. 2 gives each element k an affine frame Q_k = [e1 e2 e3] with origin A_k, and a point's
// local coordinates l = Q_k^-1 (P - A_k). Deforming with the driver frame (eq. 3 per element) gives
// P_def_k = A'_k + Q'_k Q_k^-1 (P - A_k), an affine map T_k(P) that depends on the cage alone. The
// table therefore stores, per point, the element ids and normalized weights u_k; the local
// coordinates are folded into T_k, which the deformer rebuilds once per cage change (a few thousand
// maps) and applies to the rest position P. This is algebraically eq. 3, and it is 8 bytes per
// contributing element instead of 20. The clamped variant also stores the barycentric coordinates
// of the closest point (its anchor); the extended variant collapses to a per-point list of cage
// vertices with weights W_j = sum_k u_k b_kj (its frames are per vertex).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "core/cage/cage.h"

namespace cagewrap {

enum class Variant : uint8_t { kBasic = 0, kClamped = 1, kExtended = 2 };
const char* variant_name(Variant v);
bool parse_variant(const std::string& s, Variant& out);

struct BindParams {
  double local = 4.0;           // falloff exponent of f(d) = 1 / (1 + d^local)
  double epsilon = 0.1;         // relative weight threshold: keep w_k >= epsilon * max w
  uint32_t max_elements = 8;    // K: at most this many strongest elements per point
  double scale = 0.0;           // h: distances are measured in units of h; 0 = mean cage edge length
  double max_distance = 0.0;    // world units; elements farther than this drive a point only where they nearly tie its nearest element (registration.h Taper); 0 = none
  double close_distance = 1.0;  // in units of h: "close" for the cage-quality figure (algorithm.md section 4)
  Variant variant = Variant::kExtended;  // most faithful in the bench (docs/benchmarks.md)
  // Automatic separation (beyond the paper; docs/algorithm-notes.md): an element may drive a point
  // only when their part labels (PartLabels, an input of bind_skin: for a character, the point's
  // dominant joint and the joints its corners follow) are at most `separation_steps` apart in the
  // label hierarchy. Without labels nothing is separated.
  bool separate = true;
  uint32_t separation_steps = 1;  // 1: the same bone, its parent or a child

  bool operator==(const BindParams&) const = default;
};

// Checks ranges; names the offending parameter.
Status validate(const BindParams& params);
// A skin to bind: at least one vertex, every coordinate finite (the error names the vertex).
Status check_skin(std::span<const glm::vec3> skin);

// User edits of contributing sets, an input of registration (so editing is a parameter, not a patch).
// Exclusions act before the threshold (an excluded element does not exist for that point), inclusions
// apart from it: an included element joins the set with its own eq. 1 weight f(d), never tapered and
// not counted in K, so that its weight does not jump as it crosses the rule's threshold or the K-th rank.
// `only`: the set may hold nothing but the `include` elements (every other element is excluded), a
// compact form of "exclude the rest" for the "make these the only ones" edit. core/deform/set_editing.h builds
// canonical edits (one per point, sorted lists, no element in both, `exclude` empty when `only`).
struct SetEdit {
  uint32_t point;
  std::vector<uint32_t> exclude;  // element ids
  std::vector<uint32_t> include;  // element ids
  bool only = false;

  bool operator==(const SetEdit&) const = default;
  // Whether the edit removes element e from the point's candidates (before the threshold). The
  // lists must be sorted (canonical edits are).
  bool excludes(uint32_t e) const;
};

struct Binding {
  BindParams params;
  double h = 1.0;                // the distance scale actually used
  glm::dvec3 origin{0.0};        // all maps are expressed relative to this point (float precision)
  uint32_t num_points = 0;
  uint32_t num_cage_vertices = 0;
  // A sample-driven binding (a parametric driver, core/deform/patch_binding.h) when > 0: the stencil's ids
  // name these driver samples, the variant is basic, and there is no cage (no rest_cage, elements
  // or fallback points); the maps come from the driver (Deformer::deform_with_maps).
  uint32_t num_samples = 0;
  std::vector<glm::vec3> rest_cage;  // #Vc x 3 reference cage R
  std::vector<Tri> elements;         // #E control elements of R
  std::vector<ElementStatus> element_status;  // #E

  // Main stencil. basic/clamped: ids are elements; extended: ids are cage vertices.
  std::vector<uint32_t> offsets;  // #P+1
  std::vector<uint32_t> ids;      // #entries
  std::vector<float> weights;     // #entries, sum to 1 per point
  std::vector<float> bary;        // clamped only: #entries x 2, (b1, b2) of the anchor; b0 = 1 - b1 - b2

  // The contributing sets C_P themselves (element ids, normalized weights u_k, strongest first), for
  // display and editing (core/document/set_queries.h). The basic and clamped stencils are these sets, so
  // these stay empty for them; the extended stencil lists cage vertices, so its sets are kept here.
  // Use sets(), which picks the right table.
  std::vector<uint32_t> set_offsets;  // #P+1 (extended), else empty
  std::vector<uint32_t> set_ids;      // #members
  std::vector<float> set_weights;     // #members

  // Points whose contributing set came out empty follow their nearest valid element rigidly.
  std::vector<uint32_t> rigid_points;   // point indices
  std::vector<uint32_t> rigid_element;  // element each follows
  std::vector<float> rigid_bary;        // x 2, anchor on that element

  // Report
  std::vector<uint32_t> invalid_elements;  // ids of elements with status != kValid
  uint32_t quality_inside = 0;             // points close to and projecting inside some set element
  uint32_t max_set_size = 0;
  uint64_t total_set_size = 0;             // sum of |C_P| (elements, before the extended collapse)
  // Automatic separation: whether part labels were applied, and per point (#P when they were, else
  // empty) how many elements they kept out of its reach: elements of unconnected parts nearer than
  // the point's (K+1)-th nearest allowed element and within its threshold radius, which would
  // otherwise have competed for its set.
  bool separation_applied = false;
  std::vector<uint32_t> separated;  // #P
  uint64_t total_separated = 0;     // sum of `separated`
  uint32_t separated_points = 0;    // points with separated > 0
  double seconds = 0.0;
  // Per point (#P; empty for a binding read from a file, which does not store it): the distance
  // from the point within which lies every element its registration depends on (its threshold
  // radius, or nearer its (K+1)-th nearest allowed element), rounded up; infinite for a point
  // that follows its nearest element. Moving cage elements farther than this leaves the point's
  // registration as it is (core/deform/rest_edit.h). Not read by the deformer.
  std::vector<float> reach;

  struct SetsView {
    std::span<const uint32_t> offsets;  // #P+1
    std::span<const uint32_t> ids;      // element ids
    std::span<const float> weights;     // u_k
    std::span<const uint32_t> of(uint32_t point) const {
      return ids.subspan(offsets[point], offsets[point + 1] - offsets[point]);
    }
  };
  // The contributing sets, whatever the variant (the main stencil for basic and clamped).
  SetsView sets() const;
  bool has_sets() const { return params.variant != Variant::kExtended || set_offsets.size() == size_t(num_points) + 1; }

  size_t num_entries() const { return ids.size(); }
  double quality() const { return num_points ? double(quality_inside) / num_points : 0.0; }
  size_t bytes() const;
};

}  // namespace cagewrap
