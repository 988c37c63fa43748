// The deformation phase on the GPU (OpenGL 4.3 compute shaders: shaders/deform.comp.glsl,
// shaders/normals.comp.glsl and, for a stack of deformers, shaders/combine_stack.comp.glsl).
//
// Bind once, deform many, as on the CPU (core/deform/deformer.h): the binding's stencil table, the rest
// skin and the skin's vertex -> triangles table are uploaded once. Per cage change only the maps
// core's Deformer builds from the posed cage go up (Deformer::update_maps: one 3x4 map per element
// or cage vertex, rigid maps for the clamped variant and the fallback points; a few hundred KB),
// then one compute pass writes the deformed positions and two more write the smooth normals, straight
// into the vertex buffers that are drawn (render::TriangleBuffer). Nothing comes back to the CPU.
// The kernels do Deformer::deform's float32 arithmetic in the same order, and the normals are
// core/geometry/mesh_normals.h's (tests/gpu_deformer_test.cpp holds both paths to each other).
//
// Several deformers on one skin (issue 21, docs/deformer-stack.md: GpuStack below): one GpuDeformer
// per deformer, each with its own table and maps; the document's cage deforms into the drawn buffer,
// every other deformer into its slice of a table of layer skins, then one pass combines them there as
// core/rig/deformer_stack.h combine_stack does (each layer's mask a slice of a mask table), and the
// normals pass runs on the result (tests/gpu_stack_test.cpp holds it to the CPU rig).
#pragma once

#include <epoxy/gl.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/deform/deformer.h"
#include "core/geometry/mesh.h"
#include "core/base/result.h"
#include "core/document/document.h"
#include "render/gl_program.h"
#include "render/gpu_buffers.h"

namespace cagewrap::render {

// Smooth vertex normals of a skin whose positions a kernel wrote (shaders/normals.comp.glsl): the
// skin's vertex -> triangles table is uploaded once.
class GpuNormals {
 public:
  // `triangles` index the skin's `num_vertices` points and must be what the target buffers' index
  // buffer holds. Fails, saying why, when a kernel does not compile or a table is over the GL's limit.
  static Result<std::unique_ptr<GpuNormals>> create(size_t num_vertices, std::span<const Tri> triangles);
  GpuNormals(const GpuNormals&) = delete;
  GpuNormals& operator=(const GpuNormals&) = delete;
  ~GpuNormals();

  // Recomputes `target`'s normals from its positions.
  void compute(TriangleBuffer& target);
  void limit_groups_per_row(size_t groups) { max_groups_x_ = std::max<size_t>(groups, 1); }
  size_t gpu_bytes() const { return bytes_; }

 private:
  GpuNormals() = default;
  GlProgram faces_, vertices_;
  GLuint starts_ = 0, incident_ = 0, face_normals_ = 0;
  size_t num_triangles_ = 0, num_vertices_ = 0, bytes_ = 0;
  size_t max_groups_x_ = 65535;
};

class GpuDeformer {
 public:
  // Why the current GL context cannot run the kernels (older than 4.3), or empty when it can.
  static std::string unsupported_reason();

  // `deformer` (with its binding and rest skin) must outlive this; `triangles` index the skin and
  // must be what the target buffers' index buffer holds. Fails, saying why, when the context is
  // older than 4.3, a kernel does not compile, or a table is larger than the GL's shader-storage
  // limit (naming the table, its size and the limit).
  static Result<std::unique_ptr<GpuDeformer>> create(const Deformer& deformer, std::span<const Tri> triangles);
  // The positions alone, for a deformer of a stack (GpuStack computes the combined skin's normals):
  // normals() must not be called.
  static Result<std::unique_ptr<GpuDeformer>> create(const Deformer& deformer);

  GpuDeformer(const GpuDeformer&) = delete;
  GpuDeformer& operator=(const GpuDeformer&) = delete;
  ~GpuDeformer();

  // The binding's table changed in place (Deformer::stencil_changed after a live set edit): uploads
  // it again. Same checks as create.
  Status table_changed();

  // Uploads the maps of the deformer's last update_maps() (call it first, with the posed cage) and
  // writes the deformed skin into `target`'s position buffer (sized here).
  void deform(TriangleBuffer& target);
  // The same into shader-storage buffer `buffer` from byte `offset` on (a multiple of
  // GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT), which must hold num_points() x 3 floats there.
  void deform_into(GLuint buffer, size_t offset);
  // Recomputes `target`'s normals from its positions (after deform()).
  void normals(TriangleBuffer& target);

  // For tests: pretends the GL allows at most `groups` work groups per row, so that the 2-D grid
  // large skins need (over 16.7M points at the guaranteed 65535) runs on a small one.
  void limit_groups_per_row(size_t groups) {
    max_groups_x_ = std::max<size_t>(groups, 1);
    if (normals_) normals_->limit_groups_per_row(groups);
  }

  size_t num_points() const;
  // Whether the uploaded table is the deformer's compact one (Deformer::kernel_table), not the float table.
  bool reads_compact_table() const { return dense_; }
  // Bytes held on the GPU: table, rest skin, adjacency, scratch and maps (not the target buffers).
  size_t gpu_bytes() const { return table_bytes_ + (normals_ ? normals_->gpu_bytes() : 0) + maps_bytes_; }
  // Bytes uploaded per cage change (the maps).
  size_t bytes_uploaded_per_change() const;

 private:
  GpuDeformer() = default;
  static Result<std::unique_ptr<GpuDeformer>> make(const Deformer& deformer);
  Status upload_table();

  const Deformer* deformer_ = nullptr;
  GlProgram affine_, rigid_, fallback_;
  GlProgram dense_affine_, dense_rigid_;  // the same kernels reading the compact table (Deformer::kernel_table)
  bool dense_ = false;                    // the uploaded table is the compact one
  // shader-storage buffers
  // once per table (compact: offsets_ the groups, ids_ the 16-bit ids, weights_ the weights' top 16
  // bits, bary_ their low 8 bits)
  GLuint rest_ = 0, offsets_ = 0, ids_ = 0, weights_ = 0, bary_ = 0, fallback_list_ = 0;
  GLuint affine_maps_ = 0, rigid_maps_ = 0;                                            // per change
  std::unique_ptr<GpuNormals> normals_;  // null: positions only
  size_t num_fallback_ = 0;
  size_t max_groups_x_ = 65535;  // GL_MAX_COMPUTE_WORK_GROUP_COUNT[0]
  size_t affine_allocated_ = 0, rigid_allocated_ = 0;  // bytes of the map buffers
  size_t table_bytes_ = 0, maps_bytes_ = 0;
};

// A stack of deformers on one skin (issue 21, docs/deformer-stack.md), deformed and combined on the GPU:
// each deformer's own pass (a GpuDeformer, made when it first comes and kept while it stays), then one
// pass that does core/rig/deformer_stack.h combine_stack's arithmetic per point (float32 where the CPU
// computes in double: the two agree within 1e-5 of the skin's diagonal), then the normals. Per frame
// only each deformer's maps go up; a table when its revision changes, the masks when they change.
class GpuStack {
 public:
  // One deformer of the frame.
  struct Deformed {
    size_t index = 0;                    // its number in the stack (0: the document's cage), for messages
    const Deformer* deformer = nullptr;  // its maps built for this frame (Deformer::update_maps)
    // Changes whenever the deformer or its table does (a rebind, a live set edit): the GPU's copy follows.
    uint64_t revision = 0;
    std::shared_ptr<const std::vector<float>> mask;  // #P weights in [0, 1], or null: 1 everywhere (layers)
    // Non-empty (#P): a parametric driver's displacement of this frame (no deformer), uploaded and added
    // where it sits (core/rig/deformer_stack.h combine_layers); its mask as a layer's.
    std::span<const glm::vec3> displacement;
  };

  // `skin_rest` (#P) is every deformer's rest skin; `triangles` index it and must be what the target
  // buffers' index buffer holds. Fails, saying why, as GpuDeformer::create.
  static Result<std::unique_ptr<GpuStack>> create(std::span<const glm::vec3> skin_rest, std::span<const Tri> triangles);
  GpuStack(const GpuStack&) = delete;
  GpuStack& operator=(const GpuStack&) = delete;
  ~GpuStack();

  // Writes the frame's skin into `target`'s positions: `base` (deformer 0, f_0; null: it is muted and
  // f_0 is the rest skin) with `layers` (the other deformers that move the skin, in stack order)
  // combined over it as `stack` says. A deformer's GpuDeformer is made the first time it comes (its
  // table uploaded) and dropped when a frame leaves it out. Fails, naming the deformer or table, when
  // one cannot go to the GPU (GpuDeformer::create's reasons), a mask has the wrong size, or the
  // stack's blend exponent is not a finite number >= 0.
  Status deform(const DeformerStack& stack, const Deformed* base, std::span<const Deformed> layers,
                TriangleBuffer& target);
  // Recomputes `target`'s normals from its positions (after deform()).
  void normals(TriangleBuffer& target);

  size_t num_points() const { return num_points_; }
  // How many deformers the GPU holds tables for (those of the last deform()).
  size_t num_deformers() const { return deformers_.size(); }
  // Bytes held on the GPU: the deformers' tables and maps, the layer skins, the masks, rest skin and normals.
  size_t gpu_bytes() const;

 private:
  GpuStack() = default;
  // The GpuDeformer of `d`, made or brought up to date (its revision).
  Result<GpuDeformer*> deformer_for(const Deformed& d);
  Status upload_masks(std::span<const Deformed> layers);

  struct Held {
    const Deformer* deformer = nullptr;
    uint64_t revision = 0;
    std::unique_ptr<GpuDeformer> gpu;
  };
  std::vector<Held> deformers_;
  std::unique_ptr<GpuNormals> normals_;
  GlProgram combine_;
  GLuint rest_ = 0, layer_skins_ = 0, masks_ = 0, mask_starts_ = 0;
  size_t num_points_ = 0, stride_ = 0;  // bytes from one layer's slice to the next
  size_t layers_allocated_ = 0;          // slices the layer table holds
  // the masks the GPU holds, kept alive so that a pointer names the same weights while it is held
  std::vector<std::shared_ptr<const std::vector<float>>> masks_held_;
  std::vector<bool> displacements_held_;  // which layers of the held masks were displacements
  size_t rest_bytes_ = 0, mask_bytes_ = 0;
  size_t max_groups_x_ = 65535;
};

}  // namespace cagewrap::render
