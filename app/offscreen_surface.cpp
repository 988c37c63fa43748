#if CAGEWRAP_GUI  // the editor and its GL exist only in GUI builds
#include "app/offscreen_surface.h"

#include <epoxy/gl.h>

#include <algorithm>

namespace cagewrap::app {

Result<std::unique_ptr<OffscreenSurface>> OffscreenSurface::create(int width, int height, int samples) {
  if (width <= 0 || height <= 0)
    return make_error(ErrorCode::kInvalidArgument, "the offscreen frame needs a size above 0 (got " +
                                                       std::to_string(width) + " x " + std::to_string(height) + ")");
  auto gl = render::HeadlessGl::create();
  if (!gl) return gl.error();
  std::unique_ptr<OffscreenSurface> s(new OffscreenSurface());
  s->gl_ = std::move(*gl);
  s->width_ = width;
  s->height_ = height;
  samples = render::editor_samples(samples, s->gl_->software());
  GLint max_samples = 0;
  glGetIntegerv(GL_MAX_SAMPLES, &max_samples);
  samples = std::min(samples, static_cast<int>(max_samples));
  GLuint rb[3];
  glGenRenderbuffers(3, rb);
  s->color_ = rb[0];
  s->depth_ = rb[1];
  s->resolved_color_ = rb[2];
  glBindRenderbuffer(GL_RENDERBUFFER, s->color_);
  glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_RGBA8, width, height);
  glBindRenderbuffer(GL_RENDERBUFFER, s->depth_);
  glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_DEPTH24_STENCIL8, width, height);
  glBindRenderbuffer(GL_RENDERBUFFER, s->resolved_color_);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
  glBindRenderbuffer(GL_RENDERBUFFER, 0);
  GLuint fbo[2];
  glGenFramebuffers(2, fbo);
  s->draw_fbo_ = fbo[0];
  s->resolve_fbo_ = fbo[1];
  glBindFramebuffer(GL_FRAMEBUFFER, s->resolve_fbo_);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, s->resolved_color_);
  const GLenum resolve_status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  glBindFramebuffer(GL_FRAMEBUFFER, s->draw_fbo_);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, s->color_);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, s->depth_);
  const GLenum draw_status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  if (resolve_status != GL_FRAMEBUFFER_COMPLETE || draw_status != GL_FRAMEBUFFER_COMPLETE)
    return make_error(ErrorCode::kUnsupportedFormat,
                      "the offscreen " + std::to_string(width) + " x " + std::to_string(height) + " framebuffer with " +
                          std::to_string(samples) + " samples is incomplete on " + s->description());
  return s;
}

OffscreenSurface::~OffscreenSurface() {
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  const GLuint fbo[2] = {draw_fbo_, resolve_fbo_};
  glDeleteFramebuffers(2, fbo);
  const GLuint rb[3] = {color_, depth_, resolved_color_};
  glDeleteRenderbuffers(3, rb);
}

void OffscreenSurface::begin_frame() const { glBindFramebuffer(GL_FRAMEBUFFER, draw_fbo_); }

void OffscreenSurface::resolve() const {
  glBindFramebuffer(GL_READ_FRAMEBUFFER, draw_fbo_);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, resolve_fbo_);
  glBlitFramebuffer(0, 0, width_, height_, 0, 0, width_, height_, GL_COLOR_BUFFER_BIT, GL_NEAREST);
}

void OffscreenSurface::end_frame() const {
  resolve();
  glFinish();
  begin_frame();
}

void OffscreenSurface::bind_for_reading() const {
  resolve();
  glBindFramebuffer(GL_READ_FRAMEBUFFER, resolve_fbo_);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
}

}  // namespace cagewrap::app

#endif  // CAGEWRAP_GUI
