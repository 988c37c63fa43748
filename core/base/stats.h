#pragma once
// Small statistics over timings and errors (benchmarks, the editor's frame split).

#include <algorithm>
#include <vector>

namespace cagewrap {

// The median of v (the upper one of an even count); 0 for none. Takes a copy: it reorders.
inline double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

}  // namespace cagewrap
