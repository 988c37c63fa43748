// A linked GLSL program from the shaders embedded at build time (shaders/*.glsl -> the binary).
#pragma once

#include <epoxy/gl.h>

#include <initializer_list>
#include <string>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace cagewrap::render {

// The text of an embedded shader file ("mesh.vert"), or empty.
std::string_view embedded_shader(std::string_view name);

class GlProgram {
 public:
  GlProgram() = default;
  GlProgram(const GlProgram&) = delete;
  GlProgram& operator=(const GlProgram&) = delete;
  ~GlProgram();
  // Compiles and links; on failure returns false and fills `log`.
  bool build(std::string_view vertex_name, std::string_view fragment_name, std::string& log);
  // A compute program (GL 4.3) from one embedded shader; `defines` ("KERNEL_FACES") are added as
  // #define lines after its #version line, so one file can hold several kernels.
  bool build_compute(std::string_view compute_name, std::initializer_list<std::string_view> defines, std::string& log);
  GLuint id() const { return id_; }
  void use() const { glUseProgram(id_); }
  void set(const char* name, const glm::mat4& m) const;
  void set(const char* name, const glm::vec4& v) const;
  void set(const char* name, float v) const;
  void set(const char* name, int v) const;
  void set(const char* name, unsigned v) const;
  void set(const char* name, const glm::vec3& v) const;

 private:
  GLuint id_ = 0;
};

}  // namespace cagewrap::render
