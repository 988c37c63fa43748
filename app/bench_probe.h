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
};

// Medians over `repeats` runs of each, on arrays of `array_bytes` (several times the last-level cache).
BandwidthProbe measure_bandwidth(size_t array_bytes = size_t(64) << 20, int repeats = 10);

}  // namespace cagewrap::app
