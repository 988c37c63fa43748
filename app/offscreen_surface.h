// The editor with no window: a headless OpenGL 4.3 context (render/headless_gl.h, EGL, no display)
// and a multisampled framebuffer of the window's size that the editor draws into instead of a
// window. `cagewrap --offscreen` uses it to run scripted sessions and measure frame times on a GPU
// server or a CI runner that has no X server. There is no input: the script drives the editor.
#pragma once

#include <memory>
#include <string>

#include "core/base/result.h"
#include "render/headless_gl.h"

namespace cagewrap::app {

class OffscreenSurface {
 public:
  // Opens the context and a width x height framebuffer with `samples` samples (0 = none; < 0: the editor's
  // choice for the context, render::editor_samples), bound for
  // drawing. Fails with what was tried (no EGL, no 4.3 context, an incomplete framebuffer).
  static Result<std::unique_ptr<OffscreenSurface>> create(int width, int height, int samples);
  ~OffscreenSurface();
  OffscreenSurface(const OffscreenSurface&) = delete;
  OffscreenSurface& operator=(const OffscreenSurface&) = delete;

  int width() const { return width_; }
  int height() const { return height_; }
  const std::string& description() const { return gl_->description(); }
  // Binds the drawing framebuffer (the editor's frame starts here, as with a window's back buffer).
  void begin_frame() const;
  // Resolves the multisampled frame into the single-sampled one and waits for the GL to finish it,
  // as a blocking buffer swap would (so a frame's time includes its GPU work).
  void end_frame() const;
  // Resolves the frame and leaves it bound for glReadPixels (GL_COLOR_ATTACHMENT0).
  void bind_for_reading() const;

 private:
  OffscreenSurface() = default;
  void resolve() const;
  std::unique_ptr<render::HeadlessGl> gl_;
  int width_ = 0, height_ = 0;
  unsigned draw_fbo_ = 0, resolve_fbo_ = 0;
  unsigned color_ = 0, depth_ = 0, resolved_color_ = 0;
};

}  // namespace cagewrap::app
