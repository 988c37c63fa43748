// Registration (section 3.2): which elements drive each skin point, and how much.
#pragma once

#include <atomic>
#include <functional>
#include <span>

#include "core/binding.h"

namespace cagewrap {

struct BindProgress {
  // Called from worker threads (must be thread-safe) with the share done in [0, 1].
  std::function<void(double)> on_progress;
  const std::atomic<bool>* cancel = nullptr;  // set to true to stop; bind returns kCancelled
};

// Binds the skin points to the cage at rest (R := the given positions). Bad elements (zero area,
// non-finite, duplicate) get no weight and are listed in the result; a point whose set is empty
// follows its nearest valid element. Errors: no valid elements, bad parameters, edits naming
// points or elements that do not exist, cancellation.
Result<Binding> bind_skin(std::span<const glm::vec3> skin, const Cage& cage, std::span<const glm::vec3> rest_positions,
                     const BindParams& params, std::span<const SetEdit> edits = {},
                     const BindProgress& progress = {});

// Reference implementation: a plain loop over all elements per point. Same sets and weights as
// bind(); used by the tests to check the hierarchy.
Result<Binding> bind_skin_brute_force(std::span<const glm::vec3> skin, const Cage& cage,
                                 std::span<const glm::vec3> rest_positions, const BindParams& params,
                                 std::span<const SetEdit> edits = {});

// The skin points that fail the cage-quality test (algorithm.md section 4: close to, within
// close_distance * h, and projecting inside some element of their set): sorted indices, as many as
// num_points - quality_inside. Registers the skin again against the binding's reference cage with
// the binding's parameters and h (the edits must be those it was bound with), so it costs a bind;
// the binding itself, its memory and the deformer are untouched. Errors: a skin of another size.
Result<std::vector<uint32_t>> quality_failures(const Binding& binding, std::span<const glm::vec3> skin,
                                               std::span<const SetEdit> edits = {});

// Weight function of eq. 1 on a distance already divided by h.
double falloff(double d, double local);
// Largest distance (in units of h) an element may have and still pass the relative threshold,
// given the nearest distance d_min: w_k >= eps * w_max  <=>  d_k <= radius.
double threshold_radius(double d_min, double local, double epsilon);

}  // namespace cagewrap
