// Tests for core/geometry/interpolation.h: piecewise-linear weights, the Fritsch-Carlson monotone cubic
// (exact at keys, monotone between monotone keys, flat at extrema, clamped outside, C1), and RBF
// interpolation (every key reproduced exactly by every kernel, also in degenerate layouts).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/geometry/interpolation.h"

namespace cagewrap {
namespace {

TEST(LinearWeights, ExactAtKeysHalfWayBetweenClampedOutside) {
  const std::vector<double> xs = {-30, 0, 60, 120};
  std::vector<double> w(4);
  for (size_t k = 0; k < xs.size(); ++k) {
    linear_weights(xs, xs[k], w);
    for (size_t i = 0; i < 4; ++i) EXPECT_EQ(w[i], i == k ? 1.0 : 0.0) << k << " " << i;
  }
  linear_weights(xs, 30, w);
  EXPECT_EQ(w, (std::vector<double>{0, 0.5, 0.5, 0}));
  linear_weights(xs, 75, w);
  EXPECT_DOUBLE_EQ(w[2], 0.75);
  EXPECT_DOUBLE_EQ(w[3], 0.25);
  linear_weights(xs, -1000, w);
  EXPECT_EQ(w, (std::vector<double>{1, 0, 0, 0}));
  linear_weights(xs, 1000, w);
  EXPECT_EQ(w, (std::vector<double>{0, 0, 0, 1}));
  std::vector<double> one(1);
  linear_weights(std::vector<double>{5}, -3, one);
  EXPECT_EQ(one[0], 1.0);
}

TEST(MonotoneCubic, ExactAtKeysAndClampedOutside) {
  const std::vector<double> xs = {0, 10, 30, 35, 90};
  const std::vector<double> ys = {0, 2, 2.5, 7, -1};
  for (size_t k = 0; k < xs.size(); ++k) EXPECT_DOUBLE_EQ(monotone_cubic(xs, ys, xs[k]), ys[k]);
  EXPECT_EQ(monotone_cubic(xs, ys, -5), 0.0);
  EXPECT_EQ(monotone_cubic(xs, ys, 500), -1.0);
}

TEST(MonotoneCubic, StaysMonotoneBetweenMonotoneKeys) {
  // data that makes an ordinary cubic spline overshoot: a steep step between flat stretches
  const std::vector<double> xs = {0, 1, 2, 3, 4, 5, 6};
  const std::vector<double> ys = {0, 0.01, 0.02, 5, 5.01, 5.02, 9};
  double prev = monotone_cubic(xs, ys, -1);
  for (double x = 0; x <= 6.0; x += 0.001) {
    double y = monotone_cubic(xs, ys, x);
    EXPECT_GE(y, prev - 1e-12) << "at x = " << x;
    prev = y;
  }
  // non-increasing data gives a non-increasing curve
  const std::vector<double> down = {3, 1, 0.9, 0.9, -4, -4.5, -20};
  prev = monotone_cubic(xs, down, 0);
  for (double x = 0; x <= 6.0; x += 0.001) {
    double y = monotone_cubic(xs, down, x);
    EXPECT_LE(y, prev + 1e-12) << "at x = " << x;
    prev = y;
  }
}

TEST(MonotoneCubic, FlatAtExtremaAndEndsNoOvershoot) {
  const std::vector<double> xs = {0, 60, 120};
  const std::vector<double> ys = {0, 1, 0};  // an extremum at 60: the curve never exceeds 1
  for (double x = 0; x <= 120; x += 0.1) {
    double y = monotone_cubic(xs, ys, x);
    EXPECT_LE(y, 1.0 + 1e-12);
    EXPECT_GE(y, -1e-12);
  }
  std::vector<double> m(3);
  monotone_slopes(xs, ys, m);
  EXPECT_EQ(m, (std::vector<double>{0, 0, 0}));
}

TEST(MonotoneCubic, TwoKeysEaseInAndOutAndTheCurveIsC1) {
  const std::vector<double> xs = {0, 120};
  const std::vector<double> ys = {0, 1};
  EXPECT_DOUBLE_EQ(monotone_cubic(xs, ys, 60), 0.5);
  EXPECT_NEAR(monotone_cubic(xs, ys, 30), 0.15625, 1e-12);  // smoothstep(1/4)
  // the derivative is continuous everywhere, including where the curve meets the clamped ends
  const std::vector<double> xs4 = {0, 10, 30, 35, 90};
  const std::vector<double> ys4 = {0, 2, 2.5, 7, -1};
  auto slope = [&](double x, double h) {
    return (monotone_cubic(xs4, ys4, x + h) - monotone_cubic(xs4, ys4, x)) / h;
  };
  for (double x : {0.0, 10.0, 30.0, 35.0, 90.0}) {
    double left = slope(x - 1e-6, 1e-7), right = slope(x + 1e-7, 1e-7);
    EXPECT_NEAR(left, right, 1e-3) << "at key " << x;
  }
}

TEST(Rbf, EveryKernelReproducesEveryKey) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-120, 120);
  for (RbfKernel kernel : {RbfKernel::kGaussian, RbfKernel::kThinPlate, RbfKernel::kLinear}) {
    for (size_t dims : {1u, 2u, 3u}) {
      std::vector<double> centres(dims, 0.0);  // the rest point
      for (int k = 0; k < 6; ++k)
        for (size_t d = 0; d < dims; ++d) centres.push_back(u(rng));
      auto rbf = RbfInterpolator::create(centres, dims, kernel);
      ASSERT_TRUE(rbf.ok()) << rbf.error().message;
      const size_t n = rbf->num_centres();
      ASSERT_EQ(n, 7u);
      std::vector<double> w(n);
      for (size_t i = 0; i < n; ++i) {
        rbf->weights(std::span<const double>(&centres[i * dims], dims), w);
        for (size_t j = 0; j < n; ++j)
          EXPECT_NEAR(w[j], i == j ? 1.0 : 0.0, 1e-8)
              << rbf_kernel_name(kernel) << " dims " << dims << " key " << i;
      }
    }
  }
}

TEST(Rbf, DegenerateLayoutsStillInterpolate) {
  // thin plate with every centre on one line in 2-D (the affine term is then not determined), and
  // centres a unit apart (phi(1) = 0)
  for (const std::vector<double>& centres :
       {std::vector<double>{0, 0, 30, 0, 90, 0}, std::vector<double>{0, 0, 1, 0},
        std::vector<double>{0, 0, 1, 0, 0, 1}}) {
    for (RbfKernel kernel : {RbfKernel::kGaussian, RbfKernel::kThinPlate, RbfKernel::kLinear}) {
      auto rbf = RbfInterpolator::create(centres, 2, kernel);
      ASSERT_TRUE(rbf.ok());
      std::vector<double> w(rbf->num_centres());
      for (size_t i = 0; i < rbf->num_centres(); ++i) {
        rbf->weights(std::span<const double>(&centres[2 * i], 2), w);
        for (size_t j = 0; j < w.size(); ++j)
          EXPECT_NEAR(w[j], i == j ? 1.0 : 0.0, 1e-8) << rbf_kernel_name(kernel);
      }
    }
  }
}

TEST(Rbf, GaussianWidthAndDecay) {
  const std::vector<double> centres = {0, 0, 100, 0, 0, 60};
  auto rbf = RbfInterpolator::create(centres, 2, RbfKernel::kGaussian);
  ASSERT_TRUE(rbf.ok());
  EXPECT_NEAR(rbf->width(), (60.0 + 100.0 + 60.0) / 3.0, 1e-12);  // mean nearest-neighbour distance
  auto wide = RbfInterpolator::create(centres, 2, RbfKernel::kGaussian, 250.0);
  EXPECT_EQ(wide->width(), 250.0);
  // far from every key the weights vanish (the shape goes back to rest)
  std::vector<double> w(3);
  rbf->weights(std::vector<double>{5000, 5000}, w);
  for (double x : w) EXPECT_NEAR(x, 0.0, 1e-12);
  EXPECT_FALSE(RbfInterpolator::create(std::vector<double>{0, NAN}, 2, RbfKernel::kGaussian).ok());
  EXPECT_FALSE(RbfInterpolator::create({}, 0, RbfKernel::kGaussian).ok());
}

TEST(Rbf, KernelNames) {
  for (RbfKernel k : {RbfKernel::kGaussian, RbfKernel::kThinPlate, RbfKernel::kLinear}) {
    RbfKernel back;
    ASSERT_TRUE(parse_rbf_kernel(rbf_kernel_name(k), back));
    EXPECT_EQ(back, k);
  }
  RbfKernel x;
  EXPECT_FALSE(parse_rbf_kernel("cubic", x));
}

}  // namespace
}  // namespace cagewrap
