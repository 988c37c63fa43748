#include "render/gl_program.h"

#include <utility>
#include <vector>

#include <glm/gtc/type_ptr.hpp>

namespace cagewrap::shaders {
extern const std::pair<std::string_view, std::string_view> kEmbedded[];
extern const int kEmbeddedCount;
}  // namespace cagewrap::shaders

namespace cagewrap::render {

std::string_view embedded_shader(std::string_view name) {
  for (int i = 0; i < shaders::kEmbeddedCount; ++i)
    if (shaders::kEmbedded[i].first == name) return shaders::kEmbedded[i].second;
  return {};
}

namespace {
// `defines` go after the #version line (which must come first in GLSL).
GLuint compile(GLenum type, std::string_view name, std::string& log,
               std::initializer_list<std::string_view> defines = {}) {
  std::string_view text = embedded_shader(name);
  if (text.empty()) {
    log = "shader " + std::string(name) + " is not embedded";
    return 0;
  }
  std::string source(text);
  if (defines.size()) {
    size_t at = source.rfind("#version", 0) == 0 ? source.find('\n') + 1 : 0;
    std::string lines;
    for (auto d : defines) lines += "#define " + std::string(d) + "\n";
    source.insert(at, lines);
  }
  GLuint s = glCreateShader(type);
  const char* src = source.data();
  GLint len = static_cast<GLint>(source.size());
  glShaderSource(s, 1, &src, &len);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char buf[2048];
    glGetShaderInfoLog(s, sizeof buf, nullptr, buf);
    log = std::string(name) + ": " + buf;
    glDeleteShader(s);
    return 0;
  }
  return s;
}
// Links `id` (its shaders attached); on failure fills `log`, naming `what`.
bool link(GLuint id, const std::string& what, std::string& log) {
  glLinkProgram(id);
  GLint ok = 0;
  glGetProgramiv(id, GL_LINK_STATUS, &ok);
  if (ok) return true;
  char buf[2048];
  glGetProgramInfoLog(id, sizeof buf, nullptr, buf);
  log = what + ": " + buf;
  return false;
}
}  // namespace

GlProgram::~GlProgram() {
  if (id_) glDeleteProgram(id_);
}

bool GlProgram::build(std::string_view vs_name, std::string_view fs_name, std::string& log) {
  GLuint vs = compile(GL_VERTEX_SHADER, vs_name, log);
  if (!vs) return false;
  GLuint fs = compile(GL_FRAGMENT_SHADER, fs_name, log);
  if (!fs) {
    glDeleteShader(vs);
    return false;
  }
  id_ = glCreateProgram();
  glAttachShader(id_, vs);
  glAttachShader(id_, fs);
  const bool ok = link(id_, std::string(vs_name) + " + " + std::string(fs_name), log);
  glDeleteShader(vs);
  glDeleteShader(fs);
  return ok;
}

bool GlProgram::build_compute(std::string_view name, std::initializer_list<std::string_view> defines, std::string& log) {
  GLuint cs = compile(GL_COMPUTE_SHADER, name, log, defines);
  if (!cs) return false;
  if (id_) glDeleteProgram(id_);
  id_ = glCreateProgram();
  glAttachShader(id_, cs);
  const bool ok = link(id_, std::string(name), log);
  glDeleteShader(cs);
  return ok;
}

void GlProgram::set(const char* name, const glm::mat4& m) const {
  glUniformMatrix4fv(glGetUniformLocation(id_, name), 1, GL_FALSE, glm::value_ptr(m));
}
void GlProgram::set(const char* name, const glm::vec4& v) const {
  glUniform4fv(glGetUniformLocation(id_, name), 1, glm::value_ptr(v));
}
void GlProgram::set(const char* name, float v) const { glUniform1f(glGetUniformLocation(id_, name), v); }
void GlProgram::set(const char* name, int v) const { glUniform1i(glGetUniformLocation(id_, name), v); }
void GlProgram::set(const char* name, unsigned v) const { glUniform1ui(glGetUniformLocation(id_, name), v); }
void GlProgram::set(const char* name, const glm::vec3& v) const {
  glUniform3fv(glGetUniformLocation(id_, name), 1, glm::value_ptr(v));
}

}  // namespace cagewrap::render
