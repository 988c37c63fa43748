#include "core/deform/patch_surface.h"

#include <algorithm>
#include <cmath>

#include "core/base/check.h"
#include "core/base/digits.h"

namespace cagewrap {

const char* patch_basis_name(PatchBasis b) {
  return b == PatchBasis::kBezier ? "bezier" : "bspline";
}

bool parse_patch_basis(const std::string& s, PatchBasis& out) {
  if (s == "bspline")
    out = PatchBasis::kBSpline;
  else if (s == "bezier")
    out = PatchBasis::kBezier;
  else
    return false;
  return true;
}

size_t PatchSurface::num_control_points() const {
  size_t n = 0;
  for (const PatchGrid& g : grids) n += g.points.size();
  return n;
}

std::vector<glm::dvec3> PatchSurface::control_points() const {
  std::vector<glm::dvec3> out;
  out.reserve(num_control_points());
  for (const PatchGrid& g : grids) out.insert(out.end(), g.points.begin(), g.points.end());
  return out;
}

void PatchSurface::set_control_points(std::span<const glm::dvec3> points) {
  CAGEWRAP_CHECK(points.size() == num_control_points(), "one position per control point");
  size_t k = 0;
  for (PatchGrid& g : grids)
    for (glm::dvec3& p : g.points) p = points[k++];
}

std::vector<std::array<uint32_t, 2>> control_net_edges(const PatchSurface& surface) {
  std::vector<std::array<uint32_t, 2>> out;
  uint32_t base = 0;
  for (const PatchGrid& g : surface.grids) {
    for (uint32_t r = 0; r < g.rows; ++r)
      for (uint32_t c = 0; c + 1 < g.cols; ++c) out.push_back({base + r * g.cols + c, base + r * g.cols + c + 1});
    for (uint32_t r = 0; r + 1 < g.rows; ++r)
      for (uint32_t c = 0; c < g.cols; ++c) out.push_back({base + r * g.cols + c, base + (r + 1) * g.cols + c});
    base += static_cast<uint32_t>(g.points.size());
  }
  return out;
}

uint32_t patch_spans(PatchBasis basis, uint32_t n) {
  if (n < 4) return 0;
  return basis == PatchBasis::kBezier ? (n - 1) / 3 : n - 3;
}

Status validate_patch_surface(const PatchSurface& s, const std::string& what) {
  if (s.grids.empty()) return make_error(ErrorCode::kEmpty, what + ": the patch driver has no grid");
  for (size_t gi = 0; gi < s.grids.size(); ++gi) {
    const PatchGrid& g = s.grids[gi];
    const std::string grid = what + ": grid " + std::to_string(gi);
    if (g.rows < 4 || g.cols < 4)
      return make_error(ErrorCode::kInvalidArgument,
                        grid + " has " + std::to_string(g.rows) + " x " + std::to_string(g.cols) +
                            " control points; a bicubic grid needs at least 4 x 4");
    if (g.basis == PatchBasis::kBezier)
      for (uint32_t n : {g.rows, g.cols})
        if ((n - 1) % 3 != 0)
          return make_error(ErrorCode::kInvalidArgument,
                            grid + " is a Bezier grid of " + std::to_string(g.rows) + " x " +
                                std::to_string(g.cols) +
                                " control points; each side must be 3 m + 1 (4, 7, 10, ...)");
    if (g.points.size() != size_t(g.rows) * g.cols)
      return make_error(ErrorCode::kTopologyMismatch,
                        grid + " declares " + std::to_string(g.rows) + " x " + std::to_string(g.cols) +
                            " control points but holds " + std::to_string(g.points.size()));
    for (uint32_t r = 0; r < g.rows; ++r)
      for (uint32_t c = 0; c < g.cols; ++c) {
        const glm::dvec3& p = g.at(r, c);
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
          return make_error(ErrorCode::kNonFinite, grid + ", control point row " + std::to_string(r) +
                                                       " column " + std::to_string(c) +
                                                       " has a non-finite coordinate");
      }
  }
  return Ok{};
}

namespace {

// The clamped uniform knot vector of a cubic B-spline with n control points: 0 four times, 1, ...,
// n - 4, n - 3 four times.
double knot(uint32_t n, int64_t i) {
  return static_cast<double>(std::clamp<int64_t>(i - 3, 0, int64_t(n) - 3));
}

CubicBasis bspline_basis(uint32_t n, double t) {
  const uint32_t spans = n - 3;
  t = std::clamp(t, 0.0, double(spans));
  // knot span i with U[i] <= t < U[i+1], i in [3, n - 1] (the last span also takes t = spans)
  const int64_t i = 3 + std::min<int64_t>(static_cast<int64_t>(std::floor(t)), int64_t(spans) - 1);
  // Cox-de Boor triangle (The NURBS Book, A2.2), keeping the degree-2 values for the derivative
  double N[4] = {1, 0, 0, 0}, left[4]{}, right[4]{}, deg2[3]{};
  for (int j = 1; j <= 3; ++j) {
    left[j] = t - knot(n, i + 1 - j);
    right[j] = knot(n, i + j) - t;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      const double denom = right[r + 1] + left[j - r];
      const double temp = denom != 0.0 ? N[r] / denom : 0.0;
      N[r] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    N[j] = saved;
    if (j == 2) std::copy(N, N + 3, deg2);
  }
  CubicBasis b;
  b.first = static_cast<uint32_t>(i - 3);
  for (int k = 0; k < 4; ++k) {
    b.value[k] = N[k];
    // N'_{j,3} = 3 (N_{j,2} / (U[j+3] - U[j]) - N_{j+1,2} / (U[j+4] - U[j+1])), j = i - 3 + k;
    // N_{j,2} is deg2[k - 1] and N_{j+1,2} is deg2[k] where they are non-zero.
    const int64_t j = i - 3 + k;
    double d = 0.0;
    const double a = knot(n, j + 3) - knot(n, j), c = knot(n, j + 4) - knot(n, j + 1);
    if (k >= 1 && a != 0.0) d += deg2[k - 1] / a;
    if (k <= 2 && c != 0.0) d -= deg2[k] / c;
    b.deriv[k] = 3.0 * d;
  }
  return b;
}

CubicBasis bezier_basis(uint32_t n, double t) {
  const uint32_t spans = (n - 1) / 3;
  t = std::clamp(t, 0.0, double(spans));
  const uint32_t s = std::min<uint32_t>(static_cast<uint32_t>(std::floor(t)), spans - 1);
  const double x = t - s, y = 1.0 - x;
  CubicBasis b;
  b.first = 3 * s;
  b.value[0] = y * y * y;
  b.value[1] = 3 * x * y * y;
  b.value[2] = 3 * x * x * y;
  b.value[3] = x * x * x;
  b.deriv[0] = -3 * y * y;
  b.deriv[1] = 3 * y * y - 6 * x * y;
  b.deriv[2] = 6 * x * y - 3 * x * x;
  b.deriv[3] = 3 * x * x;
  return b;
}

}  // namespace

CubicBasis cubic_basis(PatchBasis basis, uint32_t n, double t) {
  CAGEWRAP_CHECK(n >= 4, "a cubic needs 4 control points");
  return basis == PatchBasis::kBezier ? bezier_basis(n, t) : bspline_basis(n, t);
}

namespace {

PatchSample make_sample(const PatchGrid& g, uint32_t grid, double u, double v) {
  const CubicBasis bu = cubic_basis(g.basis, g.cols, u), bv = cubic_basis(g.basis, g.rows, v);
  PatchSample s;
  s.grid = grid;
  s.u = u;
  s.v = v;
  s.first_row = bv.first;
  s.first_col = bu.first;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) {
      s.w[4 * r + c] = bv.value[r] * bu.value[c];
      s.wu[4 * r + c] = bv.value[r] * bu.deriv[c];
      s.wv[4 * r + c] = bv.deriv[r] * bu.value[c];
    }
  return s;
}

SampleFrame apply(const PatchGrid& g, const PatchSample& s) {
  SampleFrame f;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) {
      const glm::dvec3& p = g.at(s.first_row + r, s.first_col + c);
      f.position += s.w[4 * r + c] * p;
      f.du += s.wu[4 * r + c] * p;
      f.dv += s.wv[4 * r + c] * p;
    }
  return f;
}

}  // namespace

PatchPoint evaluate(const PatchGrid& grid, double u, double v) {
  return apply(grid, make_sample(grid, 0, u, v));
}

Result<std::vector<PatchSample>> sample_patch_surface(const PatchSurface& surface, uint32_t density) {
  if (density == 0 || density > 1024)
    return make_error(ErrorCode::kInvalidArgument,
                      "the sampling density must be between 1 and 1024 samples per span (got " +
                          std::to_string(density) + ")");
  if (auto s = validate_patch_surface(surface, "the patch driver"); !s) return s.error();
  // counted before anything is allocated: a small file may ask for a fine density on many spans
  uint64_t total = 0;
  for (const PatchGrid& g : surface.grids)
    total += (uint64_t(patch_spans(g.basis, g.cols)) * density + 1) * (uint64_t(patch_spans(g.basis, g.rows)) * density + 1);
  if (total > kMaxPatchSamples)
    return make_error(ErrorCode::kInvalidArgument,
                      "the patch driver at density " + std::to_string(density) + " has " + group_digits(total) +
                          " samples, more than " + group_digits(kMaxPatchSamples) +
                          " (each a control element of the skin); lower the density");
  std::vector<PatchSample> out;
  out.reserve(total);
  for (size_t gi = 0; gi < surface.grids.size(); ++gi) {
    const PatchGrid& g = surface.grids[gi];
    const uint32_t nu = patch_spans(g.basis, g.cols) * density, nv = patch_spans(g.basis, g.rows) * density;
    for (uint32_t j = 0; j <= nv; ++j)
      for (uint32_t i = 0; i <= nu; ++i)
        out.push_back(make_sample(g, static_cast<uint32_t>(gi), double(i) / density, double(j) / density));
  }
  return out;
}

SampleFrame sample_frame(const PatchSurface& surface, const PatchSample& sample) {
  CAGEWRAP_CHECK(sample.grid < surface.grids.size(), "a sample of this surface");
  return apply(surface.grids[sample.grid], sample);
}

}  // namespace cagewrap
