// Registration (section 3.2): which elements drive each skin point, and how much.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <span>
#include <string>

#include "core/deform/binding.h"

namespace cagewrap {

// Part labels for automatic separation (BindParams::separate). Labels are the nodes of a forest
// (for a character: skeleton nodes, core/deform/part_labels.h); a point and an element are connected when
// the point's label and a label of one of the element's corners are at most
// BindParams::separation_steps edges apart in it, or either is unlabelled. Only connected elements
// may drive a point (they act like user exclusions: before the threshold).
struct PartLabels {
  static constexpr uint32_t kUnlabelled = UINT32_MAX;
  std::vector<int32_t> parent;        // #L parent of each label, -1 for a root
  std::vector<uint32_t> point;        // #P label of each skin point (or kUnlabelled)
  std::vector<uint32_t> cage_vertex;  // #Vc label of each cage vertex (or kUnlabelled)
  // Optional #L x #L (row-major): label pairs that are one part whatever their hierarchy steps
  // (a chain of short bones, core/deform/part_labels.h chained_nodes); empty = the steps alone.
  std::vector<uint8_t> related;
  // Optional (#P and #Vc, or empty): the cage shell owning each skin point (kUnlabelled: none) and
  // each cage vertex's shell (core/cage/cage_shells.h); an owned point may use only its shell's elements.
  std::vector<uint32_t> point_shell;
  std::vector<uint32_t> vertex_shell;
  // Optional (#L each, or empty): each label's joint head and bone length in the bind pose. With them,
  // an element spanning two sibling parts (the thighs under the hips) bridges them only away from
  // where they branch: farther from both heads than half the shorter bone (the crotch's elements
  // span both thighs and stay; those between legs held together further down do not).
  std::vector<glm::vec3> head;
  std::vector<float> length;
  bool empty() const { return parent.empty(); }
  bool operator==(const PartLabels&) const = default;
};

struct BindProgress {
  // Called from worker threads (must be thread-safe) with the share done in [0, 1].
  std::function<void(double)> on_progress;
  const std::atomic<bool>* cancel = nullptr;  // set to true to stop; bind returns kCancelled
};

// Binds the skin points to the cage at rest (R := the given positions). Bad elements (zero area,
// non-finite, duplicate) get no weight and are listed in the result; a point whose set is empty
// follows its nearest valid element. `labels` (may be null or empty) drive the automatic
// separation when params.separate is set. Errors: no valid elements, bad parameters, edits naming
// points or elements that do not exist, labels of the wrong size or out of range, cancellation.
// Edits are read as canonical_set_edits (core/deform/set_editing.h) reads them: one per point, the last given
// wins, an element both excluded and included is included.
Result<Binding> bind_skin(std::span<const glm::vec3> skin, const Cage& cage, std::span<const glm::vec3> rest_positions,
                     const BindParams& params, std::span<const SetEdit> edits = {},
                     const BindProgress& progress = {}, const PartLabels* labels = nullptr);

// Reference implementation: a plain loop over all elements per point. Same sets and weights as
// bind(); used by the tests to check the hierarchy.
Result<Binding> bind_skin_brute_force(std::span<const glm::vec3> skin, const Cage& cage,
                                 std::span<const glm::vec3> rest_positions, const BindParams& params,
                                 std::span<const SetEdit> edits = {}, const PartLabels* labels = nullptr);

// Re-registration of some points only, for live set editing: what bind_skin builds once per cage
// and parameters (element statuses, h, the hierarchy, the label relation) is kept, so a brush
// stroke costs only its points. The result is exactly what bind_skin gives with the same inputs
// (same floats, bit for bit), for the points re-registered and for the rest.
// Keeps references to `skin`, `cage`, `rest_positions` and `labels`: they must outlive it.
class Rebinder {
 public:
  static Result<Rebinder> create(std::span<const glm::vec3> skin, const Cage& cage,
                                 std::span<const glm::vec3> rest_positions, const BindParams& params,
                                 const PartLabels* labels = nullptr);

  // The distance scale it registers with (BindParams::scale, or the rest cage's mean edge length).
  double h() const;

  // A full bind (bind_skin) with the kept state.
  Result<Binding> bind(std::span<const SetEdit> edits, const BindProgress& progress = {}) const;

  // Re-registers `points` (any order, repeats allowed) under `edits` (the full list; only the
  // edits of these points are read, but all are checked) and splices their stencils, sets,
  // fallbacks and report figures into `binding`, which must come from this skin, cage and
  // parameters (checked: kTopologyMismatch / kInvalidArgument). Other points are left alone. A
  // Deformer reading `binding` must then be told: Deformer::stencil_changed().
  Status update(Binding& binding, std::span<const SetEdit> edits, std::span<const uint32_t> points) const;

  // Moving reference cage vertices (same topology): `binding` was made for another rest cage, this
  // Rebinder for the moved one. Re-registers `points` as update() does (on the new rest cage) and
  // takes the new rest cage and element statuses. The result equals a full bind on the moved cage
  // when `points` holds every point whose registration can change: core/deform/rest_edit.h
  // ReachIndex::affected_points finds them. Errors: another topology, skin or parameters, and a
  // move that changes h (the mean cage edge length when BindParams::scale is 0: every weight
  // changes; bind again or fix the scale).
  // A Deformer reading `binding` keeps frames of the old rest cage: make it again (Deformer::create).
  Status move_rest(Binding& binding, std::span<const SetEdit> edits, std::span<const uint32_t> points) const;

  Rebinder(Rebinder&&) noexcept;
  Rebinder& operator=(Rebinder&&) noexcept;
  ~Rebinder();

 private:
  struct State;
  Rebinder() = default;
  Status update_points(Binding& binding, std::span<const SetEdit> edits, std::span<const uint32_t> points) const;
  std::unique_ptr<State> state_;
};

// Re-weighting from cached candidates, for parameter edits (local, epsilon, K, max distance, the
// scale h, the separation steps, the variant, set edits): per skin point, every valid element within a
// radius, gathered once per skin, cage, rest positions and labels with the hierarchy. bind() then
// registers with any parameters from these lists, and asks the hierarchy only for the points whose
// needed radius (needed_radius2) under those parameters exceeds what their list covers (a slider
// dragged far from where the cache was made). Its result equals bind_skin with the same inputs, bit
// for bit, whatever the parameters. Owns copies of its inputs (a background job may use it while the
// document changes); bind() may run on several threads at once.
struct CandidateCacheStats {
  uint64_t cached_points = 0;   // registered from their lists
  uint64_t queried_points = 0;  // asked the hierarchy (their lists fell short)
};
class CandidateCache {
 public:
  // Each point's list covers what the parameters cover_params(params) need (with its nearest
  // allowed elements under `labels`): every valid element within that radius, whatever its labels.
  // Lists are capped at kMaxEntries per point (the cover shrinks to the last one kept).
  static Result<CandidateCache> create(std::span<const glm::vec3> skin, const Cage& cage,
                                       std::span<const glm::vec3> rest_positions, const BindParams& params,
                                       const PartLabels* labels = nullptr, const BindProgress& progress = {});
  // The parameters a cache made around `params` is sized for: K doubled (at least + 8, at most 64),
  // epsilon quartered, local lowered by one (halved below 1): a wider threshold radius and tie band.
  static BindParams cover_params(const BindParams& params);
  static constexpr uint32_t kMaxEntries = 192;

  // bind_skin(skin, cage, rest, params, edits, progress, labels) from the cache.
  Result<Binding> bind(const BindParams& params, std::span<const SetEdit> edits = {}, const BindProgress& progress = {},
                       CandidateCacheStats* stats = nullptr) const;
  // Whether it was made for this skin, cage, rest positions and labels (compared in full).
  bool fits(std::span<const glm::vec3> skin, const Cage& cage, std::span<const glm::vec3> rest_positions,
            const PartLabels* labels) const;

  size_t num_points() const;
  uint64_t entries() const;  // cached elements, all points
  size_t bytes() const;      // the lists and per-point covers (not the copies of the inputs)
  double seconds() const;    // time taken to make it

  CandidateCache(CandidateCache&&) noexcept;
  CandidateCache& operator=(CandidateCache&&) noexcept;
  ~CandidateCache();
  struct State;

 private:
  CandidateCache() = default;
  std::unique_ptr<State> state_;
};

// The first table in which two bindings' registrations differ ("offsets", "weights", "reach", ...;
// floats compared bit for bit), or an empty string when every table and report figure is the same
// (the time taken apart).
std::string registration_difference(const Binding& a, const Binding& b);

// One-off form: `binding` with `points` re-registered (a copy; see Rebinder::update).
Result<Binding> rebind_points(const Binding& binding, std::span<const glm::vec3> skin, const Cage& cage,
                              std::span<const glm::vec3> rest_positions, const BindParams& params,
                              std::span<const SetEdit> edits, std::span<const uint32_t> points,
                              const PartLabels* labels = nullptr);

// The cage-quality test of one point of a binding (algorithm.md section 4): within
// close_distance * h of, and projecting inside, a member of its set (or the element it follows when
// its set is empty). Binding::quality_inside counts the points that pass. `skin`: the bound rest
// skin (#P x 3).
bool well_bound(const Binding& binding, std::span<const glm::vec3> skin, uint32_t point);

// The skin points that fail the cage-quality test (algorithm.md section 4: close to, within
// close_distance * h, and projecting inside some element of their set): sorted indices, as many as
// num_points - quality_inside: well_bound() over every point of the binding's own sets (which hold
// the edits it was made with; `edits` is ignored and kept for callers). Errors: a skin of another size.
Result<std::vector<uint32_t>> quality_failures(const Binding& binding, std::span<const glm::vec3> skin,
                                               std::span<const SetEdit> edits = {});

// The points' indices ordered along a Morton curve, so that runs of consecutive entries are
// spatially compact (registration's chunks, core/deform/rest_edit.h's leaves).
std::vector<uint32_t> morton_order(std::span<const glm::vec3> points);

// Weight function of eq. 1 on a distance already divided by h.
double falloff(double d, double local);
// Ties at the cap (docs/algorithm-notes.md "Near-ties at the cap"): where the (K+1)-th candidate, or the
// max distance, nearly ties the nearest element (d^local within a factor 1 + kTieBand of the nearest's),
// the cut of the taper is held at that band's edge, and every element inside it joins the set (K is
// exceeded there, up to kMaxTiedMembers, and so is the max distance). The nearest member then always
// keeps a weight of the order of its own, and the normalised weights never divide tiny differences.
// kTieFloor (units of h) keeps a band for skin lying on the cage.
inline constexpr double kTieBand = 7.0;  // d within a factor 8^(1/local) of the nearest: 1.68 at local 4
inline constexpr double kTieFloor = 1e-2;
inline constexpr size_t kMaxTiedMembers = 64;

// The taper (docs/algorithm-notes.md): the weight c at which an element enters or leaves a point's set,
// subtracted from every automatic member's weight so that sets change at zero weight:
//   c = max(epsilon f(d_1), min(max(f(d_K+1), f(max distance)), f(d_tie))),  d_tie^local = (1 + kTieBand) d_1^local
//                                                                            + kTieBand kTieFloor^local,
// raised to f(d_M+1) where more than M = kMaxTiedMembers elements pass. With p = d^local, f = 1 / (1 + p)
// and c = 1 / (1 + q), a member's weight f - c = (q - p) / ((1 + p)(1 + q)) is computed in that form (no
// cancellation for skin on the cage), and in units of max(1, d_1^local) (no overflow for any `local`).
class Taper {
 public:
  // `dist`: the point's automatic candidates (user inclusions apart), ascending, in units of h: every
  // element within needed_radius of it (more are harmless).
  Taper(const BindParams& params, double h, std::span<const double> dist);
  // The weight of automatic candidate i (0: not a member), on the common scale of raw().
  double weight(size_t i) const;
  // Every candidate's weight into `w` (#dist); returns their sum. 0 when no candidate has a weight
  // (every one at the cut: epsilon = 1, or more than kMaxTiedMembers exact ties); the point then takes
  // plain eq. 1 weights (raw) over its first K candidates.
  double weights(std::span<double> w) const;
  // Eq. 1 weight f(d) of a user inclusion at distance d (units of h), on the same scale: inclusions keep
  // their own weight and are never tapered.
  double raw(double d) const;

 private:
  double ratio(double d) const;  // d^local in units of the scale
  std::span<const double> dist_;
  double local_ = 0, d1_ = 0, u_ = 1, q_ = 0;
  bool scaled_ = false;
};
// Squared radius (world units) within which every automatic candidate of a point must be known for its
// weights to be exact. Squared distances: `best2` of the nearest candidate, `next2` of the (K+1)-th and
// `last2` of the (kMaxTiedMembers+1)-th (infinite where there are not that many), `radius2` the threshold
// radius of the nearest.
double needed_radius2(const BindParams& params, double h, double best2, double next2, double last2, double radius2);
// The tie band's squared radius (world units) given the nearest candidate's squared distance.
double tie_band2(const BindParams& params, double h, double best2);
// Largest distance (in units of h) an element may have and still pass the relative threshold,
// given the nearest distance d_min: w_k >= eps * w_max  <=>  d_k <= radius.
double threshold_radius(double d_min, double local, double epsilon);

}  // namespace cagewrap
