#include "render/headless_gl.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <vector>

namespace cagewrap::render {

namespace {

bool has_word(const char* list, const char* word) {
  if (!list) return false;
  const size_t n = std::strlen(word);
  for (const char* p = list; (p = std::strstr(p, word)); p += n)
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == 0)) return true;
  return false;
}

// A display to try and how it was found.
struct Candidate {
  EGLDisplay display;
  std::string how;
};

void add_surfaceless(const char* client_extensions, std::vector<Candidate>& out) {
  if (!has_word(client_extensions, "EGL_MESA_platform_surfaceless")) return;
  EGLDisplay d = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  if (d != EGL_NO_DISPLAY) out.push_back({d, "EGL surfaceless platform"});
}

std::vector<Candidate> candidate_displays(std::string& notes) {
  std::vector<Candidate> out;
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);  // client extensions
  if (has_word(client, "EGL_EXT_device_enumeration") && has_word(client, "EGL_EXT_platform_device")) {
    EGLint n = 0;
    eglQueryDevicesEXT(0, nullptr, &n);
    std::vector<EGLDeviceEXT> devices(static_cast<size_t>(std::max(n, 0)));
    if (n > 0) eglQueryDevicesEXT(n, devices.data(), &n);
    std::vector<Candidate> hardware, software;
    for (EGLint i = 0; i < n; ++i) {
      const char* ext = eglQueryDeviceStringEXT(devices[i], EGL_EXTENSIONS);
      const bool soft = has_word(ext, "EGL_MESA_device_software");
      EGLDisplay d = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
      if (d == EGL_NO_DISPLAY) continue;
      Candidate c{d, "EGL device " + std::to_string(i) + (soft ? " (software)" : "")};
      if (const char* pick = std::getenv("CAGEWRAP_EGL_DEVICE"); pick && std::atoi(pick) == i) {
        out.push_back(c);
        return out;
      }
      (soft ? software : hardware).push_back(c);
    }
    out.insert(out.end(), hardware.begin(), hardware.end());
    // the surfaceless platform before Mesa's software device: where a GPU driver's device display
    // cannot give a context, its surfaceless platform may (NVIDIA's does), and software comes last
    add_surfaceless(client, out);
    out.insert(out.end(), software.begin(), software.end());
  } else {
    notes += "no EGL device enumeration; ";
    add_surfaceless(client, out);
  }
  EGLDisplay d = eglGetDisplay(EGL_DEFAULT_DISPLAY);
  if (d != EGL_NO_DISPLAY) out.push_back({d, "default EGL display"});
  return out;
}

// A 4.3 core context on `display`, current with no surface; EGL_NO_CONTEXT on failure (`why` says).
EGLContext make_context(EGLDisplay display, std::string& why) {
  EGLint major = 0, minor = 0;
  if (!eglInitialize(display, &major, &minor)) {
    why = "eglInitialize failed";
    return EGL_NO_CONTEXT;
  }
  if (!eglBindAPI(EGL_OPENGL_API)) {
    why = "no desktop OpenGL";
    return EGL_NO_CONTEXT;
  }
  const char* ext = eglQueryString(display, EGL_EXTENSIONS);
  if (!has_word(ext, "EGL_KHR_surfaceless_context")) {
    why = "no surfaceless contexts";
    return EGL_NO_CONTEXT;
  }
  EGLConfig config = nullptr;
  if (!has_word(ext, "EGL_KHR_no_config_context") && !has_word(ext, "EGL_MESA_configless_context")) {
    const EGLint want[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLint n = 0;
    if (!eglChooseConfig(display, want, &config, 1, &n) || n < 1) {
      why = "no OpenGL config";
      return EGL_NO_CONTEXT;
    }
  }
  const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 3,
                               EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, attributes);
  if (context == EGL_NO_CONTEXT) {
    why = "no OpenGL 4.3 core context";
    return EGL_NO_CONTEXT;
  }
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
    eglDestroyContext(display, context);
    why = "cannot make the context current";
    return EGL_NO_CONTEXT;
  }
  return context;
}

}  // namespace

Result<std::unique_ptr<HeadlessGl>> HeadlessGl::create() {
  if (!epoxy_has_egl())
    return make_error(ErrorCode::kFileNotFound, "no EGL library (libEGL.so.1): cannot open a headless OpenGL context");
  std::string tried;
  for (const Candidate& c : candidate_displays(tried)) {
    std::string why;
    EGLContext context = make_context(c.display, why);
    if (context == EGL_NO_CONTEXT) {
      tried += c.how + ": " + why + "; ";
      continue;
    }
    std::unique_ptr<HeadlessGl> gl(new HeadlessGl());
    gl->display_ = c.display;
    gl->context_ = context;
    const char* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    const char* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    gl->description_ = std::string(renderer ? renderer : "?") + ", OpenGL " + (version ? version : "?") + " (" + c.how +
                       (tried.empty() ? std::string() : "; before it: " + tried.substr(0, tried.size() - 2)) + ")";
    gl->software_ = current_context_is_software();
    return gl;
  }
  return make_error(ErrorCode::kUnsupportedFormat,
                    "no headless OpenGL 4.3 context: " + (tried.empty() ? std::string("no EGL display") : tried));
}

HeadlessGl::~HeadlessGl() {
  eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(display_, context_);
  // no eglTerminate: other contexts of this process may share the display (EGL displays are per process)
}

bool current_context_is_software() {
  const char* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  return renderer && (std::strstr(renderer, "llvmpipe") || std::strstr(renderer, "softpipe") || std::strstr(renderer, "swrast"));
}

int editor_samples(int requested, bool software) { return requested >= 0 ? requested : software ? 0 : 4; }

}  // namespace cagewrap::render
