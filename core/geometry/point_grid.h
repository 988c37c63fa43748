// A uniform grid over a point set for k-nearest-neighbour queries (cage vertices looking up the
// skin points around them). Cells hold about `points_per_cell` points; a query visits shells of
// cells around its cell until the k-th nearest found is closer than any unvisited cell can be.
#pragma once

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

namespace cagewrap {

class PointGrid {
 public:
  PointGrid() = default;
  explicit PointGrid(std::span<const glm::vec3> points, double points_per_cell = 4.0);

  // The k nearest points to p as (squared distance, index), nearest first (ties by index); fewer
  // when the set has fewer. `out` is cleared first.
  void nearest(const glm::dvec3& p, size_t k, std::vector<std::pair<double, uint32_t>>& out) const;

  size_t size() const { return points_.size(); }

 private:
  std::vector<glm::vec3> points_;
  glm::dvec3 lo_{0.0};
  double cell_ = 1.0;
  glm::ivec3 dims_{1, 1, 1};
  std::vector<uint32_t> cell_start_;  // #cells + 1
  std::vector<uint32_t> ids_;         // point ids by cell
  glm::ivec3 cell_of(const glm::dvec3& p) const;
};

}  // namespace cagewrap
