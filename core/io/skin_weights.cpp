#include "core/io/skin_weights.h"

#include <algorithm>
#include <cmath>

namespace cagewrap {

void SkinWeightCleanup::add_vertex(size_t v, const std::vector<std::pair<uint32_t, double>>& entries, Primitive& prim) {
  bool zero = false, negative = false;
  std::vector<std::pair<uint32_t, double>>& kept = kept_;  // reused: no allocation per vertex
  kept.clear();
  for (const auto& e : entries) {
    if (!(e.second > 0.0)) {
      if (e.second < 0.0) negative = true;
      else if (e.first != 0) zero = true;  // joint 0 with weight 0 is the usual padding
      continue;
    }
    kept.push_back(e);
  }
  std::sort(kept.begin(), kept.end());
  const size_t before = kept.size();
  size_t out = 0;
  for (size_t k = 0; k < kept.size(); ++k) {
    if (out > 0 && kept[out - 1].first == kept[k].first) kept[out - 1].second += kept[k].second;
    else kept[out++] = kept[k];
  }
  kept.resize(out);
  if (out < before && duplicates_++ == 0) dup_v_ = v;
  if (zero && zero_++ == 0) zero_v_ = v;
  if (negative && negative_++ == 0) negative_v_ = v;
  double sum = 0.0;
  for (const auto& e : kept) sum += e.second;
  if (kept.empty()) {
    if (unweighted_++ == 0) unweighted_v_ = v;
    kept.emplace_back(0u, 1.0);
    sum = 1.0;
  } else if (std::abs(sum - 1.0) > kSumTolerance && renormalized_++ == 0) {
    renormalized_v_ = v;
    renormalized_sum_ = sum;
  }
  std::sort(kept.begin(), kept.end(),
            [](const auto& a, const auto& b) { return a.second != b.second ? a.second > b.second : a.first < b.first; });
  if (prim.influence_start.empty()) prim.influence_start.push_back(0);
  for (const auto& e : kept) {
    prim.influence_joint.push_back(static_cast<uint16_t>(e.first));
    prim.influence_weight.push_back(static_cast<float>(e.second / sum));
  }
  prim.influence_start.push_back(static_cast<uint32_t>(prim.influence_joint.size()));
}

std::vector<std::string> SkinWeightCleanup::take_warnings(const std::string& label, const std::string& skin) {
  std::vector<std::string> w;
  auto n = [](size_t k) { return std::to_string(k); };
  if (renormalized_)
    w.push_back(label + ": " + n(renormalized_) + " vertices have weights that do not sum to one (e.g. vertex " +
                n(renormalized_v_) + " sums to " + std::to_string(renormalized_sum_) + "); renormalized");
  if (zero_)
    w.push_back(label + ": " + n(zero_) + " vertices list joints with zero weight (e.g. vertex " + n(zero_v_) + "); ignored");
  if (duplicates_)
    w.push_back(label + ": " + n(duplicates_) + " vertices list the same joint more than once (e.g. vertex " + n(dup_v_) +
                "); their weights were merged");
  if (negative_)
    w.push_back(label + ": " + n(negative_) + " vertices have negative weights (e.g. vertex " + n(negative_v_) + "); ignored");
  if (unweighted_)
    w.push_back(label + ": " + n(unweighted_) + " vertices have no non-zero weight (e.g. vertex " + n(unweighted_v_) +
                "); bound fully to joint 0 of " + skin);
  renormalized_ = zero_ = duplicates_ = unweighted_ = negative_ = 0;
  renormalized_v_ = zero_v_ = dup_v_ = unweighted_v_ = negative_v_ = 0;
  renormalized_sum_ = 0.0;
  return w;
}

}  // namespace cagewrap
