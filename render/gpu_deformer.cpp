#include "render/gpu_deformer.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <vector>

#include <glm/vec4.hpp>

#include "core/base/check.h"
#include "core/geometry/mesh_normals.h"

namespace cagewrap::render {

namespace {

constexpr size_t kGroupSize = 256;  // local_size_x of every compute shader
constexpr uint32_t kNoMask = 0xffffffffu;  // shaders/combine_stack.comp.glsl: a layer without a mask

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
  // a table under 16 bytes goes into a 16-byte buffer: the GL reads only `bytes` from `data`
  const bool padded = bytes < 16;
  glBufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(std::max<size_t>(bytes, 16)), padded ? nullptr : data, usage);
  if (padded && bytes) glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, static_cast<GLsizeiptr>(bytes), data);
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

// GL_MAX_COMPUTE_WORK_GROUP_COUNT[0]: GL 4.3 guarantees at least 65535.
size_t max_groups_per_row() {
  GLint max_x = 0;
  glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, &max_x);
  return static_cast<size_t>(std::max(max_x, 65535));
}

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

Result<std::unique_ptr<GpuNormals>> GpuNormals::create(size_t num_vertices, std::span<const Tri> triangles) {
  if (auto why = GpuDeformer::unsupported_reason(); !why.empty()) return make_error(ErrorCode::kUnsupportedFormat, why);
  std::unique_ptr<GpuNormals> g(new GpuNormals());
  g->max_groups_x_ = max_groups_per_row();
  std::string log;
  if (!g->faces_.build_compute("normals.comp.glsl", {"KERNEL_FACES"}, log) ||
      !g->vertices_.build_compute("normals.comp.glsl", {"KERNEL_VERTICES"}, log))
    return make_error(ErrorCode::kParse, "a GPU normals kernel does not compile: " + log);
  if (auto s = check_storage(triangles.size_bytes(), "the skin's triangles (" + std::to_string(triangles.size()) + ")");
      !s)
    return s.error();
  NormalComputer adjacency(num_vertices, triangles);  // the CPU path's own vertex -> triangles table
  size_t bytes = 0;
  if (auto s = fill_storage(g->starts_, adjacency.starts(), "the skin's vertex -> triangle starts", bytes); !s)
    return s.error();
  if (auto s = fill_storage(g->incident_, adjacency.incident(), "the skin's vertex -> triangle table", bytes); !s)
    return s.error();
  if (auto s = fill_storage(g->face_normals_, nullptr, triangles.size_bytes(), "the skin's triangle normals", bytes,
                            GL_DYNAMIC_COPY);
      !s)
    return s.error();
  g->num_triangles_ = triangles.size();
  g->num_vertices_ = num_vertices;
  g->bytes_ = bytes;
  return g;
}

GpuNormals::~GpuNormals() {
  GLuint buffers[] = {starts_, incident_, face_normals_};
  glDeleteBuffers(static_cast<GLsizei>(std::size(buffers)), buffers);
}

void GpuNormals::compute(TriangleBuffer& target) {
  CAGEWRAP_CHECK(target.num_triangles() == num_triangles_ && target.num_vertices() == num_vertices_,
                 "the target holds the skin the GPU normals were made for");
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

Result<std::unique_ptr<GpuDeformer>> GpuDeformer::make(const Deformer& deformer) {
  if (auto why = unsupported_reason(); !why.empty()) return make_error(ErrorCode::kUnsupportedFormat, why);
  std::unique_ptr<GpuDeformer> g(new GpuDeformer());
  g->deformer_ = &deformer;
  g->max_groups_x_ = max_groups_per_row();
  std::string log;
  if (!g->affine_.build_compute("deform.comp.glsl", {"KERNEL_AFFINE"}, log) ||
      !g->rigid_.build_compute("deform.comp.glsl", {"KERNEL_RIGID"}, log) ||
      !g->dense_affine_.build_compute("deform.comp.glsl", {"KERNEL_DENSE_AFFINE"}, log) ||
      !g->dense_rigid_.build_compute("deform.comp.glsl", {"KERNEL_DENSE_RIGID"}, log) ||
      !g->fallback_.build_compute("deform.comp.glsl", {"KERNEL_FALLBACK"}, log))
    return make_error(ErrorCode::kParse, "a GPU deformer kernel does not compile: " + log);
  if (auto s = g->upload_table(); !s) return s.error();
  return g;
}

Result<std::unique_ptr<GpuDeformer>> GpuDeformer::create(const Deformer& deformer) { return make(deformer); }

Result<std::unique_ptr<GpuDeformer>> GpuDeformer::create(const Deformer& deformer, std::span<const Tri> triangles) {
  auto g = make(deformer);
  if (!g) return g;
  auto n = GpuNormals::create(deformer.binding().num_points, triangles);
  if (!n) return n.error();
  (*g)->normals_ = std::move(n).value();
  return g;
}

GpuDeformer::~GpuDeformer() {
  GLuint buffers[] = {rest_, offsets_, ids_, weights_, bary_, fallback_list_, affine_maps_, rigid_maps_};
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
  // the table the CPU kernel reads: the compact one (core/deform/kernel_table.h) where the deformer has
  // it, else the binding's float table
  dense_ = deformer_->kernel_table() != nullptr;
  if (dense_) {
    const KernelTable& t = *deformer_->kernel_table();
    if (auto s = fill_storage(offsets_, std::span<const uint32_t>(t.group_start), "the compact table's groups", bytes); !s)
      return s;
    if (auto s = fill_storage(ids_, std::span<const uint16_t>(t.member_id), "the compact table's ids", bytes); !s) return s;
    if (auto s = fill_storage(weights_, std::span<const uint16_t>(t.weights), "the compact table's weights", bytes); !s)
      return s;
    if (auto s = fill_storage(bary_, std::span<const uint8_t>(t.weights_lo), "the compact table's low weight bits", bytes); !s)
      return s;
  } else {
    if (auto s = fill_storage(offsets_, std::span<const uint32_t>(b.offsets), "the binding's offset table", bytes); !s) return s;
    if (auto s = fill_storage(ids_, std::span<const uint32_t>(b.ids), "the binding's id table", bytes); !s) return s;
    if (auto s = fill_storage(weights_, std::span<const float>(b.weights), "the binding's weight table", bytes); !s) return s;
    if (auto s = fill_storage(bary_, std::span<const float>(b.bary), "the binding's anchor table", bytes); !s) return s;
  }
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

Status GpuDeformer::table_changed() { return upload_table(); }

void GpuDeformer::deform(TriangleBuffer& target) {
  target.allocate_vertices(deformer_->binding().num_points);
  deform_into(target.position_buffer(), 0);
}

void GpuDeformer::deform_into(GLuint buffer, size_t offset) {
  const Binding& b = deformer_->binding();
  const bool clamped = b.params.variant == Variant::kClamped;
  static_assert(sizeof(Affine) == 16 * sizeof(float) && sizeof(RigidMap) == 20 * sizeof(float),
                "the kernels read these layouts");
  if (!clamped) upload_maps(affine_maps_, affine_allocated_, deformer_->affine_maps(), maps_bytes_);
  if (clamped || num_fallback_) upload_maps(rigid_maps_, rigid_allocated_, deformer_->rigid_maps(), maps_bytes_);

  bind(0, rest_);
  glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 7, buffer, static_cast<GLintptr>(offset),
                    static_cast<GLsizeiptr>(std::max<size_t>(size_t{b.num_points} * sizeof(glm::vec3), 16)));
  const glm::vec3 origin(b.origin);
  const GlProgram& main = dense_ ? (clamped ? dense_rigid_ : dense_affine_) : (clamped ? rigid_ : affine_);
  main.use();
  main.set("u_origin", origin);
  bind(1, offsets_);
  bind(2, ids_);
  bind(3, weights_);
  if (dense_) bind(6, bary_);  // the compact table's low weight bits
  if (clamped) {
    if (!dense_) bind(4, bary_);
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
  CAGEWRAP_CHECK(normals_ != nullptr, "GpuDeformer::normals: made for the positions alone");
  normals_->compute(target);
}

Result<std::unique_ptr<GpuStack>> GpuStack::create(std::span<const glm::vec3> skin_rest,
                                                   std::span<const Tri> triangles) {
  if (auto why = GpuDeformer::unsupported_reason(); !why.empty()) return make_error(ErrorCode::kUnsupportedFormat, why);
  std::unique_ptr<GpuStack> g(new GpuStack());
  g->num_points_ = skin_rest.size();
  g->max_groups_x_ = max_groups_per_row();
  std::string log;
  if (!g->combine_.build_compute("combine_stack.comp.glsl", {}, log))
    return make_error(ErrorCode::kParse, "the GPU stack's combine kernel does not compile: " + log);
  auto n = GpuNormals::create(skin_rest.size(), triangles);
  if (!n) return n.error();
  g->normals_ = std::move(n).value();
  if (auto s = fill_storage(g->rest_, skin_rest, "the rest skin", g->rest_bytes_); !s) return s.error();
  // each layer's slice starts where a storage buffer may be bound (GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT)
  GLint align = 0;
  glGetIntegerv(GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT, &align);
  const size_t a = static_cast<size_t>(std::max(align, 16));
  g->stride_ = (skin_rest.size_bytes() + a - 1) / a * a;
  glGenBuffers(1, &g->layer_skins_);
  glGenBuffers(1, &g->masks_);
  glGenBuffers(1, &g->mask_starts_);
  return g;
}

GpuStack::~GpuStack() {
  GLuint buffers[] = {rest_, layer_skins_, masks_, mask_starts_};
  glDeleteBuffers(static_cast<GLsizei>(std::size(buffers)), buffers);
}

size_t GpuStack::gpu_bytes() const {
  size_t bytes = rest_bytes_ + layers_allocated_ * stride_ + mask_bytes_ + normals_->gpu_bytes();
  for (const Held& h : deformers_) bytes += h.gpu->gpu_bytes();
  return bytes;
}

namespace {
std::string deformer_label(size_t index) {
  return index == 0 ? std::string("the document's cage (deformer 0)") : "deformer " + std::to_string(index);
}
}  // namespace

Result<GpuDeformer*> GpuStack::deformer_for(const Deformed& d) {
  CAGEWRAP_CHECK(d.deformer != nullptr, "GpuStack: a deformer of the frame has no deformer");
  if (d.deformer->binding().num_points != num_points_)
    return make_error(ErrorCode::kInvalidArgument, deformer_label(d.index) + " deforms " +
                                                       std::to_string(d.deformer->binding().num_points) +
                                                       " points but the skin has " + std::to_string(num_points_));
  auto it = std::find_if(deformers_.begin(), deformers_.end(), [&](const Held& h) { return h.deformer == d.deformer; });
  if (it == deformers_.end()) {
    auto g = GpuDeformer::create(*d.deformer);
    if (!g) return make_error(g.error().code, deformer_label(d.index) + ": " + g.error().message);
    deformers_.push_back({d.deformer, d.revision, std::move(g).value()});
    return deformers_.back().gpu.get();
  }
  if (it->revision != d.revision) {
    // the deformer was made again in the same place, or its table changed in place (a live set edit)
    if (auto s = it->gpu->table_changed(); !s) {
      deformers_.erase(it);
      return make_error(s.error().code, deformer_label(d.index) + ": " + s.error().message);
    }
    it->revision = d.revision;
  }
  return it->gpu.get();
}

Status GpuStack::upload_masks(std::span<const Deformed> layers) {
  bool same = masks_held_.size() == layers.size();
  for (size_t k = 0; same && k < layers.size(); ++k)
    same = masks_held_[k] == layers[k].mask && displacements_held_[k] == !layers[k].displacement.empty();
  if (same) return Ok{};
  // each layer's mask start, then whether it is a displacement (the combine kernel's MaskStarts)
  std::vector<uint32_t> starts(2 * layers.size(), kNoMask);
  for (size_t k = 0; k < layers.size(); ++k) starts[layers.size() + k] = layers[k].displacement.empty() ? 0u : 1u;
  size_t total = 0;
  for (size_t k = 0; k < layers.size(); ++k)
    if (layers[k].mask) total += layers[k].mask->size();
  if (total >= kNoMask)
    return make_error(ErrorCode::kInvalidArgument, "the layers' masks have " + std::to_string(total) +
                                                       " weights, more than the GPU stack indexes");
  std::vector<float> all;
  all.reserve(total);
  for (size_t k = 0; k < layers.size(); ++k)
    if (layers[k].mask) {
      starts[k] = static_cast<uint32_t>(all.size());
      all.insert(all.end(), layers[k].mask->begin(), layers[k].mask->end());
    }
  size_t bytes = 0;
  if (auto s = fill_storage(masks_, std::span<const float>(all), "the layers' masks", bytes); !s) return s;
  if (auto s = fill_storage(mask_starts_, std::span<const uint32_t>(starts), "the layers' mask starts", bytes); !s)
    return s;
  mask_bytes_ = bytes;
  masks_held_.clear();
  displacements_held_.clear();
  for (const Deformed& l : layers) {
    masks_held_.push_back(l.mask);
    displacements_held_.push_back(!l.displacement.empty());
  }
  return Ok{};
}

Status GpuStack::deform(const DeformerStack& stack, const Deformed* base, std::span<const Deformed> layers,
                        TriangleBuffer& target) {
  if (stack.mode == StackMode::kBlend && !(stack.exponent >= 0 && std::isfinite(stack.exponent)))
    return make_error(ErrorCode::kInvalidArgument, "the deformer stack's blend exponent must be a finite number >= 0, not " +
                                                       std::to_string(stack.exponent));
  for (const Deformed& l : layers) {
    if (l.mask && l.mask->size() != num_points_)
      return make_error(ErrorCode::kInvalidArgument, deformer_label(l.index) + "'s mask has " +
                                                         std::to_string(l.mask->size()) + " weights but the skin has " +
                                                         std::to_string(num_points_) + " points");
    if (!l.displacement.empty() && l.displacement.size() != num_points_)
      return make_error(ErrorCode::kInvalidArgument, "a parametric driver's displacement has " + std::to_string(l.displacement.size()) +
                                                         " points but the skin has " + std::to_string(num_points_));
  }
  // the deformers this frame leaves out go first: theirs may be gone (a rig dropped), so they are never used again
  std::erase_if(deformers_, [&](const Held& h) {
    if (base && base->deformer == h.deformer) return false;
    return std::none_of(layers.begin(), layers.end(), [&](const Deformed& l) { return l.deformer == h.deformer; });
  });
  target.allocate_vertices(num_points_);
  if (base) {
    auto g = deformer_for(*base);
    if (!g) return g.error();
    (*g)->deform_into(target.position_buffer(), 0);
  } else {  // f_0 is the rest skin
    glBindBuffer(GL_COPY_READ_BUFFER, rest_);
    glBindBuffer(GL_COPY_WRITE_BUFFER, target.position_buffer());
    glCopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, 0, 0,
                        static_cast<GLsizeiptr>(num_points_ * sizeof(glm::vec3)));
  }
  if (layers.empty()) return Ok{};
  if (layers.size() > layers_allocated_) {
    size_t bytes = 0;
    if (auto s = fill_storage(layer_skins_, nullptr, layers.size() * stride_,
                              "the skins of " + std::to_string(layers.size()) + " layers", bytes, GL_DYNAMIC_COPY);
        !s)
      return s;
    layers_allocated_ = layers.size();
  }
  for (size_t k = 0; k < layers.size(); ++k) {
    if (!layers[k].displacement.empty()) {  // a driver's displacement, made on the CPU
      glBindBuffer(GL_SHADER_STORAGE_BUFFER, layer_skins_);
      glBufferSubData(GL_SHADER_STORAGE_BUFFER, static_cast<GLintptr>(k * stride_),
                      static_cast<GLsizeiptr>(layers[k].displacement.size_bytes()), layers[k].displacement.data());
      continue;
    }
    auto g = deformer_for(layers[k]);
    if (!g) return g.error();
    (*g)->deform_into(layer_skins_, k * stride_);
  }
  if (auto s = upload_masks(layers); !s) return s;
  combine_.use();
  combine_.set("u_layers", static_cast<unsigned>(layers.size()));
  combine_.set("u_stride", static_cast<unsigned>(stride_ / sizeof(float)));
  combine_.set("u_mode", static_cast<unsigned>(stack.mode));
  combine_.set("u_exponent", static_cast<float>(stack.exponent));
  bind(0, rest_);
  bind(1, layer_skins_);
  bind(2, masks_);
  bind(3, mask_starts_);
  bind(7, target.position_buffer());
  dispatch(combine_, num_points_, max_groups_x_);
  barrier();
  return Ok{};
}

void GpuStack::normals(TriangleBuffer& target) { normals_->compute(target); }

}  // namespace cagewrap::render
