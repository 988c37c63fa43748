// Binding a skin to a parametric driver and deforming it (core/deform/patch_binding.h): the properties of
// algorithm.md section 4.1 for sample elements, locality and smoothness of a control point's pull,
// and the sample count set by the density.
#include "core/deform/patch_binding.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "core/io/binding_io.h"
#include "tests/expect_error.h"
#include "tests/patch_fixtures.h"

namespace cagewrap {
namespace {

double diagonal(std::span<const glm::vec3> pts) {
  return bounding_box(pts).diagonal();
}

double max_distance(std::span<const glm::vec3> a, std::span<const glm::vec3> b) {
  double worst = 0;
  for (size_t i = 0; i < a.size(); ++i) worst = std::max(worst, double(glm::length(a[i] - b[i])));
  return worst;
}

struct Bound {
  PatchSurface rest;
  std::vector<glm::vec3> skin;
  Binding binding;
  std::unique_ptr<PatchDeformer> deformer;

  explicit Bound(uint32_t density, BindParams params = {}, uint32_t rows = 7, uint32_t cols = 8)
      : rest(test::wavy_surface(rows, cols)), skin(test::slab_skin(3000, rows, cols)) {
    auto b = bind_skin_to_patches(skin, rest, density, params);
    EXPECT_TRUE(b.ok()) << b.error().message;
    binding = std::move(*b);
    auto d = PatchDeformer::create(binding, skin, rest, density);
    EXPECT_TRUE(d.ok()) << d.error().message;
    deformer = std::make_unique<PatchDeformer>(std::move(*d));
  }
  std::vector<glm::vec3> deform(const PatchSurface& posed) {
    std::vector<glm::vec3> out(skin.size());
    auto s = deformer->deform(posed, out);
    EXPECT_TRUE(s.ok()) << s.error().message;
    return out;
  }
};

TEST(PatchBinding, TheTableIsOverSamplesWithNormalizedWeights) {
  for (uint32_t density : {1u, 3u}) {
    Bound b(density);
    const Binding& t = b.binding;
    EXPECT_EQ(t.num_samples, (5 * density + 1) * (4 * density + 1));  // 8 x 7 control points: 5 x 4 spans
    EXPECT_EQ(t.params.variant, Variant::kBasic);
    EXPECT_TRUE(t.elements.empty());
    EXPECT_TRUE(validate_binding(t).ok());
    for (uint32_t i = 0; i < t.num_points; ++i) {
      ASSERT_GT(t.offsets[i + 1], t.offsets[i]) << "point " << i;
      ASSERT_LE(t.offsets[i + 1] - t.offsets[i], kMaxTiedMembers);  // K, more only near ties
      double sum = 0;
      for (uint32_t e = t.offsets[i]; e < t.offsets[i + 1]; ++e) sum += t.weights[e];
      ASSERT_NEAR(sum, 1.0, 1e-6) << "point " << i;
    }
  }
}

// The weights are eq. 1 with the taper over the samples within the threshold radius, at most K (more
// only in the tie band):
// the same rule as polygon elements, checked against a loop over every sample.
TEST(PatchBinding, WeightsFollowEquationOneOverAllSamples) {
  BindParams params;
  params.max_elements = 6;
  Bound b(2, params);
  auto samples = sample_patch_surface(b.rest, 2);
  ASSERT_TRUE(samples.ok());
  const std::vector<glm::vec3> at = sample_positions(b.rest, *samples);
  for (uint32_t i = 0; i < b.binding.num_points; i += 97) {
    std::vector<std::pair<double, uint32_t>> all;
    for (uint32_t k = 0; k < at.size(); ++k)
      all.push_back({glm::length(glm::dvec3(b.skin[i]) - glm::dvec3(at[k])) / b.binding.h, k});
    std::sort(all.begin(), all.end());
    const double radius = threshold_radius(all[0].first, params.local, params.epsilon);
    std::vector<std::pair<double, uint32_t>> in;
    for (const auto& c : all)
      if (c.first <= radius) in.push_back(c);
    // the cut, written out from its definition (registration.h Taper): the relative threshold, the
    // (K+1)-th unless it is in the tie band, held at the band's edge there
    const double f1 = falloff(in[0].first, params.local);
    const double l = params.local;
    const double tie = std::pow((1 + kTieBand) * std::pow(in[0].first, l) + kTieBand * std::pow(kTieFloor, l), 1 / l);
    double cut = params.epsilon * f1;
    if (in.size() > 6) cut = std::max(cut, std::min(falloff(in[6].first, l), falloff(tie, l)));
    std::erase_if(in, [&](const auto& c) { return !(falloff(c.first, params.local) > cut); });
    size_t e = b.binding.offsets[i];
    double total = 0;
    for (const auto& c : in) total += std::max(falloff(c.first, params.local) - cut, 0.0);
    for (const auto& c : in) {
      const double w = std::max(falloff(c.first, params.local) - cut, 0.0) / total;
      if (w <= 0) continue;
      ASSERT_LT(e, b.binding.offsets[i + 1]) << "point " << i;
      EXPECT_EQ(b.binding.ids[e], c.second) << "point " << i;
      EXPECT_NEAR(b.binding.weights[e], w, 1e-5) << "point " << i;
      ++e;
    }
    EXPECT_EQ(e, b.binding.offsets[i + 1]) << "point " << i;
  }
}

TEST(PatchBinding, RestDriverReproducesTheSkin) {
  for (uint32_t density : {1u, 2u, 4u}) {
    Bound b(density);
    const auto out = b.deform(b.rest);
    EXPECT_LT(max_distance(out, b.skin), 1e-6 * diagonal(b.skin)) << "density " << density;
  }
}

TEST(PatchBinding, RigidMotionOfTheControlPointsMovesTheSkinRigidly) {
  Bound b(2);
  const glm::dmat4 m = glm::translate(glm::dmat4(1.0), glm::dvec3(3.0, -1.5, 2.0)) *
                       glm::rotate(glm::dmat4(1.0), 1.1, glm::normalize(glm::dvec3(0.3, 1.0, -0.4)));
  PatchSurface posed = b.rest;
  for (glm::dvec3& p : posed.grids[0].points) p = glm::dvec3(m * glm::dvec4(p, 1.0));
  const auto out = b.deform(posed);
  std::vector<glm::vec3> expected(b.skin.size());
  for (size_t i = 0; i < b.skin.size(); ++i)
    expected[i] = glm::vec3(m * glm::dvec4(glm::dvec3(b.skin[i]), 1.0));
  // float maps and positions: a few float ulps of the coordinates
  EXPECT_LT(max_distance(out, expected), 2e-6 * diagonal(b.skin));
}

// One control point moved: skin far from its support does not move at all, skin near it moves, and
// the displacement along a line through the region changes without jumps (the largest step between
// neighbouring points shrinks in proportion when the points get closer).
TEST(PatchBinding, OneControlPointMovesNearbySkinSmoothly) {
  Bound b(2, {}, 10, 12);
  PatchSurface posed = b.rest;
  const uint32_t r0 = 3, c0 = 3;
  const glm::dvec3 move(0.0, 0.8, 0.0);
  posed.grids[0].points[r0 * 12 + c0] += move;
  const auto out = b.deform(posed);
  const auto at_rest = b.deform(b.rest);
  // The control point (3, 3) shapes the spans u, v in [0, 4] (clamped knots 0, 0, 0, 0, 1, ...); the
  // sheet's control points sit near their Greville abscissae, x = u + 1 inside, so it shapes
  // x, z < 5. The samples it moves are then farther than the threshold radius (1.73 h, h about 1)
  // from skin beyond x or z = 8.
  size_t far = 0, moved = 0;
  for (size_t i = 0; i < b.skin.size(); ++i) {
    const double d = glm::length(out[i] - b.skin[i]);
    if (b.skin[i].x > 8.0 || b.skin[i].z > 8.0) {
      ++far;
      // its samples' maps are bit for bit those of the rest driver (the moved point's basis is 0 there)
      EXPECT_EQ(out[i], at_rest[i]) << "skin point " << i << " at " << b.skin[i].x << ", " << b.skin[i].z;
    }
    if (glm::length(glm::dvec2(b.skin[i].x - 3.0, b.skin[i].z - 3.0)) < 0.5 && d > 0.2) ++moved;
  }
  EXPECT_GT(far, 10u);
  EXPECT_GT(moved, 10u);

  auto largest_step = [&](int n) {
    std::vector<glm::vec3> line(n);
    for (int k = 0; k < n; ++k) line[k] = {0.6f + 5.0f * k / (n - 1), 0.3f, 2.7f};
    auto bb = bind_skin_to_patches(line, b.rest, 2, {});
    EXPECT_TRUE(bb.ok());
    auto dd = PatchDeformer::create(*bb, line, b.rest, 2);
    EXPECT_TRUE(dd.ok());
    std::vector<glm::vec3> o(line.size());
    EXPECT_TRUE(dd->deform(posed, o).ok());
    double step = 0, biggest = 0;
    for (int k = 0; k < n; ++k) {
      biggest = std::max(biggest, double(glm::length(o[k] - line[k])));
      if (k) step = std::max(step, double(glm::length((o[k] - line[k]) - (o[k - 1] - line[k - 1]))));
    }
    EXPECT_GT(biggest, 0.2);
    return step;
  };
  const double coarse = largest_step(1001), fine = largest_step(2001);
  EXPECT_LT(coarse, 0.02 * glm::length(move));  // 5 mm spacing: no step beyond 2 % of the pull
  EXPECT_LT(fine, 0.6 * coarse) << "coarse " << coarse << " fine "
                                << fine;  // continuous: halves with the spacing
}

TEST(PatchBinding, DegenerateSamplesAreReportedAndSkipped) {
  // collapse the first row of control points into one point: the samples on that edge have S_u = 0
  Bound b(1);
  PatchSurface pole = b.rest;
  for (uint32_t c = 0; c < 8; ++c) pole.grids[0].points[c] = glm::dvec3(3.5, 0.0, -0.5);
  auto bound = bind_skin_to_patches(b.skin, pole, 1, {});
  ASSERT_TRUE(bound.ok()) << bound.error().message;
  EXPECT_EQ(bound->invalid_elements.size(), 6u);  // the 6 samples of row v = 0
  for (uint32_t k : bound->invalid_elements) EXPECT_LT(k, 6u);
  for (uint32_t id : bound->ids) EXPECT_GE(id, 6u);
  auto d = PatchDeformer::create(*bound, b.skin, pole, 1);
  ASSERT_TRUE(d.ok());
  std::vector<glm::vec3> out(b.skin.size());
  ASSERT_TRUE(d->deform(pole, out).ok());
  EXPECT_LT(max_distance(out, b.skin), 1e-6 * diagonal(b.skin));
}

// Set edits on a driver (their element ids are samples), as on a cage: an excluded sample leaves the
// point's set (the next nearest takes its place), an included one joins it with its own weight, `only`
// keeps the included alone; the other points keep their sets; a sample or point out of range is named.
TEST(PatchBinding, SetEditsExcludeIncludeAndOnlyActOnSamples) {
  Bound plain(2);
  const Binding& t = plain.binding;
  const auto set_of = [](const Binding& b, uint32_t i) {
    return std::vector<uint32_t>(b.ids.begin() + b.offsets[i], b.ids.begin() + b.offsets[i + 1]);
  };
  const uint32_t point = 1234;
  const std::vector<uint32_t> before = set_of(t, point);
  ASSERT_GE(before.size(), 2u);
  // the point's strongest sample excluded; a far one (not in the set) included
  uint32_t strongest = before[0];
  float best = -1.0f;
  for (uint32_t e = t.offsets[point]; e < t.offsets[point + 1]; ++e)
    if (t.weights[e] > best) best = t.weights[e], strongest = t.ids[e];
  uint32_t far = 0;
  while (std::find(before.begin(), before.end(), far) != before.end()) ++far;
  SetEdit edit;
  edit.point = point;
  edit.exclude = {strongest};
  edit.include = {far};
  const std::vector<SetEdit> edits{edit};
  auto b = bind_skin_to_patches(plain.skin, plain.rest, 2, {}, {}, edits);
  ASSERT_TRUE(b.ok()) << b.error().message;
  const std::vector<uint32_t> after = set_of(*b, point);
  EXPECT_EQ(std::count(after.begin(), after.end(), strongest), 0) << "excluded";
  EXPECT_EQ(std::count(after.begin(), after.end(), far), 1) << "included";
  EXPECT_GE(after.size(), 2u) << "the next nearest took the excluded one's place";
  double sum = 0;
  for (uint32_t e = b->offsets[point]; e < b->offsets[point + 1]; ++e) sum += b->weights[e];
  EXPECT_NEAR(sum, 1.0, 1e-6);
  for (uint32_t i : {0u, 1233u, 1235u, 2999u}) EXPECT_EQ(set_of(*b, i), set_of(t, i)) << "point " << i << " keeps its set";
  // only: the included alone
  edit.only = true;
  edit.exclude.clear();
  edit.include = {far, strongest};
  auto only = bind_skin_to_patches(plain.skin, plain.rest, 2, {}, {}, std::vector<SetEdit>{edit});
  ASSERT_TRUE(only.ok()) << only.error().message;
  std::vector<uint32_t> kept = set_of(*only, point);
  std::sort(kept.begin(), kept.end());
  EXPECT_EQ(kept, (std::vector<uint32_t>{std::min(far, strongest), std::max(far, strongest)}));
  // out of range: named
  edit.include = {t.num_samples};
  auto bad = bind_skin_to_patches(plain.skin, plain.rest, 2, {}, {}, std::vector<SetEdit>{edit});
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("names sample " + std::to_string(t.num_samples)), std::string::npos) << bad.error().message;
  edit.point = 3000;
  edit.include = {0};
  bad = bind_skin_to_patches(plain.skin, plain.rest, 2, {}, {}, std::vector<SetEdit>{edit});
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("skin point 3000"), std::string::npos) << bad.error().message;
}

TEST(PatchBinding, BadInputsAreRefused) {
  const PatchSurface rest = test::wavy_surface();
  const auto skin = test::slab_skin(50);
  EXPECT_TRUE(Fails(bind_skin_to_patches(skin, rest, 0, {}), ErrorCode::kInvalidArgument, {"density"}));
  std::vector<glm::vec3> bad = skin;
  bad[7].y = std::nanf("");
  EXPECT_TRUE(Fails(bind_skin_to_patches(bad, rest, 1, {}), ErrorCode::kNonFinite, {"skin vertex 7"}));
  auto b = bind_skin_to_patches(skin, rest, 2, {});
  ASSERT_TRUE(b.ok());
  EXPECT_TRUE(Fails(PatchDeformer::create(*b, skin, rest, 3), ErrorCode::kTopologyMismatch, {"density 3"}));
  auto d = PatchDeformer::create(*b, skin, rest, 2);
  ASSERT_TRUE(d.ok());
  std::vector<glm::vec3> out(skin.size());
  PatchSurface other = test::wavy_surface(7, 9);
  EXPECT_TRUE(Fails(d->deform(other, out), ErrorCode::kTopologyMismatch, {"grids"}));
  PatchSurface nan = rest;
  nan.grids[0].points[9].x = std::nan("");
  EXPECT_TRUE(Fails(d->deform(nan, out), ErrorCode::kNonFinite, {"row 1 column 1"}));
  // the cage paths refuse a sample binding instead of reading past its tables
  EXPECT_TRUE(
      Fails(save_binding("/tmp/never-written.cwb", *b), ErrorCode::kInvalidArgument, {"parametric driver"}));
  auto cage_deformer = Deformer::create(*b, skin);
  ASSERT_TRUE(cage_deformer.ok());
  std::vector<glm::vec3> cage(4, glm::vec3(0.f));
  EXPECT_TRUE(Fails(cage_deformer->deform(cage, out), ErrorCode::kInvalidArgument, {"parametric driver"}));
}

}  // namespace
}  // namespace cagewrap
