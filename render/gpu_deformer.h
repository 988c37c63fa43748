// The deformation phase on the GPU (OpenGL 4.3 compute shaders: shaders/deform.comp.glsl and
// shaders/normals.comp.glsl).
//
// Bind once, deform many, as on the CPU (core/deform/deformer.h): the binding's stencil table, the rest
// skin and the skin's vertex -> triangles table are uploaded once. Per cage change only the maps
// core's Deformer builds from the posed cage go up (Deformer::update_maps: one 3x4 map per element
// or cage vertex, rigid maps for the clamped variant and the fallback points; a few hundred KB),
// then one compute pass writes the deformed positions and two more write the smooth normals, straight
// into the vertex buffers that are drawn (render::TriangleBuffer). Nothing comes back to the CPU.
// The kernels do Deformer::deform's float32 arithmetic in the same order, and the normals are
// core/geometry/mesh_normals.h's (tests/gpu_deformer_test.cpp holds both paths to each other).
#pragma once

#include <epoxy/gl.h>

#include <algorithm>
#include <memory>
#include <span>
#include <string>

#include "core/deform/deformer.h"
#include "core/geometry/mesh.h"
#include "core/base/result.h"
#include "render/gl_program.h"
#include "render/gpu_buffers.h"

namespace cagewrap::render {

class GpuDeformer {
 public:
  // Why the current GL context cannot run the kernels (older than 4.3), or empty when it can.
  static std::string unsupported_reason();

  // `deformer` (with its binding and rest skin) must outlive this; `triangles` index the skin and
  // must be what the target buffers' index buffer holds. Fails, saying why, when the context is
  // older than 4.3, a kernel does not compile, or a table is larger than the GL's shader-storage
  // limit (naming the table, its size and the limit).
  static Result<std::unique_ptr<GpuDeformer>> create(const Deformer& deformer, std::span<const Tri> triangles);

  GpuDeformer(const GpuDeformer&) = delete;
  GpuDeformer& operator=(const GpuDeformer&) = delete;
  ~GpuDeformer();

  // The binding's table changed in place (Deformer::stencil_changed after a live set edit): uploads
  // it again. Same checks as create.
  Status table_changed();

  // Uploads the maps of the deformer's last update_maps() (call it first, with the posed cage) and
  // writes the deformed skin into `target`'s position buffer (sized here).
  void deform(TriangleBuffer& target);
  // Recomputes `target`'s normals from its positions (after deform()).
  void normals(TriangleBuffer& target);

  // For tests: pretends the GL allows at most `groups` work groups per row, so that the 2-D grid
  // large skins need (over 16.7M points at the guaranteed 65535) runs on a small one.
  void limit_groups_per_row(size_t groups) { max_groups_x_ = std::max<size_t>(groups, 1); }

  size_t num_points() const;
  // Bytes held on the GPU: table, rest skin, adjacency, scratch and maps (not the target buffers).
  size_t gpu_bytes() const { return table_bytes_ + topology_bytes_ + maps_bytes_; }
  // Bytes uploaded per cage change (the maps).
  size_t bytes_uploaded_per_change() const;

 private:
  GpuDeformer() = default;
  Status upload_table();
  Status upload_topology(std::span<const Tri> triangles);

  const Deformer* deformer_ = nullptr;
  GlProgram affine_, rigid_, fallback_, faces_, vertices_;
  // shader-storage buffers
  GLuint rest_ = 0, offsets_ = 0, ids_ = 0, weights_ = 0, bary_ = 0, fallback_list_ = 0;  // once per table
  GLuint affine_maps_ = 0, rigid_maps_ = 0;                                            // per change
  GLuint starts_ = 0, incident_ = 0, face_normals_ = 0;                                 // skin topology
  size_t num_fallback_ = 0, num_triangles_ = 0, num_vertices_ = 0;
  size_t max_groups_x_ = 65535;  // GL_MAX_COMPUTE_WORK_GROUP_COUNT[0]
  size_t affine_allocated_ = 0, rigid_allocated_ = 0;  // bytes of the map buffers
  size_t table_bytes_ = 0, topology_bytes_ = 0, maps_bytes_ = 0;
};

}  // namespace cagewrap::render
