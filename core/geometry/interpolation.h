// Scattered-data interpolation for keyposes: piecewise-linear and monotone cubic curves over one
// driver, and radial-basis interpolation over several (pose space).
//
// This work is based on:
//   Fritsch, Carlson, "Monotone Piecewise Cubic Interpolation", SIAM J. Numer. Anal. 17(2), 1980;
//   Lewis, Cordner, Fong, "Pose Space Deformation: A Unified Approach to Shape Interpolation and
//   Skeleton-Driven Deformation", SIGGRAPH 2000 (RBF interpolation of shapes over pose space);
//   Micchelli, "Interpolation of Scattered Data: Distance Matrices and Conditionally Positive
//   Definite Functions", Constr. Approx. 2, 1986 (when the RBF system is solvable).
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "core/base/result.h"

namespace cagewrap {

// ---------------------------------------------------------------- one driver
// `xs` (#K) are strictly increasing key positions. Outside [xs.front(), xs.back()] every curve
// here is clamped: it holds the end key's value.

// Weights of each key at x for piecewise-linear interpolation (#K; at most two are non-zero, they
// sum to 1): value(x) = sum_k out[k] * y_k.
void linear_weights(std::span<const double> xs, double x, std::span<double> out);

// Fritsch-Carlson slopes (#K) for the data (xs, ys): the Hermite cubic through them with these
// slopes is monotone on every interval where the data is monotone, and is flat at local extrema.
// **decision:** the end slopes are 0 (not the one-sided secant of the paper), so the curve meets
// the clamped constant continuation with a continuous first derivative; two keys give an ease
// in/out (smoothstep) rather than a straight line.
void monotone_slopes(std::span<const double> xs, std::span<const double> ys, std::span<double> slopes);

// The Hermite cubic through (xs, ys) with `slopes` at x, clamped outside the keys.
double hermite_at(std::span<const double> xs, std::span<const double> ys, std::span<const double> slopes,
                  double x);

// Monotone cubic interpolation in one call (monotone_slopes, then hermite_at).
double monotone_cubic(std::span<const double> xs, std::span<const double> ys, double x);

// ---------------------------------------------------------------- several drivers (RBF)
enum class RbfKernel {
  kGaussian,   // phi(r) = exp(-(r / width)^2); positive definite, no polynomial term; decays to 0
               // (the rest shape) far from every key, as in Lewis et al.
  kThinPlate,  // phi(r) = r^2 log r with an affine term (sum w = 0, sum w x = 0)
  kLinear,     // phi(r) = r with a constant term (sum w = 0)
};
const char* rbf_kernel_name(RbfKernel k);
bool parse_rbf_kernel(const std::string& name, RbfKernel& out);

// Interpolates data given at #K centres in D dimensions. The system [Phi P; P^T 0] depends on the
// centres only, so its pseudo-inverse is computed once; value(x) = sum_k c_k(x) f_k with the
// cardinal weights c(x), for any data f (vectors too). With distinct centres c(centre_i) is the
// i-th unit vector: every key is reproduced exactly (to rounding).
class RbfInterpolator {
 public:
  // centres: #K x D, row-major. width: the Gaussian's width in the centres' units; <= 0 picks the
  // mean distance from each centre to its nearest other centre (1 when there is one centre).
  // Fails on a non-finite centre, or D == 0.
  static Result<RbfInterpolator> create(std::span<const double> centres, size_t dims, RbfKernel kernel,
                                        double width = 0.0);

  size_t num_centres() const { return k_; }
  size_t dims() const { return d_; }
  double width() const { return width_; }
  // Cardinal weights at x (#D) into out (#K).
  void weights(std::span<const double> x, std::span<double> out) const;

 private:
  double phi(double r) const;
  std::vector<double> centres_;  // #K x D
  std::vector<double> inverse_;  // #K x (K + P): the first K rows of the system's pseudo-inverse
  size_t k_ = 0, d_ = 0, p_ = 0;  // P: polynomial terms (0, 1 or D + 1)
  RbfKernel kernel_ = RbfKernel::kGaussian;
  double width_ = 1.0;
};

}  // namespace cagewrap
