// An OpenGL 4.3+ core context with no window, for the GPU tests and `cagewrap bench --gpu`: EGL with
// no surface, so it runs on a machine with no display (a CI runner, a GPU server) as well as on a
// desktop. It tries, in order: the machine's hardware EGL devices (EGL_EXT_platform_device), the
// surfaceless platform (EGL_MESA_platform_surfaceless, which NVIDIA's driver has too), Mesa's
// software device, and the default display; CAGEWRAP_EGL_DEVICE=n picks device n alone.
#pragma once

#include <memory>
#include <string>

#include "core/base/result.h"

namespace cagewrap::render {

// Whether the current context's GL_RENDERER is Mesa's software rasterizer (llvmpipe, softpipe, swrast),
// where compute shaders and multisampling run on the CPU.
bool current_context_is_software();
// The antialiasing samples the editor draws with: `requested` when >= 0 (--msaa), else 4 on a GPU and
// none on a software OpenGL, where 4x multisampling made a 1280 x 720 frame of the demo take 100 ms
// instead of 41 (llvmpipe, two cores).
int editor_samples(int requested, bool software);

class HeadlessGl {
 public:
  // Creates the context and makes it current on this thread; fails with what was tried and why.
  static Result<std::unique_ptr<HeadlessGl>> create();
  ~HeadlessGl();
  HeadlessGl(const HeadlessGl&) = delete;
  HeadlessGl& operator=(const HeadlessGl&) = delete;

  // "GL_RENDERER, OpenGL GL_VERSION" of the context, and how it was reached.
  const std::string& description() const { return description_; }
  // Whether the context runs on Mesa's software rasterizer (llvmpipe, softpipe, swrast).
  bool software() const { return software_; }

 private:
  HeadlessGl() = default;
  void* display_ = nullptr;
  void* context_ = nullptr;
  std::string description_;
  bool software_ = false;
};

}  // namespace cagewrap::render
