// GPU copies of core data. Each owns its vertex array and buffers; `upload_*` replaces contents.
#pragma once

#include <epoxy/gl.h>

#include <span>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "core/mesh.h"

namespace cagewrap::render {

// Triangles with per-vertex position, normal and optional colour (attribute 2).
class TriangleBuffer {
 public:
  TriangleBuffer();
  ~TriangleBuffer();
  TriangleBuffer(const TriangleBuffer&) = delete;
  TriangleBuffer& operator=(const TriangleBuffer&) = delete;
  void upload_indices(std::span<const Tri> triangles);
  void upload_positions(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals);
  void upload_colors(std::span<const glm::vec4> colors);  // empty: use the uniform colour
  bool has_colors() const { return has_colors_; }
  void draw() const;

 private:
  GLuint vao_ = 0, positions_ = 0, normals_ = 0, colors_ = 0, indices_ = 0;
  GLsizei index_count_ = 0;
  bool has_colors_ = false;
};

// Coloured lines (pairs of vertices) or points.
class LineBuffer {
 public:
  LineBuffer();
  ~LineBuffer();
  LineBuffer(const LineBuffer&) = delete;
  LineBuffer& operator=(const LineBuffer&) = delete;
  void upload(std::span<const glm::vec3> positions, std::span<const glm::vec4> colors);
  void draw(GLenum mode) const;
  size_t size() const { return static_cast<size_t>(count_); }

 private:
  GLuint vao_ = 0, positions_ = 0, colors_ = 0;
  GLsizei count_ = 0;
};

}  // namespace cagewrap::render
