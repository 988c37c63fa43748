// The analytic twist of the bench triplets (../shared/assets/bench/<asset>/inputs.json, "twist"):
// a smoothstep-profiled rotation about an axis, used as the reference a good deformer approaches.
#pragma once

#include <span>
#include <string>

#include <glm/vec3.hpp>

#include "core/base/result.h"

namespace cagewrap {

struct Twist {
  int axis = 1;
  glm::dvec3 center{0.0};
  double lo = 0, hi = 1;
  double degrees = 0;
  glm::dvec3 apply(const glm::dvec3& p) const;
};

Result<Twist> load_twist(const std::string& inputs_json_path);

// RMS and max distance between two point sets of equal size, divided by `diagonal`. Sets of different
// sizes are a programming error: the call prints both sizes and aborts (in every build type).
struct Fidelity {
  double rms = 0, max = 0;
};
Fidelity relative_distance(std::span<const glm::vec3> a, std::span<const glm::vec3> b, double diagonal);

}  // namespace cagewrap
