// The GPU tests' GL context (tests/gpu_deformer_test.cpp, tests/gpu_stack_test.cpp): one headless
// OpenGL context for a test suite, and why the tests skip where there is no OpenGL 4.3 (the kernels'
// version). A suite derives from GlSuite and calls skip_without_gl(what) first in its SetUp.
#pragma once

#if CAGEWRAP_GUI

#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "render/gpu_deformer.h"
#include "render/headless_gl.h"

namespace cagewrap::test {

class GlSuite : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    auto gl = render::HeadlessGl::create();
    if (!gl) {
      skip_reason_ = gl.error().message;
      return;
    }
    gl_ = std::move(gl).value();
    skip_reason_ = render::GpuDeformer::unsupported_reason();
  }
  static void TearDownTestSuite() { gl_.reset(); }
  // Whether the suite has no GL context to run in (then GTEST_SKIP, saying what is not tested).
  static bool no_gl() { return !skip_reason_.empty(); }
  static const std::string& no_gl_reason() { return skip_reason_; }

 private:
  static inline std::unique_ptr<render::HeadlessGl> gl_;
  static inline std::string skip_reason_;
};

}  // namespace cagewrap::test

#endif  // CAGEWRAP_GUI
