// A Lipschitz figure for a binding (issue 18): how far apart the deformed skin can put two points
// that were close at rest, next to how much the cage itself stretches, and whether a skin point pops
// as the cage moves from rest to a pose.
//
// Space: along segments of densely spaced points (through the cage's interior, across its vertices of
// highest valence, across the max-distance boundary, through edited points), each segment is bound
// as a skin with the ordinary registration (bind_skin, what `cagewrap bind` runs) and deformed by the
// posed cage with the ordinary Deformer. The largest step between consecutive deformed points divided
// by the spacing (the "step ratio") is at most the map's local Lipschitz constant; for an affine cage
// motion it equals the stretch along the line. The same figure at half the spacing tells a steep but
// continuous map (the largest step halves: shrink about 0.5) from a jump (it does not: about 1).
// The figure of record is the worst step ratio over the cage's own largest stretch (the largest
// in-plane singular value of the map taking a rest triangle to its posed self).
//
// Time: the cage moves linearly (vertex by vertex) from rest to the pose in N steps; for every skin
// point, its largest step between two consecutive frames over its average step. A smooth motion
// gives about 1; a point that jumps when its contributing set changes gives more.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "core/deform/binding.h"
#include "core/deform/registration.h"

namespace cagewrap {

// At most this many samples per probe line (the half-spacing pass uses 2 x samples - 1), and at most
// this many probe points in all (every line, both spacings), checked before anything is allocated.
inline constexpr uint32_t kMaxProbeSamples = 1'000'000;
inline constexpr size_t kMaxProbePoints = 20'000'000;

// A segment of probe points a + t (b - a), t in [0, 1]. With `edit`, every point of the line is
// bound with that set edit (its `point` field is ignored).
struct ProbeLine {
  std::string what;
  glm::dvec3 a{0.0}, b{0.0};
  std::optional<SetEdit> edit;
};

// The distance scale h a bind with these parameters uses: params.scale, or the mean edge length of
// the cage's polygons at `rest_positions` when it is 0.
double probe_scale(const Cage& cage, std::span<const glm::vec3> rest_positions, const BindParams& params);

struct ProbeLineOptions {
  uint32_t valence_vertices = 5;   // (b) lines across this many vertices of highest valence
  uint32_t max_distance_lines = 3;  // (c) lines beyond the max distance (at the first of those vertices)
  uint32_t shells = 3;             // (a) a line through each of this many largest shells (when > 1)
  uint32_t edited_points = 5;      // (d) lines through this many edited skin points
};

// The automatic probe lines of a cage at rest (`h`: probe_scale):
//  (a) interior: through the centre of the cage's bounding box along x, y and z, spanning the box and
//      0.5 h beyond each side; when the cage has several shells (connected pieces of its valid
//      elements), also one through the box centre of each of the largest, along its longest side;
//  (b) across the vertices of highest valence (most valid elements around them; ties: lower index):
//      along the vertex normal from 0.5 h inside to 0.5 h outside, and tangent to the surface through
//      the point 0.1 h inside (0.5 h each way);
//  (c) with params.max_distance > 0: along those vertices' normals from 0.5 to 1.5 max_distance
//      outside, across the boundary beyond which no element drives a point;
//  (d) with `skin` and `edits`: through edited skin points (spread over the edit list), along the
//      normal of the nearest valid element, 0.5 h each way, every point carrying that point's edit.
// Lines that cannot be made (a zero normal, no valid element) are left out.
std::vector<ProbeLine> automatic_probe_lines(const Cage& cage, std::span<const glm::vec3> rest_positions,
                                             const BindParams& params, double h,
                                             std::span<const glm::vec3> skin = {}, std::span<const SetEdit> edits = {},
                                             const ProbeLineOptions& options = {});

// The largest in-plane stretch of the cage: over the elements valid at rest (classify_elements) whose
// posed corners are finite, the largest singular value of the linear map taking the rest triangle
// to the posed one (within their planes). 1 for a rigid motion, s for a uniform scale by s.
struct CageStretch {
  double stretch = 0.0;
  uint32_t element = 0;  // where it is largest
};
CageStretch cage_stretch(const Cage& cage, std::span<const glm::vec3> rest_positions,
                         std::span<const glm::vec3> posed_positions);

// The largest distance between consecutive points of a polyline, and where (the first point of that
// step). Zero for fewer than two points.
struct LargestStep {
  double step = 0.0;
  size_t at = 0;
};
LargestStep largest_step(std::span<const glm::vec3> points);

struct LineProbe {
  std::string what;
  glm::dvec3 a{0.0}, b{0.0};
  bool edited = false;
  double spacing = 0.0;          // |b - a| / (samples - 1)
  double step_ratio = 0.0;       // largest deformed step / spacing
  double at_t = 0.0;             // the line parameter of that step's middle
  glm::dvec3 at{0.0};            // its rest position
  double half_step_ratio = 0.0;  // the same with spacing / 2 (2 samples - 1 points)
  // Largest deformed step at spacing / 2 over the largest at spacing: about 0.5 where the map is
  // continuous along the line, about 1 across a jump (0 when the line does not move).
  double shrink = 0.0;
};

struct ProbeReport {
  Variant variant = Variant::kExtended;
  double h = 0.0;
  uint32_t samples = 0;
  std::vector<LineProbe> lines;
  CageStretch cage;
  double worst_ratio = 0.0;   // the largest step ratio over the lines (either spacing)
  size_t worst_line = 0;
  double worst_shrink = 0.0;  // the largest shrink over the lines
  size_t worst_shrink_line = 0;
  uint32_t rigid_points = 0;  // probe points with an empty set (following their nearest element rigidly)
  double seconds = 0.0;
  // worst_ratio / cage stretch: the figure of record (issue 18: at most 3). Infinite when the cage
  // collapses (stretch 0) and a line still moves; 0 when nothing moves.
  double figure() const;
};

// The thresholds of issue 18: no step larger than 3 x the cage's largest stretch; the largest step
// must shrink when the spacing halves (0.75: halfway between a continuous map's 0.5 and a jump's 1);
// no skin point's step between consecutive frames larger than 3 x its average step.
struct ProbeLimits {
  double max_ratio = 3.0;
  double max_shrink = 0.75;
  double max_time_ratio = 3.0;
};
bool ratio_passes(const ProbeReport& r, const ProbeLimits& limits = {});
bool continuity_passes(const ProbeReport& r, const ProbeLimits& limits = {});

// The probe points of `lines` at `samples` per line, in order (line 0's samples, line 1's, ...), with
// one set edit per point of an edited line: a skin for bind_skin. Checks the counts (samples in
// [3, kMaxProbeSamples], the total under kMaxProbePoints) and that every line is finite and of
// non-zero length, naming the line.
struct ProbeSkin {
  std::vector<glm::vec3> points;
  std::vector<SetEdit> edits;
};
Result<ProbeSkin> probe_line_points(std::span<const ProbeLine> lines, uint32_t samples);

// Binds the points of each line (at `samples` and at 2 samples - 1 per line) to the cage at
// `rest_positions` with `params` (bind_skin, one call per line; an edited line's points carry its
// edit), deforms them by `posed_positions` with the CPU Deformer and measures the steps. Each line is
// bound and deformed relative to its middle and to where that goes, so that the deformer's float
// positions are exact to about 1e-7 of the line's length, not of the scene's size: step ratios are
// then good to about samples x 1e-7. Errors: bad parameters, counts or lines, a posed cage of another
// size or with a non-finite vertex, a failed bind, cancellation (progress.cancel).
Result<ProbeReport> probe_lipschitz(const Cage& cage, std::span<const glm::vec3> rest_positions,
                                    std::span<const glm::vec3> posed_positions, const BindParams& params,
                                    std::span<const ProbeLine> lines, uint32_t samples = 2001,
                                    const BindProgress& progress = {});

struct TimeProbeReport {
  uint32_t steps = 0;
  size_t points = 0;    // skin points
  size_t measured = 0;  // points whose path is long enough to measure (min_path)
  double worst_ratio = 0.0;  // largest (largest step / average step) over the measured points
  uint32_t worst_point = 0;
  uint32_t worst_step = 0;   // the frame the largest step of that point ends at (1..steps)
  glm::dvec3 worst_rest{0.0};  // that point's rest position
  double seconds = 0.0;
};
bool time_passes(const TimeProbeReport& r, const ProbeLimits& limits = {});

// Binds `skin` (with `edits`, as bind_skin reads them) to the cage at rest and deforms it at
// `steps` + 1 cage states, vertex positions interpolated linearly from `rest_positions` (frame 0) to
// `posed_positions` (frame steps). A point counts when its path (the sum of its steps) is at least
// `min_path` times the rest cage's bounding-box diagonal: the deformer's float positions are exact
// to about 1e-7 of the scene size, which would dominate the steps of a point that barely moves.
// Errors: those of probe_lipschitz, steps outside [1, 100000].
Result<TimeProbeReport> probe_time_steps(const Cage& cage, std::span<const glm::vec3> rest_positions,
                                         std::span<const glm::vec3> posed_positions, const BindParams& params,
                                         std::span<const glm::vec3> skin, std::span<const SetEdit> edits = {},
                                         uint32_t steps = 200, double min_path = 1e-4,
                                         const BindProgress& progress = {});

}  // namespace cagewrap
