// Binding a skin to a parametric driver (section 3.3, last paragraph) and deforming it.
//
// The control elements are the samples of core/deform/patch_surface.h. Sample k at rest has the point S_k
// and the frame F_k = [S_u, S_v, N] (N = S_u x S_v normalised); posed, S'_k and F'_k. Its map is
//   A_k(p) = S'_k + F'_k F_k^-1 (p - S_k),
// the sample's version of eq. 2/3 (local coordinates in F_k, rebuilt in F'_k). The weights are eq. 1
// on the distance from the skin point to the sample point, in units of h (0 = the mean control-net
// edge length), with the same relative threshold epsilon, at most K samples and the same taper as
// polygon elements (registration.h: taper_cut, tapered_weights). The result is an ordinary Binding
// whose elements are samples (Binding::num_samples; basic variant), applied by the Deformer's one
// kernel (Deformer::deform_with_maps); PatchDeformer builds the per-sample maps from the posed
// control points. See docs/parametric-drivers.md.
#pragma once

#include <span>
#include <vector>

#include "core/deform/binding.h"
#include "core/deform/deformer.h"
#include "core/deform/patch_surface.h"
#include "core/deform/registration.h"

namespace cagewrap {

// Binds `skin` to the samples of `rest` at `density` (core/deform/patch_surface.h). params.variant and
// the separation settings are ignored (the basic variant; no skeleton labels). `edits` (contributing-set
// edits whose element ids are sample ids; any order) act as on a cage: excluded samples leave a point's
// candidates, included ones join its set with their own weight, `only` keeps the included alone; a point
// left with none follows its nearest valid sample. Errors also name an edit's point or sample out of range.
// A point that no sample reaches (max_distance) follows its nearest valid sample alone. Errors: bad
// parameters or density, a surface validate_patch_surface refuses, an empty or non-finite skin,
// no valid sample, a zero control-net scale, cancellation. Reports progress like bind_skin.
Result<Binding> bind_skin_to_patches(std::span<const glm::vec3> skin, const PatchSurface& rest,
                                     uint32_t density, const BindParams& params,
                                     const BindProgress& progress = {}, std::span<const SetEdit> edits = {});
// How many samples `rest` has at `density` (the element ids set edits on a driver name); 0 when it cannot
// be sampled.
size_t patch_sample_count(const PatchSurface& rest, uint32_t density);
// The parameters bind_skin_to_patches binds with (and records in Binding::params): `params` with the
// basic variant and no separation.
BindParams patch_bind_params(const BindParams& params);

// Deforms a skin bound by bind_skin_to_patches. Keeps references to `binding` and `skin_rest` (both
// must outlive it); copies what it needs of the rest surface.
class PatchDeformer {
 public:
  // Errors: the binding is not a sample binding of this surface and density (sample count), the
  // skin size differs, a bad surface.
  static Result<PatchDeformer> create(const Binding& binding, std::span<const glm::vec3> skin_rest,
                                      const PatchSurface& rest, uint32_t density);

  // Checks the posed surface (same grids and sizes as the rest surface, finite control points),
  // rebuilds the per-sample maps and applies the table to the skin (#P x 3).
  Status deform(const PatchSurface& posed, std::span<glm::vec3> out);

 private:
  explicit PatchDeformer(Deformer d) : deformer_(std::move(d)) {}
  Status update_maps(const PatchSurface& posed);
  Deformer deformer_;
  std::vector<uint32_t> shape_;          // rows, cols and basis of each grid (to check posed surfaces)
  std::vector<PatchSample> samples_;     // #S
  std::vector<glm::dvec3> rest_point_;   // #S, relative to the binding's origin
  std::vector<glm::dvec3> rest_normal_;  // #S
  std::vector<glm::dmat3> rest_inv_;     // #S inverse rest frames (identity for degenerate samples)
  std::vector<uint8_t> valid_;           // #S
  std::vector<Affine> maps_;             // #S
};

// Rest positions of the samples (#S x 3), for display and tests.
std::vector<glm::vec3> sample_positions(const PatchSurface& surface, std::span<const PatchSample> samples);

}  // namespace cagewrap
