// Cleaning a vertex's skin weights as every loader does (glTF, and the formats read through assimp): joints
// listed twice merged, zero and negative weights dropped, the rest renormalised to sum to one, a vertex with
// none bound to joint 0; each kind of problem counted over a primitive and reported once, naming the first
// vertex it was seen on.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "core/character/character.h"

namespace cagewrap {

class SkinWeightCleanup {
 public:
  // Tolerance on the sum before renormalising counts as a problem (normalized 8-bit weights round to 1/255).
  static constexpr double kSumTolerance = 2e-3;

  // Appends vertex v's influences (joint, weight) to prim's CSR arrays, cleaned, largest first.
  void add_vertex(size_t v, const std::vector<std::pair<uint32_t, double>>& entries, Primitive& prim);
  // One line per kind of problem seen ("LABEL: 12 vertices have weights that do not sum to one (e.g. vertex 4
  // sums to 0.8); renormalized"), then counts reset. `skin` names the skin a weightless vertex is bound to.
  std::vector<std::string> take_warnings(const std::string& label, const std::string& skin);

 private:
  size_t renormalized_ = 0, zero_ = 0, duplicates_ = 0, unweighted_ = 0, negative_ = 0;
  size_t renormalized_v_ = 0, zero_v_ = 0, dup_v_ = 0, unweighted_v_ = 0, negative_v_ = 0;
  double renormalized_sum_ = 0.0;
  std::vector<std::pair<uint32_t, double>> kept_;  // add_vertex's scratch
};

}  // namespace cagewrap
