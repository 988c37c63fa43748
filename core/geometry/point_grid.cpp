#include "core/geometry/point_grid.h"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

namespace cagewrap {

PointGrid::PointGrid(std::span<const glm::vec3> points, double points_per_cell) : points_(points.begin(), points.end()) {
  if (points_.empty()) {
    cell_start_.assign(2, 0);
    return;
  }
  glm::dvec3 lo(points_[0]), hi(points_[0]);
  for (const glm::vec3& p : points_) {
    lo = glm::min(lo, glm::dvec3(p));
    hi = glm::max(hi, glm::dvec3(p));
  }
  const glm::dvec3 ext = glm::max(hi - lo, glm::dvec3(1e-12));
  // cubic cells, about points_per_cell points each if the points filled the box; an axis thinner
  // than a cell (a flat or straight set: a sheet of samples) counts as one cell, so the others
  // share the cells instead of the cube root making them vanishingly small
  const double cells = std::max(1.0, double(points_.size()) / std::max(points_per_cell, 1.0));
  cell_ = std::cbrt(ext.x * ext.y * ext.z / cells);
  for (int pass = 0; pass < 2; ++pass) {
    double volume = 1.0;
    int wide = 0;
    for (int a = 0; a < 3; ++a)
      if (ext[a] > cell_) volume *= ext[a], ++wide;
    if (wide > 0 && wide < 3) cell_ = std::pow(volume / cells, 1.0 / wide);
  }
  cell_ = std::max(cell_, std::max({ext.x, ext.y, ext.z}) / 1024.0);  // at most 1024 cells a side
  lo_ = lo;
  for (int a = 0; a < 3; ++a) dims_[a] = std::max(1, int(std::ceil(ext[a] / cell_)) + 1);
  const size_t n_cells = size_t(dims_.x) * dims_.y * dims_.z;
  std::vector<uint32_t> cell(points_.size());
  cell_start_.assign(n_cells + 1, 0);
  for (size_t i = 0; i < points_.size(); ++i) {
    const glm::ivec3 c = cell_of(glm::dvec3(points_[i]));
    cell[i] = uint32_t((size_t(c.z) * dims_.y + c.y) * dims_.x + c.x);
    ++cell_start_[cell[i] + 1];
  }
  for (size_t c = 0; c < n_cells; ++c) cell_start_[c + 1] += cell_start_[c];
  ids_.resize(points_.size());
  std::vector<uint32_t> fill(cell_start_.begin(), cell_start_.end() - 1);
  for (size_t i = 0; i < points_.size(); ++i) ids_[fill[cell[i]]++] = uint32_t(i);
}

glm::ivec3 PointGrid::cell_of(const glm::dvec3& p) const {
  glm::ivec3 c;
  for (int a = 0; a < 3; ++a) c[a] = std::clamp(int(std::floor((p[a] - lo_[a]) / cell_)), 0, dims_[a] - 1);
  return c;
}

void PointGrid::nearest(const glm::dvec3& p, size_t k, std::vector<std::pair<double, uint32_t>>& out) const {
  out.clear();
  if (k == 0 || points_.empty()) return;
  k = std::min(k, points_.size());
  const glm::ivec3 c = cell_of(p);
  // distance from p to the outside of the box of cells within `r` of c: anything not yet visited
  // is at least this far
  auto reach = [&](int r) {
    double d = 1e300;
    for (int a = 0; a < 3; ++a) {
      const double below = p[a] - (lo_[a] + (c[a] - r) * cell_);
      const double above = lo_[a] + (c[a] + r + 1) * cell_ - p[a];
      if (c[a] - r > 0) d = std::min(d, below);
      if (c[a] + r + 1 < dims_[a]) d = std::min(d, above);
    }
    return d;
  };
  auto better = [](const std::pair<double, uint32_t>& a, const std::pair<double, uint32_t>& b) { return a < b; };
  const int max_r = std::max({dims_.x, dims_.y, dims_.z});
  for (int r = 0; r <= max_r; ++r) {
    auto visit = [&](int x, int y, int z) {
      const size_t cell = (size_t(z) * dims_.y + y) * dims_.x + x;
      for (uint32_t s = cell_start_[cell]; s < cell_start_[cell + 1]; ++s) {
        const uint32_t i = ids_[s];
        const glm::dvec3 d = glm::dvec3(points_[i]) - p;
        const std::pair<double, uint32_t> cand{glm::dot(d, d), i};
        if (out.size() < k) {
          out.push_back(cand);
          std::push_heap(out.begin(), out.end(), better);
        } else if (better(cand, out.front())) {
          std::pop_heap(out.begin(), out.end(), better);
          out.back() = cand;
          std::push_heap(out.begin(), out.end(), better);
        }
      }
    };
    // the cells at Chebyshev distance r from c, clipped to the grid
    const int x0 = std::max(c.x - r, 0), x1 = std::min(c.x + r, dims_.x - 1);
    const int y0 = std::max(c.y - r, 0), y1 = std::min(c.y + r, dims_.y - 1);
    const int z0 = std::max(c.z - r, 0), z1 = std::min(c.z + r, dims_.z - 1);
    for (int z = z0; z <= z1; ++z)
      for (int y = y0; y <= y1; ++y) {
        if (std::abs(z - c.z) == r || std::abs(y - c.y) == r) {
          for (int x = x0; x <= x1; ++x) visit(x, y, z);
        } else {
          if (c.x - r >= 0) visit(c.x - r, y, z);
          if (r > 0 && c.x + r < dims_.x) visit(c.x + r, y, z);
        }
      }
    if (out.size() == k) {
      const double rr = reach(r);
      if (rr * rr >= out.front().first) break;
    }
  }
  std::sort_heap(out.begin(), out.end(), better);
}

}  // namespace cagewrap
