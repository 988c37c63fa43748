// The memory-bandwidth probe of `cagewrap bench` (issue 24): a STREAM-like triad and read measured in
// the same run as the deform kernel, on the same threads, so that the kernel's achieved bandwidth is
// read as a fraction of what this machine streams now rather than as an absolute time.
#pragma once

#include <cstddef>

namespace cagewrap::app {

struct BandwidthProbe {
  double triad_gbps = 0;  // a[i] = b[i] + s c[i]: 12 bytes an element (STREAM's count: the write-allocate read is not counted)
  double read_gbps = 0;   // sum of one array: 4 bytes an element
  size_t array_bytes = 0; // each of the three arrays
  int threads = 0;
  int runs = 0;           // of each
};

// The best of `repeats` runs of each (STREAM's convention), on arrays of `array_bytes` (several times
// the last-level cache). On the 2-core machine one run's triad moved between 32 and 62 GB/s from one
// process to the next, so `cagewrap bench` measures it before and after its kernel timings and keeps
// the best of both (best_of).
BandwidthProbe measure_bandwidth(size_t array_bytes = size_t(64) << 20, int repeats = 10);
BandwidthProbe best_of(const BandwidthProbe& a, const BandwidthProbe& b);

}  // namespace cagewrap::app
