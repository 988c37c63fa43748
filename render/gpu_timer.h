// GPU time of sections of work, measured with OpenGL timer queries (GL_TIME_ELAPSED, GL 3.3).
// Sections are numbered and must not overlap (GL allows one elapsed-time query at a time). Each
// keeps a few queries in flight, so a frame loop reads the newest finished figure without waiting
// for the GPU; a benchmark waits for each figure instead.
#pragma once

#include <epoxy/gl.h>

#include <cstdint>
#include <vector>

namespace cagewrap::render {

class GpuTimer {
 public:
  explicit GpuTimer(size_t sections, size_t in_flight = 4);
  ~GpuTimer();
  GpuTimer(const GpuTimer&) = delete;
  GpuTimer& operator=(const GpuTimer&) = delete;

  void begin(size_t section);
  void end(size_t section);
  // The newest finished measurement of the section in milliseconds, without waiting; negative
  // before the first one has finished.
  double ms(size_t section);
  // Waits for the section's last ended query and returns it in milliseconds.
  double wait_ms(size_t section);

 private:
  struct Section {
    std::vector<GLuint> queries;
    std::vector<uint8_t> pending;  // ended, result not read yet
    std::vector<uint64_t> ended_at;  // order in which queries were ended
    size_t next = 0;
    size_t last = SIZE_MAX;  // the query ended most recently
    uint64_t newest_order = 0;
    double newest_ms = -1.0;
  };
  void collect(Section& s, size_t q, bool wait);
  std::vector<Section> sections_;
  uint64_t counter_ = 0;
};

}  // namespace cagewrap::render
