#include "render/gpu_deformer.h"

#include <algorithm>
#include <bit>
#include <cstdio>
#include <vector>

#include <glm/vec4.hpp>

#include "core/base/check.h"
#include "core/geometry/mesh_normals.h"

namespace cagewrap::render {

namespace {

constexpr size_t kGroupSize = 256;  // local_size_x of both compute shaders

std::string megabytes(size_t bytes) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f MB", bytes / 1e6);
  return buf;
}

size_t storage_limit() {
  GLint64 v = 0;
  glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &v);
  return v > 0 ? static_cast<size_t>(v) : 0;
}

// Refuses a buffer the kernels could not address whole (GL_MAX_SHADER_STORAGE_BLOCK_SIZE).
Status check_storage(size_t bytes, const std::string& what) {
  const size_t limit = storage_limit();
  if (limit && bytes > limit)
    return make_error(ErrorCode::kInvalidArgument, what + " needs " + megabytes(bytes) +
                                                       " in one shader-storage buffer but this OpenGL allows " +
                                                       megabytes(limit) + " (GL_MAX_SHADER_STORAGE_BLOCK_SIZE)");
  return Ok{};
}

// (Re)fills a shader-storage buffer (at least 16 bytes, so an empty table still binds); adds its
// size to `total`. Fails beyond the GL's limit or when the GL runs out of memory, naming `what`.
Status fill_storage(GLuint& buffer, const void* data, size_t bytes, const std::string& what, size_t& total,
                    GLenum usage = GL_STATIC_DRAW) {
  if (auto s = check_storage(bytes, what); !s) return s;
  if (!buffer) glGenBuffers(1, &buffer);
  while (glGetError() != GL_NO_ERROR) {
  }
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, buffer);
  glBufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(std::max<size_t>(bytes, 16)), bytes ? data : nullptr,
               usage);
  if (glGetError() == GL_OUT_OF_MEMORY)
    return make_error(ErrorCode::kInvalidArgument, "the GPU has no room for " + what + " (" + megabytes(bytes) + ")");
  total += bytes;
  return Ok{};
}

template <class T>
Status fill_storage(GLuint& buffer, std::span<const T> data, const std::string& what, size_t& total) {
  return fill_storage(buffer, data.data(), data.size_bytes(), what, total);
}

void bind(GLuint index, GLuint buffer) { glBindBufferBase(GL_SHADER_STORAGE_BUFFER, index, buffer); }

// Runs `count` invocations of the program in use, on a 2-D grid of groups when one row would exceed
// the GL's group-count limit (u_row tells the kernel the row length).
void dispatch(const GlProgram& program, size_t count, size_t max_groups_x) {
  if (!count) return;
  const size_t groups = (count + kGroupSize - 1) / kGroupSize;
  const size_t gx = std::min(groups, max_groups_x);
  const size_t gy = (groups + gx - 1) / gx;
  program.set("u_count", static_cast<unsigned>(count));
  program.set("u_row", static_cast<unsigned>(gx * kGroupSize));
  glDispatchCompute(static_cast<GLuint>(gx), static_cast<GLuint>(gy), 1);
}

// What a later pass, the draw and a read-back need to see of a kernel's writes.
void barrier() {
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
}

// Uploads the per-change maps into `buffer`, growing it when the deformer's maps grew.
template <class T>
void upload_maps(GLuint& buffer, size_t& allocated, std::span<const T> maps, size_t& total) {
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, buffer);
  if (maps.size_bytes() != allocated) {
    glBufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(std::max<size_t>(maps.size_bytes(), 16)), nullptr,
                 GL_STREAM_DRAW);
    total = total - allocated + maps.size_bytes();
    allocated = maps.size_bytes();
  }
  if (!maps.empty())
    glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, static_cast<GLsizeiptr>(maps.size_bytes()), maps.data());
}

}  // namespace

std::string GpuDeformer::unsupported_reason() {
  const int version = epoxy_gl_version();
  if (version >= 43) return {};
  const char* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  char buf[256];
  std::snprintf(buf, sizeof buf, "OpenGL %d.%d (%s) has no compute shaders; the GPU deformer needs 4.3", version / 10,
                version % 10, renderer ? renderer : "unknown renderer");
  return buf;
}

Result<std::unique_ptr<GpuDeformer>> GpuDeformer::create(const Deformer& deformer, std::span<const Tri> triangles) {
  if (auto why = unsupported_reason(); !why.empty()) return make_error(ErrorCode::kUnsupportedFormat, why);
  std::unique_ptr<GpuDeformer> g(new GpuDeformer());
  g->deformer_ = &deformer;
  GLint max_x = 0;
  glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, &max_x);
  g->max_groups_x_ = static_cast<size_t>(std::max(max_x, 65535));  // GL 4.3 guarantees at least 65535
  std::string log;
  if (!g->affine_.build_compute("deform.comp.glsl", {"KERNEL_AFFINE"}, log) ||
      !g->rigid_.build_compute("deform.comp.glsl", {"KERNEL_RIGID"}, log) ||
      !g->fallback_.build_compute("deform.comp.glsl", {"KERNEL_FALLBACK"}, log) ||
      !g->faces_.build_compute("normals.comp.glsl", {"KERNEL_FACES"}, log) ||
      !g->vertices_.build_compute("normals.comp.glsl", {"KERNEL_VERTICES"}, log))
    return make_error(ErrorCode::kParse, "a GPU deformer kernel does not compile: " + log);
  if (auto s = g->upload_table(); !s) return s.error();
  if (auto s = g->upload_topology(triangles); !s) return s.error();
  return g;
}

GpuDeformer::~GpuDeformer() {
  GLuint buffers[] = {rest_,      offsets_, ids_, weights_, bary_, fallback_list_, affine_maps_, rigid_maps_, starts_,
                      incident_, face_normals_};
  glDeleteBuffers(static_cast<GLsizei>(std::size(buffers)), buffers);
}

size_t GpuDeformer::num_points() const { return deformer_->binding().num_points; }

size_t GpuDeformer::bytes_uploaded_per_change() const {
  return deformer_->affine_maps().size_bytes() + deformer_->rigid_maps().size_bytes();
}

Status GpuDeformer::upload_table() {
  const Binding& b = deformer_->binding();
  const std::span<const glm::vec3> rest = deformer_->skin_rest();
  size_t bytes = 0;
  // the kernels write positions and read them as shader storage too
  if (auto s = check_storage(rest.size_bytes(), "the deformed skin (" + std::to_string(b.num_points) + " points)"); !s)
    return s;
  if (auto s = fill_storage(rest_, rest, "the rest skin", bytes); !s) return s;
  if (auto s = fill_storage(offsets_, std::span<const uint32_t>(b.offsets), "the binding's offset table", bytes); !s) return s;
  if (auto s = fill_storage(ids_, std::span<const uint32_t>(b.ids), "the binding's id table", bytes); !s) return s;
  if (auto s = fill_storage(weights_, std::span<const float>(b.weights), "the binding's weight table", bytes); !s) return s;
  if (auto s = fill_storage(bary_, std::span<const float>(b.bary), "the binding's anchor table", bytes); !s) return s;
  std::vector<glm::uvec4> fallback(b.rigid_points.size());
  for (size_t k = 0; k < fallback.size(); ++k)
    fallback[k] = glm::uvec4(b.rigid_points[k], b.rigid_element[k], std::bit_cast<uint32_t>(b.rigid_bary[2 * k]),
                             std::bit_cast<uint32_t>(b.rigid_bary[2 * k + 1]));
  if (auto s = fill_storage(fallback_list_, std::span<const glm::uvec4>(fallback), "the fallback point table", bytes); !s)
    return s;
  num_fallback_ = fallback.size();
  table_bytes_ = bytes;
  if (!affine_maps_) glGenBuffers(1, &affine_maps_);
  if (!rigid_maps_) glGenBuffers(1, &rigid_maps_);
  return Ok{};
}

Status GpuDeformer::upload_topology(std::span<const Tri> triangles) {
  const size_t nv = deformer_->binding().num_points;
  if (auto s = check_storage(triangles.size_bytes(), "the skin's triangles (" + std::to_string(triangles.size()) + ")");
      !s)
    return s;
  NormalComputer adjacency(nv, triangles);  // the CPU path's own vertex -> triangles table
  size_t bytes = 0;
  if (auto s = fill_storage(starts_, adjacency.starts(), "the skin's vertex -> triangle starts", bytes); !s) return s;
  if (auto s = fill_storage(incident_, adjacency.incident(), "the skin's vertex -> triangle table", bytes); !s)
    return s;
  if (auto s = fill_storage(face_normals_, nullptr, triangles.size_bytes(), "the skin's triangle normals", bytes,
                            GL_DYNAMIC_COPY);
      !s)
    return s;
  num_triangles_ = triangles.size();
  num_vertices_ = nv;
  topology_bytes_ = bytes;
  return Ok{};
}

Status GpuDeformer::table_changed() { return upload_table(); }

void GpuDeformer::deform(TriangleBuffer& target) {
  const Binding& b = deformer_->binding();
  target.allocate_vertices(b.num_points);
  const bool clamped = b.params.variant == Variant::kClamped;
  static_assert(sizeof(Affine) == 16 * sizeof(float) && sizeof(RigidMap) == 20 * sizeof(float),
                "the kernels read these layouts");
  if (!clamped) upload_maps(affine_maps_, affine_allocated_, deformer_->affine_maps(), maps_bytes_);
  if (clamped || num_fallback_) upload_maps(rigid_maps_, rigid_allocated_, deformer_->rigid_maps(), maps_bytes_);

  bind(0, rest_);
  bind(7, target.position_buffer());
  const glm::vec3 origin(b.origin);
  const GlProgram& main = clamped ? rigid_ : affine_;
  main.use();
  main.set("u_origin", origin);
  bind(1, offsets_);
  bind(2, ids_);
  bind(3, weights_);
  if (clamped) {
    bind(4, bary_);
    bind(5, rigid_maps_);
  } else {
    bind(4, affine_maps_);
  }
  dispatch(main, b.num_points, max_groups_x_);
  if (num_fallback_) {
    barrier();  // the fallback points overwrite what the main pass wrote for them
    fallback_.use();
    fallback_.set("u_origin", origin);
    bind(1, fallback_list_);
    bind(5, rigid_maps_);
    dispatch(fallback_, num_fallback_, max_groups_x_);
  }
  barrier();
}

void GpuDeformer::normals(TriangleBuffer& target) {
  CAGEWRAP_CHECK(target.num_triangles() == num_triangles_ && target.num_vertices() == num_vertices_,
                 "the target holds the skin the GPU deformer was made for");
  faces_.use();
  faces_.set("u_vertices", static_cast<unsigned>(num_vertices_));
  bind(0, target.position_buffer());
  bind(1, target.index_buffer());
  bind(2, face_normals_);
  dispatch(faces_, num_triangles_, max_groups_x_);
  barrier();
  vertices_.use();
  bind(0, target.normal_buffer());
  bind(1, starts_);
  bind(2, face_normals_);
  bind(3, incident_);
  dispatch(vertices_, num_vertices_, max_groups_x_);
  barrier();
}

}  // namespace cagewrap::render
