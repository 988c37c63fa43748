#include "app/bench_probe.h"

#include <algorithm>
#include <chrono>
#include <vector>

#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

namespace cagewrap::app {

namespace {

template <typename F>
double best_seconds(int repeats, F&& f) {
  f();  // first touch
  double best = 1e300;
  for (int k = 0; k < repeats; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  return best;
}

}  // namespace

BandwidthProbe measure_bandwidth(size_t array_bytes, int repeats) {
  const size_t n = std::max<size_t>(array_bytes / sizeof(float), 1024);
  std::vector<float> a(n, 0.f), b(n, 1.f), c(n, 2.f);
  const tbb::blocked_range<size_t> all(0, n, size_t(1) << 16);
  BandwidthProbe p;
  p.array_bytes = n * sizeof(float);
  p.threads = tbb::info::default_concurrency();
  p.runs = std::max(repeats, 1);
  const double triad = best_seconds(repeats, [&] {
    tbb::parallel_for(all, [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) a[i] = b[i] + 3.f * c[i];
    }, tbb::static_partitioner());
  });
  volatile float sink = 0.f;
  const double read = best_seconds(repeats, [&] {
    sink = tbb::parallel_reduce(all, 0.f, [&](const tbb::blocked_range<size_t>& r, float s) {
      float part[16] = {};  // independent sums, so that the adds' latency does not bound the loop
      size_t i = r.begin();
      for (; i + 16 <= r.end(); i += 16)
        for (int k = 0; k < 16; ++k) part[k] += a[i + k];
      for (; i != r.end(); ++i) s += a[i];
      for (float x : part) s += x;
      return s;
    }, [](float x, float y) { return x + y; }, tbb::static_partitioner());
  });
  (void)sink;
  p.triad_gbps = 3.0 * double(p.array_bytes) / triad / 1e9;
  p.read_gbps = double(p.array_bytes) / read / 1e9;
  return p;
}

BandwidthProbe best_of(const BandwidthProbe& a, const BandwidthProbe& b) {
  BandwidthProbe p = a;
  p.triad_gbps = std::max(a.triad_gbps, b.triad_gbps);
  p.read_gbps = std::max(a.read_gbps, b.read_gbps);
  p.runs = a.runs + b.runs;
  return p;
}

}  // namespace cagewrap::app
