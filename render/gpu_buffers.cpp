#include "render/gpu_buffers.h"

#include "core/base/check.h"

namespace cagewrap::render {

namespace {
void attribute(GLuint buffer, GLuint index, GLint components) {
  glBindBuffer(GL_ARRAY_BUFFER, buffer);
  glEnableVertexAttribArray(index);
  glVertexAttribPointer(index, components, GL_FLOAT, GL_FALSE, 0, nullptr);
}
template <class T>
void fill(GLuint buffer, std::span<const T> data) {
  glBindBuffer(GL_ARRAY_BUFFER, buffer);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(data.size_bytes()), data.data(), GL_DYNAMIC_DRAW);
}
}  // namespace

TriangleBuffer::TriangleBuffer() {
  glGenVertexArrays(1, &vao_);
  GLuint b[4];
  glGenBuffers(4, b);
  positions_ = b[0], normals_ = b[1], colors_ = b[2], indices_ = b[3];
  glBindVertexArray(vao_);
  attribute(positions_, 0, 3);
  attribute(normals_, 1, 3);
  glBindBuffer(GL_ARRAY_BUFFER, colors_);
  glVertexAttribPointer(2, 4, GL_FLOAT, GL_FALSE, 0, nullptr);
  glBindVertexArray(0);
}

TriangleBuffer::~TriangleBuffer() {
  GLuint b[4] = {positions_, normals_, colors_, indices_};
  glDeleteBuffers(4, b);
  glDeleteVertexArrays(1, &vao_);
}

void TriangleBuffer::upload_indices(std::span<const Tri> triangles) {
  glBindVertexArray(vao_);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, indices_);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(triangles.size_bytes()), triangles.data(),
               GL_STATIC_DRAW);
  glBindVertexArray(0);
  index_count_ = static_cast<GLsizei>(triangles.size() * 3);
}

void TriangleBuffer::upload_positions(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals) {
  fill(positions_, positions);
  fill(normals_, normals);
  vertex_count_ = positions.size();
}

void TriangleBuffer::allocate_vertices(size_t n) {
  if (n == vertex_count_) return;
  const auto bytes = static_cast<GLsizeiptr>(n * sizeof(glm::vec3));
  for (GLuint b : {positions_, normals_}) {
    glBindBuffer(GL_ARRAY_BUFFER, b);
    glBufferData(GL_ARRAY_BUFFER, bytes, nullptr, GL_DYNAMIC_COPY);
  }
  vertex_count_ = n;
}

namespace {
void read_back(GLuint buffer, size_t count, std::span<glm::vec3> out) {
  CAGEWRAP_CHECK(out.size() == count, "read back as many vertices as the buffer holds");
  glBindBuffer(GL_ARRAY_BUFFER, buffer);
  glGetBufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(out.size_bytes()), out.data());
}
}  // namespace

void TriangleBuffer::read_positions(std::span<glm::vec3> out) const { read_back(positions_, vertex_count_, out); }
void TriangleBuffer::read_normals(std::span<glm::vec3> out) const { read_back(normals_, vertex_count_, out); }

void TriangleBuffer::upload_colors(std::span<const glm::vec4> colors) {
  has_colors_ = !colors.empty();
  if (has_colors_) fill(colors_, colors);
  glBindVertexArray(vao_);
  if (has_colors_) glEnableVertexAttribArray(2);
  else glDisableVertexAttribArray(2);
  glBindVertexArray(0);
}

void TriangleBuffer::draw() const {
  if (!index_count_) return;
  glBindVertexArray(vao_);
  glDrawElements(GL_TRIANGLES, index_count_, GL_UNSIGNED_INT, nullptr);
  glBindVertexArray(0);
}

LineBuffer::LineBuffer() {
  glGenVertexArrays(1, &vao_);
  GLuint b[2];
  glGenBuffers(2, b);
  positions_ = b[0], colors_ = b[1];
  glBindVertexArray(vao_);
  attribute(positions_, 0, 3);
  attribute(colors_, 1, 4);
  glBindVertexArray(0);
}

LineBuffer::~LineBuffer() {
  GLuint b[2] = {positions_, colors_};
  glDeleteBuffers(2, b);
  glDeleteVertexArrays(1, &vao_);
}

void LineBuffer::upload(std::span<const glm::vec3> positions, std::span<const glm::vec4> colors) {
  fill(positions_, positions);
  fill(colors_, colors);
  count_ = static_cast<GLsizei>(positions.size());
}

void LineBuffer::draw(GLenum mode) const {
  if (!count_) return;
  glBindVertexArray(vao_);
  glDrawArrays(mode, 0, count_);
  glBindVertexArray(0);
}

}  // namespace cagewrap::render
