#include "render/gpu_timer.h"

#include <cstdint>

#include "core/base/check.h"

namespace cagewrap::render {

GpuTimer::GpuTimer(size_t sections, size_t in_flight) : sections_(sections) {
  CAGEWRAP_CHECK(in_flight > 0, "at least one query per section");
  for (auto& s : sections_) {
    s.queries.resize(in_flight);
    glGenQueries(static_cast<GLsizei>(in_flight), s.queries.data());
    s.pending.assign(in_flight, 0);
    s.ended_at.assign(in_flight, 0);
  }
}

GpuTimer::~GpuTimer() {
  for (auto& s : sections_) glDeleteQueries(static_cast<GLsizei>(s.queries.size()), s.queries.data());
}

void GpuTimer::collect(Section& s, size_t q, bool wait) {
  if (!s.pending[q]) return;
  if (!wait) {
    GLint available = 0;
    glGetQueryObjectiv(s.queries[q], GL_QUERY_RESULT_AVAILABLE, &available);
    if (!available) return;
  }
  GLuint64 ns = 0;
  glGetQueryObjectui64v(s.queries[q], GL_QUERY_RESULT, &ns);
  s.pending[q] = 0;
  if (s.ended_at[q] >= s.newest_order) {
    s.newest_order = s.ended_at[q];
    s.newest_ms = ns * 1e-6;
  }
}

void GpuTimer::begin(size_t section) {
  CAGEWRAP_CHECK(section < sections_.size(), "a section this timer has");
  Section& s = sections_[section];
  collect(s, s.next, true);  // the oldest query in flight: long finished in a frame loop
  glBeginQuery(GL_TIME_ELAPSED, s.queries[s.next]);
}

void GpuTimer::end(size_t section) {
  CAGEWRAP_CHECK(section < sections_.size(), "a section this timer has");
  Section& s = sections_[section];
  glEndQuery(GL_TIME_ELAPSED);
  s.pending[s.next] = 1;
  s.ended_at[s.next] = ++counter_;
  s.last = s.next;
  s.next = (s.next + 1) % s.queries.size();
}

double GpuTimer::ms(size_t section) {
  CAGEWRAP_CHECK(section < sections_.size(), "a section this timer has");
  Section& s = sections_[section];
  for (size_t q = 0; q < s.queries.size(); ++q) collect(s, q, false);
  return s.newest_ms;
}

double GpuTimer::wait_ms(size_t section) {
  CAGEWRAP_CHECK(section < sections_.size(), "a section this timer has");
  Section& s = sections_[section];
  if (s.last == SIZE_MAX) return -1.0;
  collect(s, s.last, true);
  return s.newest_ms;
}

}  // namespace cagewrap::render
