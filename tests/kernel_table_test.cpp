// The compact table the deformation kernel reads (core/deform/kernel_table.h, issue 24) against the
// binding's float table: the same deformed skin within 1e-6 of the skin's bounding-box diagonal, for
// every variant, on the bench mannequin (shared assets) and on generated skins; the weights' exact
// sums; the fallbacks to the float table; the AVX and generic code paths; the GPU path in
// tests/gpu_deformer_test.cpp reads the same table.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "core/cage/cage.h"
#include "core/deform/deformer.h"
#include "core/deform/kernel_table.h"
#include "core/deform/registration.h"
#include "core/geometry/mesh_io.h"
#include "core/geometry/subdivide.h"
#include "tests/fixtures.h"
#include "tests/test_assets.h"

namespace cagewrap {
namespace {

// The bar: the compact table changes the deformed skin by at most this much of the diagonal.
constexpr double kFidelity = 1e-6;

double diagonal_of(std::span<const glm::vec3> pts) {
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (const auto& p : pts) lo = glm::min(lo, p), hi = glm::max(hi, p);
  return glm::length(glm::dvec3(hi - lo));
}

// Cage states between rest and `posed`, and the posed cage pushed further (1.5x), each deformed through
// the float table and through the compact one: the largest difference relative to the diagonal.
double worst_difference(const Binding& b, std::span<const glm::vec3> skin, std::span<const glm::vec3> rest_cage,
                        std::span<const glm::vec3> posed, bool expect_compact = true) {
  auto exact = Deformer::create(b, skin, TableFormat::kFloat);
  auto compact = Deformer::create(b, skin, TableFormat::kCompact);
  EXPECT_TRUE(exact.ok() && compact.ok());
  if (!exact.ok() || !compact.ok()) return 1.0;
  EXPECT_EQ(exact->kernel_table(), nullptr);
  EXPECT_EQ(compact->kernel_table() != nullptr, expect_compact);
  const double diag = diagonal_of(skin);
  std::vector<glm::vec3> a(skin.size()), c(skin.size()), state(rest_cage.size());
  double worst = 0.0;
  for (double t : {0.0, 0.3, 1.0, 1.5}) {
    for (size_t v = 0; v < state.size(); ++v)
      state[v] = glm::vec3(glm::mix(glm::dvec3(rest_cage[v]), glm::dvec3(posed[v]), t));
    EXPECT_TRUE(exact->deform(state, a).ok());
    EXPECT_TRUE(compact->deform(state, c).ok());
    for (size_t i = 0; i < skin.size(); ++i) worst = std::max(worst, double(glm::length(a[i] - c[i])) / diag);
  }
  return worst;
}

const Variant kTableVariants[] = {Variant::kBasic, Variant::kClamped, Variant::kExtended};

// The cage twisted about the x axis by `degrees` from x = -0.3 to x = 4.3 (the cylinder cage's ends).
std::vector<glm::vec3> twisted(std::span<const glm::vec3> rest, double degrees) {
  std::vector<glm::vec3> out(rest.begin(), rest.end());
  for (size_t v = 0; v < rest.size(); ++v) {
    const double angle = glm::radians(degrees) * std::clamp((rest[v].x + 0.3) / 4.6, 0.0, 1.0);
    const glm::dvec3 p(rest[v]);
    out[v] = glm::vec3(p.x, p.y * std::cos(angle) - p.z * std::sin(angle), p.y * std::sin(angle) + p.z * std::cos(angle));
  }
  return out;
}

TEST(KernelTable, BenchMannequinDeformsAsTheFloatTableDoes) {
  CAGEWRAP_REQUIRE_ASSETS(dir);
  const std::string d = dir + "/bench/mannequiny/";
  auto mesh = load_mesh(d + "mesh_7136.obj");
  auto cage_mesh = load_mesh(d + "cage.obj");
  auto posed = load_mesh(d + "cage_posed.obj");
  ASSERT_TRUE(mesh.ok() && cage_mesh.ok() && posed.ok());
  auto cage = make_cage(*cage_mesh, "cage.obj");
  ASSERT_TRUE(cage.ok());
  const PolyMesh skin = subdivide_edges_uniform(*mesh, 3);  // 114k points: the 1M bench's table, smaller
  ASSERT_NE(skin.positions.size() % KernelTable::kLanes, 0u) << "the last group should be a partial one";
  for (Variant v : kTableVariants) {
    BindParams p;
    p.variant = v;
    auto b = bind_skin(skin.positions, *cage, cage->polygons.positions, p);
    ASSERT_TRUE(b.ok());
    // the clamped variant's compact table (3 weight rows) outweighs its float table until about 180k
    // points here (at 1M: 94.5 against 128.9 B/vertex), so at this size it keeps the float one
    const bool compact = v != Variant::kClamped;
    const double worst = worst_difference(*b, skin.positions, cage->polygons.positions, posed->positions, compact);
    EXPECT_LE(worst, kFidelity) << variant_name(v);
    std::printf("  %s: compact vs float table, worst %.2e of the diagonal\n", variant_name(v), worst);
  }
}

TEST(KernelTable, GeneratedSkinsDeformAsTheFloatTableDoes) {
  // a cylinder bent 75 degrees (extrapolated: 112), twisted 180 degrees along its length (extrapolated:
  // 270), and its cage shaken at random by a fifth of its ring spacing. With 16-bit weights this moved
  // the skin by up to 6.7e-6 of the diagonal (2e-5 for the clamped variant's anchor terms).
  const PolyMesh skin = fixtures::cylinder_skin(0.5, 4.0, 37, 41);  // 1517 points: a partial last group
  const Cage cage = fixtures::cylinder_cage();
  const auto& rest = cage.polygons.positions;
  std::vector<std::vector<glm::vec3>> poses{fixtures::bent(rest, 2.0, 75.0), twisted(rest, 180.0), rest};
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> jitter(-0.15f, 0.15f);  // rings are 0.77 apart
  for (auto& q : poses[2]) q += glm::vec3(jitter(rng), jitter(rng), jitter(rng));
  const char* names[] = {"bent", "twisted", "shaken"};
  for (Variant v : kTableVariants)
    for (double local : {2.0, 4.0, 8.0}) {
      BindParams p;
      p.variant = v;
      p.local = local;
      auto b = bind_skin(skin.positions, cage, rest, p);
      ASSERT_TRUE(b.ok());
      for (size_t k = 0; k < poses.size(); ++k)
        EXPECT_LE(worst_difference(*b, skin.positions, rest, poses[k]), kFidelity)
            << variant_name(v) << ", local " << local << ", " << names[k];
    }
}

TEST(KernelTable, EachPointsWeightsSumToExactlyOne) {
  const PolyMesh skin = fixtures::cylinder_skin(0.5, 4.0, 37, 41);
  const Cage cage = fixtures::cylinder_cage();
  for (Variant v : kTableVariants) {
    BindParams p;
    p.variant = v;
    auto b = bind_skin(skin.positions, cage, cage.polygons.positions, p);
    ASSERT_TRUE(b.ok());
    auto t = make_kernel_table(*b);
    ASSERT_TRUE(t.has_value()) << variant_name(v);
    EXPECT_EQ(t->rigid, v == Variant::kClamped);
    std::vector<uint32_t> sum(t->num_points, 0);
    std::vector<uint32_t> members(t->num_points, 0);
    const uint32_t L = KernelTable::kLanes;
    for (size_t g = 0; g < t->num_groups(); ++g)
      for (uint32_t m = t->group_start[g]; m < t->group_start[g + 1]; ++m) {
        EXPECT_LT(t->member_id[m], t->num_maps);
        if (m > t->group_start[g]) EXPECT_LT(t->member_id[m - 1], t->member_id[m]) << "members sorted, distinct";
        for (uint32_t l = 0; l < L && g * L + l < t->num_points; ++l) {
          auto weight = [&](uint32_t row) { return t->weight(m, row, l); };
          const uint32_t w = weight(0);
          sum[g * L + l] += w;
          members[g * L + l] += w > 0;
          if (t->rigid)  // w b1 and w b2 never exceed w by more than rounding
            for (uint32_t r = 1; r < 3; ++r) EXPECT_LE(weight(r), w + 1u);
        }
      }
    std::vector<bool> fallback(b->num_points, false);
    for (uint32_t i : b->rigid_points) fallback[i] = true;
    for (uint32_t i = 0; i < t->num_points; ++i) {
      if (fallback[i]) continue;
      ASSERT_EQ(sum[i], KernelTable::kUnits) << variant_name(v) << ", point " << i;
      EXPECT_LE(members[i], b->offsets[i + 1] - b->offsets[i]) << "point " << i;
    }
  }
}

TEST(KernelTable, AnIncoherentSkinKeepsTheFloatTable) {
  // the same points in random order: a group's 8 points share almost nothing, so its members would
  // outweigh the float table; the deformer reads the float table and says so
  PolyMesh skin = fixtures::cylinder_skin();
  std::mt19937 rng(7);
  std::shuffle(skin.positions.begin(), skin.positions.end(), rng);
  const Cage cage = fixtures::cylinder_cage();
  auto b = bind_skin(skin.positions, cage, cage.polygons.positions, BindParams{});
  ASSERT_TRUE(b.ok());
  EXPECT_FALSE(make_kernel_table(*b).has_value());
  const auto bent = fixtures::bent(cage.polygons.positions, 2.0, 60.0);
  EXPECT_EQ(worst_difference(*b, skin.positions, cage.polygons.positions, bent, /*expect_compact=*/false), 0.0);
}

TEST(KernelTable, TablesItCannotHoldAreRefused) {
  const PolyMesh skin = fixtures::cylinder_skin();
  const Cage cage = fixtures::cylinder_cage();
  auto b = bind_skin(skin.positions, cage, cage.polygons.positions, BindParams{});
  ASSERT_TRUE(b.ok());
  ASSERT_TRUE(make_kernel_table(*b).has_value());
  Binding wide = *b;  // more maps than 16-bit ids can name
  wide.num_cage_vertices = 70000;
  wide.rest_cage.resize(70000, glm::vec3(0.f));
  EXPECT_FALSE(make_kernel_table(wide).has_value());
  Binding negative = *b;  // a weight outside [0, 1] (a hand-made binding): unorm16 cannot hold it
  negative.weights[3] = -0.25f;
  EXPECT_FALSE(make_kernel_table(negative).has_value());
}

TEST(KernelTable, TheAvxAndGenericPathsAgree) {
  const PolyMesh skin = fixtures::cylinder_skin(0.5, 4.0, 37, 41);
  const Cage cage = fixtures::cylinder_cage();
  const auto bent = fixtures::bent(cage.polygons.positions, 2.0, 75.0);
  const double diag = diagonal_of(skin.positions);
  for (Variant v : kTableVariants) {
    BindParams p;
    p.variant = v;
    auto b = bind_skin(skin.positions, cage, cage.polygons.positions, p);
    ASSERT_TRUE(b.ok());
    auto d = Deformer::create(*b, skin.positions);
    ASSERT_TRUE(d.ok());
    ASSERT_NE(d->kernel_table(), nullptr);
    ASSERT_TRUE(d->update_maps(bent).ok());
    std::vector<glm::vec3> best(skin.positions.size()), base(skin.positions.size());
    const glm::vec3 origin(b->origin);
    for (KernelPath path : {KernelPath::kBest, KernelPath::kBaseline}) {
      auto& out = path == KernelPath::kBest ? best : base;
      if (v == Variant::kClamped)
        apply_kernel_rigid(*d->kernel_table(), d->rigid_maps(), skin.positions, origin, out, path);
      else
        apply_kernel_affine(*d->kernel_table(), d->affine_maps(), skin.positions, origin, out, path);
    }
    double worst = 0.0;
    for (size_t i = 0; i < best.size(); ++i) worst = std::max(worst, double(glm::length(best[i] - base[i])) / diag);
    EXPECT_LE(worst, 1e-6) << variant_name(v) << (kernel_uses_avx() ? " (AVX + FMA against generic)" : "");
  }
}

TEST(KernelTable, StencilChangesRebuildTheCompactTable) {
  // a live set edit changes the binding's float table in place; stencil_changed() makes the compact
  // copy again, so the deformed skin follows the edit
  const PolyMesh skin = fixtures::cylinder_skin();
  const Cage cage = fixtures::cylinder_cage();
  auto b = bind_skin(skin.positions, cage, cage.polygons.positions, BindParams{});
  ASSERT_TRUE(b.ok());
  auto d = Deformer::create(*b, skin.positions);
  ASSERT_TRUE(d.ok());
  const auto bent = twisted(cage.polygons.positions, 120.0);  // every cage vertex's map differs
  std::vector<glm::vec3> before(skin.positions.size()), after(skin.positions.size()), exact(skin.positions.size());
  ASSERT_TRUE(d->deform(bent, before).ok());
  // a point halfway along, with several cage vertices, now follows only its strongest one
  uint32_t pt = 0;
  for (uint32_t i = 0; i < b->num_points; ++i)
    if (std::abs(skin.positions[i].x - 2.0f) < std::abs(skin.positions[pt].x - 2.0f) && b->offsets[i + 1] - b->offsets[i] > 2)
      pt = i;
  const uint32_t o = b->offsets[pt], n = b->offsets[pt + 1] - o;
  ASSERT_GT(n, 1u);
  const size_t strongest = std::max_element(b->weights.begin() + o, b->weights.begin() + o + n) - b->weights.begin();
  for (uint32_t k = o; k < o + n; ++k) b->weights[k] = k == strongest ? 1.f : 0.f;
  ASSERT_TRUE(d->stencil_changed().ok());
  ASSERT_NE(d->kernel_table(), nullptr);
  ASSERT_TRUE(d->deform(bent, after).ok());
  auto f = Deformer::create(*b, skin.positions, TableFormat::kFloat);
  ASSERT_TRUE(f.ok());
  ASSERT_TRUE(f->deform(bent, exact).ok());
  EXPECT_GT(glm::length(after[pt] - before[pt]), 1e-4f) << "the edit moved point " << pt;
  EXPECT_LE(fixtures::max_distance(after, exact) / diagonal_of(skin.positions), kFidelity);
}

// A live set edit's update of the compact table (the groups of the changed points only) equals the
// table made from scratch, when the groups keep their member counts and when they do not.
TEST(KernelTable, UpdatingTheChangedGroupsEqualsMakingItAgain) {
  const PolyMesh skin = fixtures::cylinder_skin(0.5, 4.0, 37, 41);
  const Cage cage = fixtures::cylinder_cage();
  for (Variant v : kTableVariants) {
    BindParams p;
    p.variant = v;
    auto b = bind_skin(skin.positions, cage, cage.polygons.positions, p);
    ASSERT_TRUE(b.ok());
    auto t = make_kernel_table(*b);
    ASSERT_TRUE(t.has_value());
    auto expect_same = [&](const KernelTable& x, const std::string& what) {
      auto fresh = make_kernel_table(*b);
      ASSERT_TRUE(fresh.has_value()) << what;
      EXPECT_EQ(x.group_start, fresh->group_start) << what;
      EXPECT_EQ(x.member_id, fresh->member_id) << what;
      EXPECT_EQ(x.weights, fresh->weights) << what;
      EXPECT_EQ(x.weights_lo, fresh->weights_lo) << what;
    };
    // 1. weights moved within point 700's stencil: same members
    const uint32_t a = 700, oa = b->offsets[a], na = b->offsets[a + 1] - oa;
    ASSERT_GT(na, 1u);
    std::swap(b->weights[oa], b->weights[oa + 1]);
    std::vector<uint32_t> pts{a};
    ASSERT_TRUE(update_kernel_table(*t, *b, pts));
    expect_same(*t, std::string(variant_name(v)) + ": weights swapped");
    // 2. points 3 and 1200 now follow one map each that their groups did not use: groups grow
    const uint32_t maps = t->num_maps;
    for (uint32_t i : {3u, 1200u}) {
      const uint32_t o = b->offsets[i], n = b->offsets[i + 1] - o;
      std::vector<uint32_t> used(b->ids.begin() + b->offsets[i / 8 * 8],
                                 b->ids.begin() + b->offsets[std::min<uint32_t>(b->num_points, i / 8 * 8 + 8)]);
      uint32_t fresh_id = 0;
      while (std::find(used.begin(), used.end(), fresh_id) != used.end()) ++fresh_id;
      ASSERT_LT(fresh_id, maps);
      for (uint32_t k = o; k < o + n; ++k) {
        b->ids[k] = k == o ? fresh_id : b->ids[o + 1 < o + n ? o + 1 : o];
        b->weights[k] = k == o ? 1.f : 0.f;
      }
    }
    const size_t before = t->group_start.back();
    pts = {1200, 3, 3};
    ASSERT_TRUE(update_kernel_table(*t, *b, pts));
    EXPECT_GT(t->group_start.back(), before) << "the groups grew";
    expect_same(*t, std::string(variant_name(v)) + ": new members");
  }
}

}  // namespace
}  // namespace cagewrap
