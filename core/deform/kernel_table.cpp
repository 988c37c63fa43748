#include "core/deform/kernel_table.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <type_traits>
#include <utility>
#include <vector>

#include <tbb/parallel_for.h>

#include "core/deform/deformer.h"

// the kernels pass 8-float vectors only between helpers inlined into one function
#pragma GCC diagnostic ignored "-Wpsabi"

namespace cagewrap {

namespace {

constexpr uint32_t kLanes = KernelTable::kLanes;

// A point's weights in units of 1 / `units`. Weights that sum to 1 (registration's) are rounded so
// that they sum to exactly `units` (the largest remainders get the missing units);
// others are rounded each to nearest.
// False when a weight is outside [0, 1] (a binding built by hand): the float kernel keeps those.
// `rem` is scratch.
bool quantize_weights(std::span<const float> w, uint32_t units, std::span<uint32_t> q, std::vector<double>& rem) {
  const double kUnits = units;
  double sum = 0.0;
  for (float x : w) {
    if (!(x >= 0.f && x <= 1.f)) return false;
    sum += x;
  }
  const size_t n = w.size();
  if (std::abs(sum - 1.0) > 1e-5) {
    for (size_t k = 0; k < n; ++k) q[k] = static_cast<uint32_t>(double(w[k]) * kUnits + 0.5);
    return true;
  }
  int64_t missing = units;
  for (size_t k = 0; k < n; ++k) {
    q[k] = static_cast<uint32_t>(double(w[k]) * kUnits);  // w >= 0: truncation is the floor
    missing -= q[k];
  }
  // at most n units are missing (the sum is within 1e-5 of 1); they go to the largest remainders
  // (ties: the earlier entry), by each entry's rank, counted without branches on the data
  if (missing > 0) {
    rem.resize(n);
    for (size_t k = 0; k < n; ++k) rem[k] = double(w[k]) * kUnits - q[k];
    for (size_t k = 0; k < n; ++k) {
      size_t rank = 0;
      for (size_t j = 0; j < n; ++j) rank += (rem[j] > rem[k]) | ((rem[j] == rem[k]) & (j < k));
      q[k] += rank < size_t(missing) && q[k] < units;
    }
  }
  return true;
}

// The distinct ids of a group's points, sorted, into `ids` (cleared first). `seen` (#maps, scratch)
// marks the ids met in this group by its number + 1, so that only the distinct ones (about 9 of some
// 60 entries) are sorted.
void group_ids(const Binding& b, size_t g, std::vector<uint32_t>& seen, std::vector<uint32_t>& ids) {
  ids.clear();
  const size_t i0 = g * kLanes, i1 = std::min<size_t>(b.num_points, i0 + kLanes);
  const uint32_t stamp = static_cast<uint32_t>(g + 1);
  for (uint32_t k = b.offsets[i0]; k < b.offsets[i1]; ++k) {
    const uint32_t id = b.ids[k];
    if (seen[id] != stamp) {
      seen[id] = stamp;
      ids.push_back(id);
    }
  }
  std::sort(ids.begin(), ids.end());
}

// Scratch of the table's making, per thread.
struct GroupScratch {
  std::vector<uint32_t> ids, seen, slot, q;
  std::vector<double> rem;
  explicit GroupScratch(uint32_t maps) : seen(maps, 0), slot(maps, 0) {}
};

// Group g's members (scratch.ids: its distinct ids, sorted) written from member m0 of `t` on, with
// their lane weights added into rows that hold zeros. False when a weight or an anchor coordinate is
// outside [0, 1] (a hand-made binding: the float table keeps those).
bool fill_group(const Binding& b, size_t g, KernelTable& t, size_t m0, GroupScratch& s) {
  constexpr uint32_t units = KernelTable::kUnits;
  for (size_t m = 0; m < s.ids.size(); ++m) {
    t.member_id[m0 + m] = static_cast<uint16_t>(s.ids[m]);
    s.slot[s.ids[m]] = static_cast<uint32_t>(m);
  }
  const size_t i0 = g * kLanes, i1 = std::min<size_t>(b.num_points, i0 + kLanes);
  for (size_t i = i0; i < i1; ++i) {
    const uint32_t o = b.offsets[i], n = b.offsets[i + 1] - o;
    s.q.resize(n);
    if (!quantize_weights(std::span<const float>(b.weights).subspan(o, n), units, s.q, s.rem)) return false;
    for (uint32_t k = 0; k < n; ++k) {
      const size_t m = s.slot[b.ids[o + k]];
      const size_t lane = i - i0;
      uint16_t* row = t.weights.data() + (m0 + m) * kLanes * t.rows();
      uint8_t* row_lo = t.weights_lo.data() + (m0 + m) * kLanes * t.rows();
      // an id twice in one stencil adds up (sums stay within units)
      auto add = [&](size_t cell, uint32_t v) {
        const uint32_t w24 = std::min<uint32_t>(units, ((uint32_t(row[cell]) << 8) | row_lo[cell]) + v);
        row[cell] = static_cast<uint16_t>(w24 >> 8);
        row_lo[cell] = static_cast<uint8_t>(w24 & 0xffu);
      };
      add(lane, s.q[k]);
      if (!t.rigid) continue;
      for (int c = 0; c < 2; ++c) {
        const float bc = b.bary[2 * size_t(o + k) + c];
        if (!(bc >= 0.f && bc <= 1.f)) return false;
        add((1 + c) * kLanes + lane, static_cast<uint32_t>(double(b.weights[o + k]) * bc * units + 0.5));
      }
    }
  }
  return true;
}

}  // namespace

size_t float_table_bytes(const Binding& b) {
  return b.offsets.size() * 4 + b.ids.size() * 4 + b.weights.size() * 4 + b.bary.size() * 4;
}

std::optional<KernelTable> make_kernel_table(const Binding& b) {
  KernelTable t;
  t.rigid = b.params.variant == Variant::kClamped;
  t.num_points = b.num_points;
  t.num_maps = b.num_samples > 0                          ? b.num_samples
               : b.params.variant == Variant::kExtended ? b.num_cage_vertices
                                                        : static_cast<uint32_t>(b.elements.size());
  // (Deformer::create validated the binding: ids below num_maps, offsets monotone)
  if (t.num_maps > 65536 || b.offsets.size() != size_t(b.num_points) + 1) return std::nullopt;
  const size_t groups = (size_t(b.num_points) + kLanes - 1) / kLanes;
  // pass 1: members per group
  std::vector<uint32_t> count(groups);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, groups, 1024), [&](const tbb::blocked_range<size_t>& r) {
    GroupScratch scratch(t.num_maps);
    for (size_t g = r.begin(); g != r.end(); ++g) {
      group_ids(b, g, scratch.seen, scratch.ids);
      count[g] = static_cast<uint32_t>(scratch.ids.size());
    }
  });
  t.group_start.resize(groups + 1);
  uint64_t members = 0;
  for (size_t g = 0; g < groups; ++g) {
    t.group_start[g] = static_cast<uint32_t>(members);
    members += count[g];
    if (members > UINT32_MAX) return std::nullopt;
  }
  t.group_start[groups] = static_cast<uint32_t>(members);
  // only when it pays: a skin whose neighbouring points share little would make larger groups than
  // the float table
  const size_t bytes = t.group_start.size() * 4 + members * 2 + members * kLanes * t.rows() * 3;
  if (bytes > float_table_bytes(b) && b.num_points > 0) return std::nullopt;
  t.member_id.resize(members + (members & 1));  // an even count: the GPU reads them two a 32-bit word
  t.weights.assign(members * kLanes * t.rows(), 0);
  t.weights_lo.assign(members * kLanes * t.rows(), 0);
  // pass 2: ids and lane weights
  std::atomic<bool> ok{true};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, groups, 1024), [&](const tbb::blocked_range<size_t>& r) {
    GroupScratch scratch(t.num_maps);
    for (size_t g = r.begin(); g != r.end() && ok; ++g) {
      group_ids(b, g, scratch.seen, scratch.ids);
      if (!fill_group(b, g, t, t.group_start[g], scratch)) ok = false;
    }
  });
  if (!ok) return std::nullopt;
  return t;
}

bool update_kernel_table(KernelTable& t, const Binding& b, std::span<const uint32_t> points) {
  if (t.num_points != b.num_points || t.rigid != (b.params.variant == Variant::kClamped)) return false;
  std::vector<uint32_t> touched;  // groups, ascending
  for (uint32_t i : points)
    if (i < t.num_points) touched.push_back(i / kLanes);
  std::sort(touched.begin(), touched.end());
  touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
  if (touched.empty()) return true;
  GroupScratch scratch(t.num_maps);
  std::vector<std::vector<uint32_t>> ids(touched.size());
  int64_t members = static_cast<int64_t>(t.group_start.back());
  bool same_sizes = true;
  for (size_t k = 0; k < touched.size(); ++k) {
    group_ids(b, touched[k], scratch.seen, scratch.ids);
    ids[k] = scratch.ids;
    const size_t g = touched[k], old = t.group_start[g + 1] - t.group_start[g];
    same_sizes = same_sizes && ids[k].size() == old;
    members += static_cast<int64_t>(ids[k].size()) - static_cast<int64_t>(old);
  }
  if (members > UINT32_MAX) return false;
  const size_t row = size_t(kLanes) * t.rows();  // weights per member
  if (!same_sizes) {
    // splice: the untouched groups' members move as blocks, the touched ones get their new sizes
    const size_t m_new = static_cast<size_t>(members);
    const size_t bytes = t.group_start.size() * 4 + m_new * 2 + m_new * row * 3;
    if (bytes > float_table_bytes(b)) return false;
    std::vector<uint32_t> start(t.group_start.size());
    std::vector<uint16_t> member_id(m_new + (m_new & 1), 0), weights(m_new * row, 0);
    std::vector<uint8_t> weights_lo(m_new * row, 0);
    size_t next = 0, k = 0, out = 0;
    const size_t groups = t.num_groups();
    auto copy_run = [&](size_t g0, size_t g1) {  // untouched groups g0 .. g1 - 1
      if (g0 >= g1) return;
      const size_t from = t.group_start[g0], count = t.group_start[g1] - from;
      for (size_t g = g0; g < g1; ++g) start[g] = static_cast<uint32_t>(out + (t.group_start[g] - from));
      std::copy_n(t.member_id.begin() + from, count, member_id.begin() + out);
      std::copy_n(t.weights.begin() + from * row, count * row, weights.begin() + out * row);
      std::copy_n(t.weights_lo.begin() + from * row, count * row, weights_lo.begin() + out * row);
      out += count;
    };
    for (; k < touched.size(); ++k) {
      copy_run(next, touched[k]);
      start[touched[k]] = static_cast<uint32_t>(out);
      out += ids[k].size();
      next = touched[k] + 1;
    }
    copy_run(next, groups);
    start[groups] = static_cast<uint32_t>(out);
    t.group_start = std::move(start);
    t.member_id = std::move(member_id);
    t.weights = std::move(weights);
    t.weights_lo = std::move(weights_lo);
  }
  // the touched groups' rows, zeroed and filled again
  for (size_t k = 0; k < touched.size(); ++k) {
    const size_t g = touched[k], m0 = t.group_start[g];
    std::fill_n(t.weights.begin() + m0 * row, ids[k].size() * row, uint16_t{0});
    std::fill_n(t.weights_lo.begin() + m0 * row, ids[k].size() * row, uint8_t{0});
    scratch.ids = ids[k];
    if (!fill_group(b, g, t, m0, scratch)) return false;
  }
  return true;
}

// ---- the kernels -------------------------------------------------------------------------------------
// One body, compiled four times: for AVX-512, AVX2 + FMA and AVX + FMA (chosen at run time where the
// processor has them) and for the baseline instruction set. GCC's vector extensions: 8 floats a register, points
// across lanes.

namespace {

typedef float f8 __attribute__((vector_size(32)));
typedef uint16_t u16x8 __attribute__((vector_size(16)));
typedef uint8_t u8x16 __attribute__((vector_size(16)));

// 8 lanes of 16-bit values, as floats
[[gnu::always_inline]] inline f8 lane_weights(const uint16_t* w) {
  u16x8 q;
  std::memcpy(&q, w, sizeof(q));
  return __builtin_convertvector(q, f8);
}

// 8 lanes of 24-bit weights (top 16 bits, low 8 bits), as floats (exact: below 2^24). The low bytes
// are widened to 16 bits by interleaving them with zeros (one unpack), not converted one by one.
[[gnu::always_inline]] inline f8 lane_weights(const uint16_t* hi, const uint8_t* lo) {
  u8x16 q = {};
  std::memcpy(&q, lo, 8);
  const u8x16 wide = __builtin_shufflevector(q, u8x16{}, 0, 16, 1, 16, 2, 16, 3, 16, 4, 16, 5, 16, 6, 16, 7, 16);
  u16x8 low;
  std::memcpy(&low, &wide, sizeof(low));
  return lane_weights(hi) * 256.f + __builtin_convertvector(low, f8);
}

struct Lanes {
  f8 x, y, z;
};

// The group's rest points relative to the origin, across lanes (0 beyond the skin's end).
[[gnu::always_inline]] inline Lanes load_points(const glm::vec3* skin, size_t i0, size_t n, const glm::vec3& o) {
  alignas(32) float x[kLanes] = {}, y[kLanes] = {}, z[kLanes] = {};
  for (size_t l = 0; l < n; ++l) {
    x[l] = skin[i0 + l].x - o.x;
    y[l] = skin[i0 + l].y - o.y;
    z[l] = skin[i0 + l].z - o.z;
  }
  Lanes p;
  std::memcpy(&p.x, x, sizeof(f8));
  std::memcpy(&p.y, y, sizeof(f8));
  std::memcpy(&p.z, z, sizeof(f8));
  return p;
}

[[gnu::always_inline]] inline void store_points(const f8& x, const f8& y, const f8& z, glm::vec3* dst, size_t i0,
                                                size_t n) {
  for (size_t l = 0; l < n; ++l) dst[i0 + l] = glm::vec3(x[l], y[l], z[l]);
}

// The blend applied to group g's rest points and stored: output row r is
// (rows[r][0] x + rows[r][1] y + rows[r][2] z + rows[r][3]) kScale + the origin's, per lane.
[[gnu::always_inline]] inline void finish_group(const KernelTable& t, size_t g, const f8 (&rows)[3][4],
                                                const glm::vec3* skin, const glm::vec3& o, glm::vec3* dst) {
  const size_t i0 = g * kLanes, n = std::min<size_t>(kLanes, t.num_points - i0);
  const Lanes p = load_points(skin, i0, n, o);
  const float s = KernelTable::kScale;
  f8 out[3];
  for (int r = 0; r < 3; ++r) out[r] = (rows[r][0] * p.x + rows[r][1] * p.y + rows[r][2] * p.z + rows[r][3]) * s;
  store_points(out[0] + o.x, out[1] + o.y, out[2] + o.z, dst, i0, n);
}

[[gnu::always_inline]] inline void affine_groups(const KernelTable& t, const Affine* maps, const glm::vec3* skin,
                                                 const glm::vec3& o, glm::vec3* dst, size_t g0, size_t g1) {
  const uint32_t* start = t.group_start.data();
  const uint16_t* ids = t.member_id.data();
  const uint16_t* weights = t.weights.data();
  const uint8_t* weights_lo = t.weights_lo.data();
  for (size_t g = g0; g < g1; ++g) {
    f8 acc[12];
    for (int c = 0; c < 12; ++c) acc[c] = f8{};
    for (uint32_t m = start[g]; m < start[g + 1]; ++m) {
      const f8 w = lane_weights(weights + size_t(m) * kLanes, weights_lo + size_t(m) * kLanes);
      const float* a = maps[ids[m]].m;
#pragma GCC unroll 12
      for (int c = 0; c < 12; ++c) acc[c] += w * a[c];
    }
    const f8 rows[3][4] = {{acc[0], acc[1], acc[2], acc[3]}, {acc[4], acc[5], acc[6], acc[7]},
                           {acc[8], acc[9], acc[10], acc[11]}};
    finish_group(t, g, rows, skin, o, dst);
  }
}

[[gnu::always_inline]] inline void rigid_groups(const KernelTable& t, const RigidMap* maps, const glm::vec3* skin,
                                                const glm::vec3& o, glm::vec3* dst, size_t g0, size_t g1) {
  const uint32_t* start = t.group_start.data();
  const uint16_t* ids = t.member_id.data();
  const uint16_t* weights = t.weights.data();
  const uint8_t* weights_lo = t.weights_lo.data();
  for (size_t g = g0; g < g1; ++g) {
    f8 acc[12];  // the blended rotation (9), then the blended anchor terms (3)
    for (int c = 0; c < 12; ++c) acc[c] = f8{};
    for (uint32_t m = start[g]; m < start[g + 1]; ++m) {
      const uint16_t* row = weights + size_t(m) * 3 * kLanes;
      const uint8_t* row_lo = weights_lo + size_t(m) * 3 * kLanes;
      const f8 w = lane_weights(row, row_lo), wb1 = lane_weights(row + kLanes, row_lo + kLanes),
               wb2 = lane_weights(row + 2 * kLanes, row_lo + 2 * kLanes);
      const RigidMap& r = maps[ids[m]];
#pragma GCC unroll 9
      for (int c = 0; c < 9; ++c) acc[c] += w * r.g[c];
#pragma GCC unroll 3
      for (int k = 0; k < 3; ++k) acc[9 + k] += w * r.q0[k] + wb1 * r.d1[k] + wb2 * r.d2[k];
    }
    const f8 rows[3][4] = {{acc[0], acc[1], acc[2], acc[9]}, {acc[3], acc[4], acc[5], acc[10]},
                           {acc[6], acc[7], acc[8], acc[11]}};
    finish_group(t, g, rows, skin, o, dst);
  }
}

// One map type's kernel over groups g0 .. g1 - 1.
template <class Map>
[[gnu::always_inline]] inline void groups(const KernelTable& t, const Map* maps, const glm::vec3* skin,
                                          const glm::vec3& o, glm::vec3* dst, size_t g0, size_t g1) {
  if constexpr (std::is_same_v<Map, Affine>) affine_groups(t, maps, skin, o, dst, g0, g1);
  else rigid_groups(t, maps, skin, o, dst, g0, g1);
}

template <class Map>
void groups_base(const KernelTable& t, const Map* maps, const glm::vec3* skin, const glm::vec3& o, glm::vec3* dst,
                 size_t g0, size_t g1) {
  groups(t, maps, skin, o, dst, g0, g1);
}

#if defined(__x86_64__) || defined(__i386__)
#define CAGEWRAP_KERNEL_AVX 1
template <class Map>
__attribute__((target("avx,fma"))) void groups_avx(const KernelTable& t, const Map* maps, const glm::vec3* skin,
                                                   const glm::vec3& o, glm::vec3* dst, size_t g0, size_t g1) {
  groups(t, maps, skin, o, dst, g0, g1);
}
// AVX2 widens the 16- and 8-bit weights to 8 lanes in one instruction each
template <class Map>
__attribute__((target("avx2,fma"))) void groups_avx2(const KernelTable& t, const Map* maps, const glm::vec3* skin,
                                                     const glm::vec3& o, glm::vec3* dst, size_t g0, size_t g1) {
  groups(t, maps, skin, o, dst, g0, g1);
}
// AVX-512 (VL): the same 8-lane code with 32 vector registers instead of 16 (the 12 accumulators, the
// weights and the broadcast coefficients fit without spilling)
template <class Map>
__attribute__((target("avx512f,avx512vl,avx512bw,avx2,fma"))) void groups_avx512(const KernelTable& t, const Map* maps,
                                                                               const glm::vec3* skin, const glm::vec3& o,
                                                                               glm::vec3* dst, size_t g0, size_t g1) {
  groups(t, maps, skin, o, dst, g0, g1);
}
#endif

// 0: the generic code, 1: AVX + FMA, 2: AVX2 + FMA, 3: AVX-512 (F, VL, BW) + FMA
int detect_isa() {
#ifdef CAGEWRAP_KERNEL_AVX
  __builtin_cpu_init();
  if (!__builtin_cpu_supports("avx") || !__builtin_cpu_supports("fma")) return 0;
  if (!__builtin_cpu_supports("avx2")) return 1;
  if (std::getenv("CAGEWRAP_KERNEL_NO_AVX512")) return 2;
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512bw") ? 3 : 2;
#else
  return 0;
#endif
}

int kernel_isa() {
  static const int isa = detect_isa();
  return isa;
}

// groups per task: 128 x 8 = 1024 points
constexpr size_t kKernelGrain = 128;

}  // namespace

bool kernel_uses_avx() { return kernel_isa() > 0; }

const char* kernel_isa_name() {
  static const char* names[] = {"generic", "AVX + FMA", "AVX2 + FMA", "AVX-512 + FMA"};
  return names[kernel_isa()];
}

namespace {

template <class Map>
void run_kernel(const KernelTable& t, std::span<const Map> maps, std::span<const glm::vec3> skin, const glm::vec3& origin,
                std::span<glm::vec3> out, [[maybe_unused]] KernelPath path) {
  auto* fn = groups_base<Map>;
#ifdef CAGEWRAP_KERNEL_AVX
  if (path == KernelPath::kBest && kernel_isa() == 1) fn = groups_avx<Map>;
  if (path == KernelPath::kBest && kernel_isa() == 2) fn = groups_avx2<Map>;
  if (path == KernelPath::kBest && kernel_isa() == 3) fn = groups_avx512<Map>;
#endif
  tbb::parallel_for(tbb::blocked_range<size_t>(0, t.num_groups(), kKernelGrain), [&](const tbb::blocked_range<size_t>& r) {
    fn(t, maps.data(), skin.data(), origin, out.data(), r.begin(), r.end());
  });
}

}  // namespace

void apply_kernel_affine(const KernelTable& t, std::span<const Affine> maps, std::span<const glm::vec3> skin,
                         const glm::vec3& origin, std::span<glm::vec3> out, KernelPath path) {
  run_kernel(t, maps, skin, origin, out, path);
}

void apply_kernel_rigid(const KernelTable& t, std::span<const RigidMap> maps, std::span<const glm::vec3> skin,
                        const glm::vec3& origin, std::span<glm::vec3> out, KernelPath path) {
  run_kernel(t, maps, skin, origin, out, path);
}

}  // namespace cagewrap
