// The bench's interactive-parameter figures (issue 24): a candidate cache (core/deform/registration.h
// CandidateCache) made once, then slider drags of local, epsilon and K re-weighted from it, each
// with the new deformer table; with verification, every step is compared with a fresh bind.
#pragma once

#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "core/base/result.h"
#include "core/deform/binding.h"

namespace cagewrap::app {

struct ReweightStep {
  std::string slider;  // "local", "epsilon" or "K"
  double value = 0;
  double reweight_s = 0;  // CandidateCache::bind
  double table_s = 0;     // the new deformer's table (Deformer::create)
  uint64_t cached_points = 0, queried_points = 0;
  double fresh_s = -1;     // bind_skin with the same parameters (verification only)
  std::string difference;  // registration_difference to the fresh bind ("" = identical)
};

struct ReweightFigures {
  double cache_s = 0;
  size_t cache_bytes = 0;
  double entries_per_point = 0;
  std::vector<ReweightStep> steps;
  bool verified = false;
};

// The drags (from `params`): local -0.5, -1, +0.5, +1; epsilon x 0.7, 0.5, 1.5, 2; K -2, +2, +4, +8.
Result<ReweightFigures> bench_reweight(std::span<const glm::vec3> skin, const Cage& cage, std::span<const glm::vec3> rest,
                                       const BindParams& params, bool verify);

// A local topology edit after a bind (issue 24): one cage face refined (red-green, its neighbours
// split), the binding carried across it (core/deform/rest_edit.h rebind_new_topology, h kept), against
// a fresh bind of the refined cage.
struct TopologyEditFigures {
  uint32_t face = 0;
  size_t added_elements = 0, removed_elements = 0, points = 0;
  double seconds = 0, fresh_s = 0;
  std::string difference;  // registration_difference to the fresh bind ("" = identical)
};
Result<TopologyEditFigures> bench_topology_edit(std::span<const glm::vec3> skin, const Cage& cage,
                                                std::span<const glm::vec3> rest, const BindParams& params);

}  // namespace cagewrap::app
