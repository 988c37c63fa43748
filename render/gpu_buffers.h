// GPU copies of core data. Each owns its vertex array and buffers; `upload_*` replaces contents.
#pragma once

#include <epoxy/gl.h>

#include <span>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "core/geometry/mesh.h"

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

  // For a kernel that writes the vertices on the GPU (render/gpu_deformer.h): sizes the position and
  // normal buffers for n vertices (contents undefined) and names the buffers, which it binds as
  // shader storage (float x 3 per vertex, tightly packed; indices uint x 3 per triangle).
  void allocate_vertices(size_t n);
  size_t num_vertices() const { return vertex_count_; }
  size_t num_triangles() const { return static_cast<size_t>(index_count_) / 3; }
  GLuint position_buffer() const { return positions_; }
  GLuint normal_buffer() const { return normals_; }
  GLuint index_buffer() const { return indices_; }
  // Reads the buffers back (tests, and the editor's CPU copy when it needs one): sizes must match.
  void read_positions(std::span<glm::vec3> out) const;
  void read_normals(std::span<glm::vec3> out) const;

 private:
  GLuint vao_ = 0, positions_ = 0, normals_ = 0, colors_ = 0, indices_ = 0;
  GLsizei index_count_ = 0;
  size_t vertex_count_ = 0;
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
