// Deformation phase (section 3.3, eq. 3): applies a Binding to the driver cage D.
// Validate once (create), then deform() per cage change: it checks only sizes, never allocates, and runs
// on all cores.
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include "core/deform/binding.h"
#include "core/deform/kernel_table.h"
#include "core/deform/vertex_frames.h"

namespace cagewrap {

// A 3x4 affine map in float, row-major, padded to 16 floats: y = M x + t.
struct alignas(64) Affine {
  float m[16];
};
// y = m x + t as an Affine (rounded to float).
Affine make_affine(const glm::dmat3& m, const glm::dvec3& t);

// The clamped variant's per-element map: rotation G (row-major) and the anchor terms
// q_i = v'_i - G v_i, stored as q0, q1 - q0, q2 - q0 so that the anchor is q0 + b1 d1 + b2 d2.
struct alignas(16) RigidMap {
  float g[9];
  float q0[3], d1[3], d2[3];
  float pad[2];
};

// Which table the per-change kernel reads: the compact copy (core/deform/kernel_table.h; the float
// table where it cannot be compact) or the binding's own float table.
enum class TableFormat : uint8_t { kCompact, kFloat };

class Deformer {
 public:
  // Keeps references to `binding` and `skin_rest` (#P x 3): both must outlive the deformer.
  static Result<Deformer> create(const Binding& binding, std::span<const glm::vec3> skin_rest,
                                 TableFormat format = TableFormat::kCompact);

  // Cheap check of a posed cage: same vertex count as the bound one, finite coordinates on every vertex
  // a valid element uses (vertices only bad elements use are ignored, like those elements).
  Status check_cage(std::span<const glm::vec3> posed) const;

  // Deforms into `out` (#P x 3). `vertex_linear`, for the extended variant only: the linear part of
  // the manipulation at each cage vertex (#Vc); absent, it is fitted from the one-rings.
  Status deform(std::span<const glm::vec3> posed, std::span<glm::vec3> out,
                std::span<const glm::dmat3> vertex_linear = {});

  // A sample-driven binding (Binding::num_samples > 0, core/deform/patch_binding.h): deforms into `out`
  // (#P x 3) with one map per sample (#samples, relative to Binding::origin), built by the driver
  // (PatchDeformer). The same kernel as deform().
  Status deform_with_maps(std::span<const Affine> maps, std::span<glm::vec3> out);

  // The first half of deform(): checks the posed cage and rebuilds the per-change maps from it
  // (cage-sized work), without applying them to the skin. A kernel elsewhere (the GPU deformer,
  // render/gpu_deformer.h) then applies the table with affine_maps() / rigid_maps().
  Status update_maps(std::span<const glm::vec3> posed, std::span<const glm::dmat3> vertex_linear = {});
  // The maps of the last update_maps() or deform(): basic, one per element (#E); extended, one per
  // cage vertex (#Vc); clamped, none. The stencil's ids index them.
  std::span<const Affine> affine_maps() const;
  // The clamped variant's per-element maps (#E), also used by the fallback points (rigid_points) of
  // any variant; empty when neither needs them.
  std::span<const RigidMap> rigid_maps() const { return rigid_maps_; }

  const Binding& binding() const { return *binding_; }
  std::span<const glm::vec3> skin_rest() const { return skin_; }  // #P x 3

  // The table of the Binding this deformer reads changed in place (Rebinder::update: same skin,
  // cage and parameters, some points re-registered): checks it again and sizes the fallback maps.
  // O(table); nothing per element is rebuilt. `points` (optional): the points whose stencils changed;
  // the compact table is then updated for their groups only (update_kernel_table), else made again.
  Status stencil_changed(std::span<const uint32_t> points = {});

  // The compact table the kernel reads, or null when it reads the binding's float table (kFloat, or a
  // table that cannot be compact). The GPU path uploads the same one.
  const KernelTable* kernel_table() const { return table_ ? &*table_ : nullptr; }
  // Bytes of the table the kernel reads (compact, or the binding's float stencil and offsets).
  size_t table_bytes() const;
  // Bytes the kernel reads and writes per call (table, rest skin, maps; output).
  size_t bytes_read_per_call() const;
  size_t bytes_written_per_call() const { return binding_->num_points * sizeof(glm::vec3); }

  Deformer(Deformer&&) noexcept;
  Deformer& operator=(Deformer&&) noexcept;
  ~Deformer();

 private:
  Deformer() = default;
  void build_element_maps(std::span<const glm::vec3> posed);
  void build_rigid_maps(std::span<const glm::vec3> posed);
  void build_vertex_maps(std::span<const glm::vec3> posed, std::span<const glm::dmat3> vertex_linear);
  // The table applied to the skin with `affine` (basic, extended: maps_; sample-driven: the
  // driver's) or rigid_maps_ (clamped), then the fallback points: the one kernel every deform path runs.
  void apply_table(std::span<const Affine> affine, std::span<glm::vec3> out) const;

  const Binding* binding_ = nullptr;
  std::span<const glm::vec3> skin_;
  TableFormat format_ = TableFormat::kCompact;
  std::optional<KernelTable> table_;  // the compact table (format_ kCompact and the table allows it)
  // per element, rest: inverse of the eq. 2 frame [e1 e2 e3] and the normal e3 (element_normals)
  std::vector<glm::dmat3> rest_frame_inv_;
  std::vector<glm::dvec3> rest_normal_;
  std::vector<glm::dvec3> normal_, ring_;  // scratch: posed element normals, per-vertex sums of crosses
  std::vector<Affine> maps_;        // per element (basic) or per vertex (extended), per change
  std::vector<RigidMap> rigid_maps_;  // per element (clamped variant and fallback points)
  std::vector<glm::dmat3> vertex_linear_;  // scratch for the one-ring fit
  std::unique_ptr<OneRingFit> fit_;
  std::vector<uint32_t> used_vertices_;  // vertices of valid elements
  bool need_rigid_ = false;
};

// Unit normals e3 of the binding's valid elements at `pos` (#E; `fallback[e]` for the others): the element's
// own, except where it is nearly collapsed (kCollapseRatio), where it leans continuously toward the
// area-weighted normal of the triangles around its corners, reaching it at zero area, and toward
// `fallback[e]` where that vanishes too. So an element that flattens as the cage moves keeps a normal that
// turns with its neighbours instead of jumping. `ring` is scratch (#V).
void element_normals(const Binding& b, std::span<const glm::vec3> pos, std::span<const glm::dvec3> fallback,
                     std::vector<glm::dvec3>& ring, std::vector<glm::dvec3>& out);

// Several deformers on one skin (section 6): combine their displacements dP_i = P_i - P.
enum class CombineMode { kSum, kWeighted };
// kSum: P + sum dP_i. kWeighted (Singh & Fiume, Wires): P + sum dP_i |dP_i|^m / sum |dP_i|^m, computed in
// double with |dP_i| taken relative to the largest (no overflow or underflow for any m; m = 0 is the
// mean). Errors: m negative or not finite (kWeighted), sizes that differ.
Status combine_displacements(std::span<const glm::vec3> rest, std::span<const std::span<const glm::vec3>> deformed,
                             CombineMode mode, double m, std::span<glm::vec3> out);

}  // namespace cagewrap
