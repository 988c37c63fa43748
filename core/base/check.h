// CAGEWRAP_CHECK(condition, message): a precondition on the caller that stays on in release builds.
// For programming errors only (a span of the wrong length); bad data returns a Result instead.
#pragma once

#include <cstdio>
#include <cstdlib>

namespace cagewrap {

[[noreturn]] inline void check_failed(const char* condition, const char* message, const char* file, int line) {
  std::fprintf(stderr, "%s:%d: check failed: %s (%s)\n", file, line, condition, message);
  std::abort();
}

}  // namespace cagewrap

#define CAGEWRAP_CHECK(condition, message) \
  do {                                     \
    if (!(condition)) ::cagewrap::check_failed(#condition, message, __FILE__, __LINE__); \
  } while (0)
