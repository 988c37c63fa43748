#include "core/geometry/interpolation.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "core/base/check.h"

namespace cagewrap {

void linear_weights(std::span<const double> xs, double x, std::span<double> out) {
  CAGEWRAP_CHECK(out.size() == xs.size() && !xs.empty(), "one weight per key, at least one key");
  std::fill(out.begin(), out.end(), 0.0);
  const size_t n = xs.size();
  if (x <= xs.front() || n == 1) {
    out[0] = 1.0;
    return;
  }
  if (x >= xs.back()) {
    out[n - 1] = 1.0;
    return;
  }
  size_t i = static_cast<size_t>(std::upper_bound(xs.begin(), xs.end(), x) - xs.begin()) -
             1;  // xs[i] <= x < xs[i+1]
  double t = (x - xs[i]) / (xs[i + 1] - xs[i]);
  out[i] = 1.0 - t;
  out[i + 1] = t;
}

void monotone_slopes(std::span<const double> xs, std::span<const double> ys, std::span<double> m) {
  const size_t n = xs.size();
  CAGEWRAP_CHECK(ys.size() == n && m.size() == n, "one value and one slope per key");
  std::fill(m.begin(), m.end(), 0.0);
  if (n < 2) return;
  // secants; interior slopes: their mean where they agree in sign, 0 at a local extremum
  for (size_t k = 1; k + 1 < n; ++k) {
    double a = (ys[k] - ys[k - 1]) / (xs[k] - xs[k - 1]);
    double b = (ys[k + 1] - ys[k]) / (xs[k + 1] - xs[k]);
    m[k] = (a > 0 && b > 0) || (a < 0 && b < 0) ? 0.5 * (a + b) : 0.0;
  }
  // end slopes stay 0 (see the header); Fritsch-Carlson: limit (alpha, beta) to the circle of radius 3
  for (size_t k = 0; k + 1 < n; ++k) {
    double delta = (ys[k + 1] - ys[k]) / (xs[k + 1] - xs[k]);
    if (delta == 0.0) {
      m[k] = m[k + 1] = 0.0;
      continue;
    }
    double alpha = m[k] / delta, beta = m[k + 1] / delta;
    double s = alpha * alpha + beta * beta;
    if (s > 9.0) {
      double tau = 3.0 / std::sqrt(s);
      m[k] = tau * alpha * delta;
      m[k + 1] = tau * beta * delta;
    }
  }
}

double hermite_at(std::span<const double> xs, std::span<const double> ys, std::span<const double> m,
                  double x) {
  const size_t n = xs.size();
  CAGEWRAP_CHECK(n > 0 && ys.size() == n && m.size() == n,
                 "one value and one slope per key, at least one key");
  if (x <= xs.front() || n == 1) return ys.front();
  if (x >= xs.back()) return ys.back();
  size_t i = static_cast<size_t>(std::upper_bound(xs.begin(), xs.end(), x) - xs.begin()) - 1;
  double h = xs[i + 1] - xs[i];
  double t = (x - xs[i]) / h, t2 = t * t, t3 = t2 * t;
  double h00 = 2 * t3 - 3 * t2 + 1, h10 = t3 - 2 * t2 + t, h01 = -2 * t3 + 3 * t2, h11 = t3 - t2;
  return h00 * ys[i] + h10 * h * m[i] + h01 * ys[i + 1] + h11 * h * m[i + 1];
}

double monotone_cubic(std::span<const double> xs, std::span<const double> ys, double x) {
  std::vector<double> m(xs.size());
  monotone_slopes(xs, ys, m);
  return hermite_at(xs, ys, m, x);
}

const char* rbf_kernel_name(RbfKernel k) {
  switch (k) {
    case RbfKernel::kGaussian: return "gaussian";
    case RbfKernel::kThinPlate: return "thin_plate";
    case RbfKernel::kLinear: return "linear";
  }
  return "?";
}

bool parse_rbf_kernel(const std::string& name, RbfKernel& out) {
  for (RbfKernel k : {RbfKernel::kGaussian, RbfKernel::kThinPlate, RbfKernel::kLinear})
    if (name == rbf_kernel_name(k)) {
      out = k;
      return true;
    }
  return false;
}

double RbfInterpolator::phi(double r) const {
  switch (kernel_) {
    case RbfKernel::kGaussian: {
      double q = r / width_;
      return std::exp(-q * q);
    }
    case RbfKernel::kThinPlate: return r > 0 ? r * r * std::log(r) : 0.0;
    case RbfKernel::kLinear: return r;
  }
  return 0.0;
}

Result<RbfInterpolator> RbfInterpolator::create(std::span<const double> centres, size_t dims,
                                                RbfKernel kernel, double width) {
  if (dims == 0)
    return make_error(ErrorCode::kInvalidArgument, "RBF interpolation needs at least one dimension");
  CAGEWRAP_CHECK(centres.size() % dims == 0, "centres are #K x D");
  for (double c : centres)
    if (!std::isfinite(c))
      return make_error(ErrorCode::kNonFinite, "an RBF centre has a non-finite coordinate");
  RbfInterpolator r;
  r.centres_.assign(centres.begin(), centres.end());
  r.k_ = centres.size() / dims;
  r.d_ = dims;
  r.kernel_ = kernel;
  r.p_ = kernel == RbfKernel::kGaussian ? 0 : kernel == RbfKernel::kLinear ? 1 : dims + 1;
  const size_t k = r.k_, d = r.d_;
  auto dist = [&](const double* a, const double* b) {
    double s = 0;
    for (size_t i = 0; i < d; ++i) s += (a[i] - b[i]) * (a[i] - b[i]);
    return std::sqrt(s);
  };
  if (width > 0 && std::isfinite(width)) {
    r.width_ = width;
  } else {
    double sum = 0;
    size_t counted = 0;
    for (size_t i = 0; i < k; ++i) {
      double best = HUGE_VAL;
      for (size_t j = 0; j < k; ++j)
        if (j != i) best = std::min(best, dist(&centres[i * d], &centres[j * d]));
      if (std::isfinite(best) && best > 0) {
        sum += best;
        ++counted;
      }
    }
    r.width_ = counted ? sum / double(counted) : 1.0;
  }
  if (k == 0) return r;
  const size_t n = k + r.p_;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
  for (size_t i = 0; i < k; ++i) {
    for (size_t j = 0; j < k; ++j) a(i, j) = r.phi(dist(&centres[i * d], &centres[j * d]));
    if (r.p_ > 0) a(i, k) = a(k, i) = 1.0;
    if (r.p_ > 1)
      for (size_t c = 0; c < d; ++c) a(i, k + 1 + c) = a(k + 1 + c, i) = centres[i * d + c];
  }
  // The pseudo-inverse: the plain inverse when the system is regular (distinct centres; for the
  // thin plate, centres not all on one hyperplane); otherwise the minimum-norm interpolant, which
  // still reproduces every key because the data (f, 0) lies in the system's range.
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(a);
  Eigen::MatrixXd inv = cod.pseudoInverse();
  r.inverse_.resize(k * n);
  for (size_t i = 0; i < k; ++i)
    for (size_t j = 0; j < n; ++j) r.inverse_[i * n + j] = inv(i, j);
  return r;
}

void RbfInterpolator::weights(std::span<const double> x, std::span<double> out) const {
  CAGEWRAP_CHECK(x.size() == d_ && out.size() == k_, "a query of D values, K weights");
  const size_t n = k_ + p_;
  double b_small[64];
  std::vector<double> b_big;
  double* b = b_small;
  if (n > 64) {
    b_big.resize(n);
    b = b_big.data();
  }
  for (size_t j = 0; j < k_; ++j) {
    double s = 0;
    for (size_t c = 0; c < d_; ++c) s += (x[c] - centres_[j * d_ + c]) * (x[c] - centres_[j * d_ + c]);
    b[j] = phi(std::sqrt(s));
  }
  if (p_ > 0) b[k_] = 1.0;
  if (p_ > 1)
    for (size_t c = 0; c < d_; ++c) b[k_ + 1 + c] = x[c];
  for (size_t i = 0; i < k_; ++i) {
    double s = 0;
    for (size_t j = 0; j < n; ++j) s += inverse_[i * n + j] * b[j];
    out[i] = s;
  }
}

}  // namespace cagewrap
