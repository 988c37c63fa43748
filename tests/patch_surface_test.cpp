// Bicubic patch grids (core/deform/patch_surface.h): basis functions, evaluation, sampling, validation.
#include "core/deform/patch_surface.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <limits>

#include "tests/expect_error.h"
#include "tests/patch_fixtures.h"

namespace cagewrap {
namespace {

double dist(const glm::dvec3& a, const glm::dvec3& b) {
  return glm::length(a - b);
}

TEST(PatchSurface, BasisIsAPartitionOfUnityWithZeroSumDerivatives) {
  for (PatchBasis basis : {PatchBasis::kBSpline, PatchBasis::kBezier})
    for (uint32_t n : {4u, 7u, 10u}) {
      const uint32_t spans = patch_spans(basis, n);
      for (int k = 0; k <= 40; ++k) {
        const double t = spans * k / 40.0;
        const CubicBasis b = cubic_basis(basis, n, t);
        ASSERT_LE(b.first + 4, n) << "n " << n << " t " << t;
        double sum = 0, dsum = 0;
        for (int i = 0; i < 4; ++i) {
          EXPECT_GE(b.value[i], -1e-15);
          sum += b.value[i];
          dsum += b.deriv[i];
        }
        EXPECT_NEAR(sum, 1.0, 1e-14) << patch_basis_name(basis) << " n " << n << " t " << t;
        EXPECT_NEAR(dsum, 0.0, 1e-12) << patch_basis_name(basis) << " n " << n << " t " << t;
      }
    }
}

TEST(PatchSurface, TangentsMatchFiniteDifferences) {
  for (PatchBasis basis : {PatchBasis::kBSpline, PatchBasis::kBezier}) {
    const PatchGrid g = test::wavy_grid(7, basis == PatchBasis::kBezier ? 10 : 8, basis);
    const double su = patch_spans(basis, g.cols), sv = patch_spans(basis, g.rows);
    const double step = 1e-6;
    double worst = 0;
    // inside spans and next to knots from the inside (Bezier joins are only C0: one span's
    // polynomial must hold on both sides of the difference)
    for (double u : {0.3, 0.5 * su + 0.25, su - 0.4, 1.0 + 1e-4, su - 1e-4})
      for (double v : {0.2, 0.5 * sv + 0.25, sv - 0.3, 2.0 - 1e-4}) {
        const PatchPoint p = evaluate(g, u, v);
        const glm::dvec3 fu =
            (evaluate(g, u + step, v).position - evaluate(g, u - step, v).position) / (2 * step);
        const glm::dvec3 fv =
            (evaluate(g, u, v + step).position - evaluate(g, u, v - step).position) / (2 * step);
        worst = std::max({worst, dist(p.du, fu), dist(p.dv, fv)});
        EXPECT_GT(glm::length(p.du), 0.1);
      }
    EXPECT_LT(worst, 1e-6) << patch_basis_name(basis);
  }
}

TEST(PatchSurface, ClampedGridInterpolatesItsCorners) {
  for (PatchBasis basis : {PatchBasis::kBSpline, PatchBasis::kBezier}) {
    const PatchGrid g = test::wavy_grid(7, 10, basis);
    const double su = patch_spans(basis, g.cols), sv = patch_spans(basis, g.rows);
    EXPECT_LT(dist(evaluate(g, 0, 0).position, g.at(0, 0)), 1e-14);
    EXPECT_LT(dist(evaluate(g, su, 0).position, g.at(0, g.cols - 1)), 1e-14);
    EXPECT_LT(dist(evaluate(g, 0, sv).position, g.at(g.rows - 1, 0)), 1e-14);
    EXPECT_LT(dist(evaluate(g, su, sv).position, g.at(g.rows - 1, g.cols - 1)), 1e-14);
  }
}

// Linear precision: control points at the Greville abscissae of a plane O + u a + v b reproduce it.
TEST(PatchSurface, ReproducesAPlaneFromGrevilleControlPoints) {
  const uint32_t rows = 6, cols = 8;
  auto greville = [](uint32_t n, uint32_t i) {
    auto knot = [&](int64_t k) { return double(std::clamp<int64_t>(k - 3, 0, int64_t(n) - 3)); };
    return (knot(i + 1) + knot(i + 2) + knot(i + 3)) / 3.0;
  };
  const glm::dvec3 o(1, 2, 3), a(0.5, 0.1, -0.2), b(-0.1, 0.3, 0.7);
  PatchGrid g;
  g.rows = rows;
  g.cols = cols;
  for (uint32_t r = 0; r < rows; ++r)
    for (uint32_t c = 0; c < cols; ++c) g.points.push_back(o + greville(cols, c) * a + greville(rows, r) * b);
  for (double u = 0; u <= cols - 3; u += 0.37)
    for (double v = 0; v <= rows - 3; v += 0.41) {
      const PatchPoint p = evaluate(g, u, v);
      EXPECT_LT(dist(p.position, o + u * a + v * b), 1e-13) << u << " " << v;
      EXPECT_LT(dist(p.du, a), 1e-13);
      EXPECT_LT(dist(p.dv, b), 1e-13);
    }
}

TEST(PatchSurface, DensityCutsEverySpanIntoEqualSteps) {
  PatchSurface s{{test::wavy_grid(7, 5), test::wavy_grid(7, 4, PatchBasis::kBezier)}};
  // grid 0: B-spline, 5 columns -> 2 spans along u, 7 rows -> 4 spans along v
  // grid 1: Bezier, 4 columns -> 1 span, 7 rows -> 2 spans
  for (uint32_t d : {1u, 2u, 5u}) {
    auto samples = sample_patch_surface(s, d);
    ASSERT_TRUE(samples.ok());
    EXPECT_EQ(samples->size(), size_t((2 * d + 1) * (4 * d + 1) + (1 * d + 1) * (2 * d + 1))) << d;
  }
  // density 1: the samples sit at the knot values, on the surface
  auto samples = sample_patch_surface(s, 1);
  ASSERT_TRUE(samples.ok());
  size_t k = 0;
  for (uint32_t gi = 0; gi < 2; ++gi) {
    const PatchGrid& g = s.grids[gi];
    for (uint32_t v = 0; v <= patch_spans(g.basis, g.rows); ++v)
      for (uint32_t u = 0; u <= patch_spans(g.basis, g.cols); ++u, ++k) {
        const PatchSample& sm = (*samples)[k];
        EXPECT_EQ(sm.grid, gi);
        EXPECT_EQ(sm.u, double(u));
        EXPECT_EQ(sm.v, double(v));
        const SampleFrame f = sample_frame(s, sm);
        const PatchPoint p = evaluate(g, u, v);
        EXPECT_LT(dist(f.position, p.position), 1e-14);
        EXPECT_LT(dist(f.du, p.du), 1e-13);
        EXPECT_LT(dist(f.dv, p.dv), 1e-13);
      }
  }
}

TEST(PatchSurface, ControlNetEdgesJoinRowAndColumnNeighboursGridByGrid) {
  PatchSurface s{{test::wavy_grid(4, 5), test::wavy_grid(4, 4)}};
  const auto edges = control_net_edges(s);
  // grid 0: 4 rows of 4 edges + 3 x 5 column edges; grid 1: 4 x 3 + 3 x 4
  ASSERT_EQ(edges.size(), size_t(16 + 15 + 12 + 12));
  const auto points = s.control_points();
  for (const auto& [a, b] : edges) EXPECT_NEAR(glm::length(glm::dvec2(points[a].x - points[b].x, points[a].z - points[b].z)), 1.0, 1e-12);
  EXPECT_EQ(edges[16 + 15][0], 20u);  // the second grid's first edge starts at its first point
}

TEST(PatchSurface, BadGridsAndDensitiesAreRefusedByName) {
  PatchSurface small{{test::wavy_grid(3, 5)}};
  EXPECT_TRUE(Fails(validate_patch_surface(small, "a.cwpatch"), ErrorCode::kInvalidArgument,
                    {"a.cwpatch", "grid 0", "3 x 5", "at least 4 x 4"}));
  PatchSurface bezier{{test::wavy_grid(5, 4, PatchBasis::kBezier)}};
  EXPECT_TRUE(Fails(validate_patch_surface(bezier, "b.cwpatch"), ErrorCode::kInvalidArgument,
                    {"b.cwpatch", "3 m + 1"}));
  PatchSurface nan{{test::wavy_grid(), test::wavy_grid()}};
  nan.grids[1].points[2 * 8 + 5].y = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(Fails(validate_patch_surface(nan, "c.cwpatch"), ErrorCode::kNonFinite,
                    {"c.cwpatch", "grid 1", "row 2 column 5"}));
  PatchSurface ragged{{test::wavy_grid()}};
  ragged.grids[0].points.pop_back();
  EXPECT_TRUE(
      Fails(validate_patch_surface(ragged, "d"), ErrorCode::kTopologyMismatch, {"7 x 8", "holds 55"}));
  EXPECT_TRUE(Fails(validate_patch_surface(PatchSurface{}, "e"), ErrorCode::kEmpty, {"no grid"}));
  EXPECT_TRUE(Fails(sample_patch_surface(test::wavy_surface(), 0), ErrorCode::kInvalidArgument,
                    {"density", "got 0"}));
  EXPECT_TRUE(Fails(sample_patch_surface(nan, 2), ErrorCode::kNonFinite, {"row 2 column 5"}));
  // a 7 x 8 B-spline grid has 4 x 5 spans: density 1024 would be 4,097 x 5,121 samples (8.6 GB); refused
  // before anything is allocated
  EXPECT_TRUE(Fails(sample_patch_surface(test::wavy_surface(), 1024), ErrorCode::kInvalidArgument,
                    {"density 1024", "20,980,737 samples", "more than 150,000"}));
  EXPECT_TRUE(sample_patch_surface(test::wavy_surface(), 64).ok());  // 257 x 321 = 82,497
}

}  // namespace
}  // namespace cagewrap
