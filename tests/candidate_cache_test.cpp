// CandidateCache (core/deform/registration.h): re-weighting from cached candidates equals a fresh bind
// bit for bit, for slider moves inside the cache's cover (served from the lists alone) and far outside
// it (points fall back to the hierarchy), with set edits, part labels and every variant.
#include <gtest/gtest.h>

#include <atomic>
#include <cstring>

#include "core/deform/registration.h"
#include "core/geometry/mesh_io.h"
#include "core/geometry/subdivide.h"
#include "tests/set_fixtures.h"
#include "tests/test_assets.h"

namespace cagewrap {
namespace {

using fixtures::TwoLegs;

constexpr Variant kVariants[] = {Variant::kBasic, Variant::kClamped, Variant::kExtended};

// Edits of every kind: an exclusion of a point's nearest elements, an inclusion of the other leg's,
// "only" one element, and a point that excludes everything (it follows its nearest element).
std::vector<SetEdit> some_edits(const TwoLegs& t) {
  const uint32_t right = static_cast<uint32_t>(t.left_faces);
  std::vector<SetEdit> edits;
  edits.push_back({0, {0, 1, 2, 3, 4, 5}, {}, false});
  edits.push_back({1, {}, {right + 2}, false});
  edits.push_back({t.left_points + 3, {}, {right + 7}, true});
  SetEdit none{40, {}, {}, false};
  for (uint32_t e = 0; e < t.cage.num_elements(); ++e) none.exclude.push_back(e);
  edits.push_back(none);
  return edits;
}

// Slider positions: inside the cover of a cache made at the defaults, and far beyond it.
std::vector<BindParams> slider_positions(Variant v) {
  std::vector<BindParams> out;
  BindParams base;
  base.variant = v;
  out.push_back(base);
  for (double local : {3.5, 3.0, 4.5, 6.0, 12.0, 2.0, 1.0, 0.5}) out.push_back(base), out.back().local = local;
  for (double eps : {0.07, 0.025, 0.3, 1.0, 0.005}) out.push_back(base), out.back().epsilon = eps;
  for (uint32_t k : {1u, 6u, 12u, 16u, 32u}) out.push_back(base), out.back().max_elements = k;
  for (double md : {0.05, 0.3}) out.push_back(base), out.back().max_distance = md;
  out.push_back(base), out.back().scale = 0.15;
  for (uint32_t steps : {0u, 2u}) out.push_back(base), out.back().separation_steps = steps;
  out.push_back(base), out.back().separate = false;
  return out;
}

TEST(CandidateCache, EqualsAFreshBindAtEverySliderPosition) {
  const TwoLegs t = fixtures::two_legs();
  const auto& skin = t.skin.positions;
  const auto& rest = t.cage.polygons.positions;
  const std::vector<SetEdit> edits = some_edits(t);
  for (const PartLabels* labels : {static_cast<const PartLabels*>(nullptr), &t.labels}) {
    auto cache = CandidateCache::create(skin, t.cage, rest, BindParams{}, labels);
    ASSERT_TRUE(cache.ok()) << cache.error().message;
    EXPECT_GT(cache->entries(), skin.size());
    uint64_t queried_far = 0;
    for (Variant v : kVariants) {
      for (const BindParams& p : slider_positions(v)) {
        for (std::span<const SetEdit> e : {std::span<const SetEdit>{}, std::span<const SetEdit>(edits)}) {
          CandidateCacheStats stats;
          auto cached = cache->bind(p, e, {}, &stats);
          ASSERT_TRUE(cached.ok()) << cached.error().message;
          auto fresh = bind_skin(skin, t.cage, rest, p, e, {}, labels);
          ASSERT_TRUE(fresh.ok()) << fresh.error().message;
          EXPECT_EQ(registration_difference(*cached, *fresh), "")
              << variant_name(v) << " local " << p.local << " epsilon " << p.epsilon << " K " << p.max_elements
              << " max distance " << p.max_distance << " steps " << p.separation_steps << (e.empty() ? "" : ", edits")
              << (labels ? ", labels" : "");
          EXPECT_EQ(stats.cached_points + stats.queried_points, skin.size());
          if (p == BindParams{.variant = v} && e.empty())
            EXPECT_EQ(stats.queried_points, 0u) << "the cache's own parameters are inside its cover";
          if (p.local == 0.5 || p.epsilon == 0.005) queried_far += stats.queried_points;
        }
      }
    }
    EXPECT_GT(queried_far, 0u) << "far slider positions should exceed some points' cover (the fallback is tested)";
  }
}

// A cache made at a low falloff exponent covers its own parameters too (its cover never uses a higher
// local than the one given: a higher one would need a smaller radius).
TEST(CandidateCache, ACacheMadeAtALowLocalCoversItsOwnParameters) {
  const TwoLegs t = fixtures::two_legs();
  const auto& rest = t.cage.polygons.positions;
  for (double local : {0.3, 0.8, 1.0}) {
    BindParams p;
    p.local = local;
    EXPECT_LE(CandidateCache::cover_params(p).local, local);
    auto cache = CandidateCache::create(t.skin.positions, t.cage, rest, p);
    ASSERT_TRUE(cache.ok());
    CandidateCacheStats stats;
    auto cached = cache->bind(p, {}, {}, &stats);
    ASSERT_TRUE(cached.ok());
    EXPECT_EQ(stats.queried_points, 0u) << "local " << local;
    auto fresh = bind_skin(t.skin.positions, t.cage, rest, p);
    ASSERT_TRUE(fresh.ok());
    EXPECT_EQ(registration_difference(*cached, *fresh), "") << "local " << local;
  }
}

// The bench mannequin (28k points): the bench's drags are served from the lists alone, and equal a
// fresh bind.
TEST(CandidateCache, BenchMannequinDragsStayInTheCoverAndEqualFreshBinds) {
  CAGEWRAP_REQUIRE_ASSETS(dir);
  const std::string d = dir + "/bench/mannequiny/";
  auto mesh = load_mesh(d + "mesh_7136.obj");
  auto cage_mesh = load_mesh(d + "cage.obj");
  ASSERT_TRUE(mesh.ok() && cage_mesh.ok());
  auto cage = make_cage(*cage_mesh, "cage.obj");
  ASSERT_TRUE(cage.ok());
  const PolyMesh skin = subdivide_edges_uniform(*mesh, 1);
  const auto& rest = cage->polygons.positions;
  auto cache = CandidateCache::create(skin.positions, *cage, rest, BindParams{});
  ASSERT_TRUE(cache.ok()) << cache.error().message;
  std::printf("  %zu points, %.1f cached elements per point, %.1f MB, made in %.3f s\n", skin.positions.size(),
              double(cache->entries()) / skin.positions.size(), cache->bytes() / 1e6, cache->seconds());
  for (Variant v : kVariants) {
    std::vector<BindParams> drag;
    BindParams base;
    base.variant = v;
    for (double local : {3.5, 3.0, 4.5, 5.0}) drag.push_back(base), drag.back().local = local;
    for (double eps : {0.07, 0.05, 0.15, 0.2}) drag.push_back(base), drag.back().epsilon = eps;
    for (uint32_t k : {6u, 10u, 12u, 16u}) drag.push_back(base), drag.back().max_elements = k;
    for (const BindParams& p : drag) {
      CandidateCacheStats stats;
      auto cached = cache->bind(p, {}, {}, &stats);
      ASSERT_TRUE(cached.ok());
      EXPECT_EQ(stats.queried_points, 0u) << variant_name(v) << " local " << p.local << " epsilon " << p.epsilon
                                          << " K " << p.max_elements;
      auto fresh = bind_skin(skin.positions, *cage, rest, p);
      ASSERT_TRUE(fresh.ok());
      EXPECT_EQ(registration_difference(*cached, *fresh), "")
          << variant_name(v) << " local " << p.local << " epsilon " << p.epsilon << " K " << p.max_elements;
    }
  }
}

TEST(CandidateCache, KnowsWhatItWasMadeForAndReportsBadInput) {
  const TwoLegs t = fixtures::two_legs();
  std::vector<glm::vec3> skin = t.skin.positions, rest = t.cage.polygons.positions;
  auto cache = CandidateCache::create(skin, t.cage, rest, BindParams{}, &t.labels);
  ASSERT_TRUE(cache.ok());
  EXPECT_TRUE(cache->fits(skin, t.cage, rest, &t.labels));
  EXPECT_FALSE(cache->fits(skin, t.cage, rest, nullptr)) << "made with labels";
  PartLabels other = t.labels;
  other.point[5] = 0;
  EXPECT_FALSE(cache->fits(skin, t.cage, rest, &other));
  skin[3].y += 1e-4f;
  EXPECT_FALSE(cache->fits(skin, t.cage, rest, &t.labels)) << "a skin point moved";
  skin[3] = t.skin.positions[3];
  rest[2].x += 1e-4f;
  EXPECT_FALSE(cache->fits(skin, t.cage, rest, &t.labels)) << "a rest cage vertex moved";

  BindParams bad;
  bad.epsilon = 0;
  auto b = cache->bind(bad);
  ASSERT_FALSE(b.ok());
  EXPECT_NE(b.error().message.find("epsilon"), std::string::npos) << b.error().message;
  const SetEdit out_of_range{static_cast<uint32_t>(skin.size()), {0}, {}, false};
  b = cache->bind(BindParams{}, std::span<const SetEdit>(&out_of_range, 1));
  ASSERT_FALSE(b.ok());
  EXPECT_EQ(b.error().code, ErrorCode::kIndexOutOfRange);
  EXPECT_NE(b.error().message.find(std::to_string(skin.size())), std::string::npos) << b.error().message;

  std::atomic<bool> cancel{true};
  BindProgress progress;
  progress.cancel = &cancel;
  auto cancelled = CandidateCache::create(skin, t.cage, rest, BindParams{}, nullptr, progress);
  ASSERT_FALSE(cancelled.ok());
  EXPECT_EQ(cancelled.error().code, ErrorCode::kCancelled);
  auto bad_cache = CandidateCache::create(skin, t.cage, rest, bad);
  ASSERT_FALSE(bad_cache.ok());
}

TEST(RegistrationDifference, NamesTheFirstTableThatDiffers) {
  const TwoLegs t = fixtures::two_legs();
  auto a = bind_skin(t.skin.positions, t.cage, t.cage.polygons.positions, BindParams{});
  ASSERT_TRUE(a.ok());
  Binding b = *a;
  EXPECT_EQ(registration_difference(*a, b), "");
  uint32_t bits;
  std::memcpy(&bits, &b.weights[10], 4);
  bits ^= 1u;  // one bit of one weight
  std::memcpy(&b.weights[10], &bits, 4);
  EXPECT_EQ(registration_difference(*a, b), "weights");
  b = *a;
  b.reach[3] = std::nextafter(b.reach[3], 1e30f);
  EXPECT_EQ(registration_difference(*a, b), "reach");
  b = *a;
  b.quality_inside += 1;
  EXPECT_EQ(registration_difference(*a, b), "quality_inside");
}

}  // namespace
}  // namespace cagewrap
