// The binding's stencil as the deformation kernels stream it (issue 24; docs/benchmarks.md, "Kernel").
//
// The Binding keeps its float table (one entry per contributing element or cage vertex: id, weight,
// anchor), which registration, editing, files and exports read. The per-change kernel reads this
// compact copy instead, made once per table (Deformer::create, Deformer::stencil_changed):
//
//   - Points are taken in groups of kLanes consecutive skin points. A skin's neighbouring vertices
//     share most of their stencils (1M-vertex mannequin: 7.4 entries a point, 9.2 distinct ids a group
//     of 8), so each group lists its distinct ids once ("members") and, per member, one weight per
//     lane (0 where that point does not use it).
//   - Ids are 16-bit (map index); weights are 24-bit integers (a 16-bit and an 8-bit array), each
//     point's rounded so that they sum to exactly kUnits = 2^24 - 1 (largest remainder). 16-bit weights
//     were tried first: on a cylinder bent, twisted or shaken beyond what a rig does they moved the skin
//     by up to 6.7e-6 of the diagonal against the float table (2e-5 for the clamped variant's anchor
//     terms); 24 bits keep every variant within 1e-6 (tests/kernel_table_test.cpp). The clamped variant
//     also stores w b1 and w b2 per lane (its anchor folded into the weights).
//   - The kernel holds a group's 12 blended map coefficients in 8-lane registers (points across lanes),
//     walks the members once, then applies the blend to the 8 rest points: no per-entry index decode
//     per point and no branch that depends on a point's stencil size.
//
// A table that cannot be compact (more than 65536 maps, or a skin so incoherent that the groups would
// be larger than the float table) is not built; the deformer then runs the float kernel.
// The GPU path (render/gpu_deformer.h) uploads and reads this same table.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "core/deform/binding.h"

namespace cagewrap {

struct Affine;
struct RigidMap;

struct KernelTable {
  static constexpr uint32_t kLanes = 8;       // points per group
  static constexpr uint32_t kUnits = (1u << 24) - 1;  // a weight of 1
  static constexpr float kScale = 1.0f / float(kUnits);

  bool rigid = false;           // the clamped variant's layout (3 weight rows per member)
  uint32_t num_points = 0;
  uint32_t num_maps = 0;        // the ids index this many maps
  std::vector<uint32_t> group_start;  // #groups + 1: the first member of each group
  std::vector<uint16_t> member_id;    // #members (padded to an even count): the map each member names
  // #members x kLanes (affine) or x 3 kLanes (rigid: w, w b1, w b2): the top 16 bits of each 24-bit weight
  std::vector<uint16_t> weights;
  std::vector<uint8_t> weights_lo;  // the same layout: the low 8 bits

  size_t num_groups() const { return group_start.empty() ? 0 : group_start.size() - 1; }
  uint32_t rows() const { return rigid ? 3u : 1u; }
  // A weight as stored, in units of kScale: member m's row `row`, lane `lane`.
  uint32_t weight(size_t m, uint32_t row, uint32_t lane) const {
    const size_t cell = (m * rows() + row) * kLanes + lane;
    return (uint32_t(weights[cell]) << 8) | weights_lo[cell];
  }
  size_t bytes() const {
    return group_start.size() * 4 + member_id.size() * 2 + weights.size() * 2 + weights_lo.size();
  }
};

// Bytes of `b`'s float stencil (offsets, ids, weights, anchors: 8 B an entry, 16 with anchors): the
// compact table is made only when it is not larger.
size_t float_table_bytes(const Binding& b);

// The compact table of `b`'s main stencil, or nothing when it cannot be compact (see above).
std::optional<KernelTable> make_kernel_table(const Binding& b);
// `t` made again for `b` whose stencils changed for `points` only (a live set edit): the groups holding
// them are rebuilt, the others' members move as blocks. The result equals make_kernel_table(b). False
// (t unusable) when b no longer fits a compact table; make it again then.
bool update_kernel_table(KernelTable& t, const Binding& b, std::span<const uint32_t> points);

// Whether the kernels' best path on this machine is AVX code (else the generic vector code), and its
// name: "AVX-512 + FMA" (the 8-lane code with AVX-512 VL's 32 registers), "AVX2 + FMA", "AVX + FMA" or
// "generic". CAGEWRAP_KERNEL_NO_AVX512 in the environment keeps AVX-512 out (to compare).
bool kernel_uses_avx();
const char* kernel_isa_name();
// kBest: AVX-512, else AVX2 + FMA, else AVX + FMA, where the processor has them; kBaseline: the generic
// code (tests).
enum class KernelPath : uint8_t { kBest, kBaseline };

// out[i] = sum_k w_ik maps[id_k] (skin[i] - origin) + origin for every point of the table.
void apply_kernel_affine(const KernelTable& t, std::span<const Affine> maps, std::span<const glm::vec3> skin,
                         const glm::vec3& origin, std::span<glm::vec3> out, KernelPath path = KernelPath::kBest);
// The clamped variant: out[i] = sum_k (w G_k p + w q0_k + w b1 d1_k + w b2 d2_k) + origin, p = skin[i] - origin.
void apply_kernel_rigid(const KernelTable& t, std::span<const RigidMap> maps, std::span<const glm::vec3> skin,
                        const glm::vec3& origin, std::span<glm::vec3> out, KernelPath path = KernelPath::kBest);

}  // namespace cagewrap
