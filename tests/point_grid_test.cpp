// core/geometry/point_grid.h against a brute-force search: the same k nearest, in the same order, for
// queries inside, on and far outside the points' box, clustered and degenerate (flat) sets.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include <glm/geometric.hpp>

#include "core/geometry/point_grid.h"

namespace cagewrap {
namespace {

std::vector<std::pair<double, uint32_t>> brute(std::span<const glm::vec3> pts, const glm::dvec3& q, size_t k) {
  std::vector<std::pair<double, uint32_t>> all;
  for (uint32_t i = 0; i < pts.size(); ++i) {
    const glm::dvec3 d = glm::dvec3(pts[i]) - q;
    all.push_back({glm::dot(d, d), i});
  }
  std::sort(all.begin(), all.end());
  all.resize(std::min(k, all.size()));
  return all;
}

void expect_same_as_brute_force(const std::vector<glm::vec3>& pts, std::mt19937& rng, double spread) {
  PointGrid grid(pts);
  std::uniform_real_distribution<double> u(-spread, spread);
  std::vector<std::pair<double, uint32_t>> got;
  for (int q = 0; q < 300; ++q) {
    const glm::dvec3 p = q % 3 == 0 ? glm::dvec3(pts[size_t(q) % pts.size()]) : glm::dvec3(u(rng), u(rng), u(rng));
    for (size_t k : {1u, 8u, 40u}) {
      grid.nearest(p, k, got);
      ASSERT_EQ(got, brute(pts, p, k)) << "query " << q << " k " << k;
    }
  }
}

TEST(PointGrid, SameNeighboursAsBruteForce) {
  std::mt19937 rng(7);
  std::normal_distribution<float> n(0.f, 1.f);
  std::vector<glm::vec3> cloud, clusters, flat;
  for (int i = 0; i < 3000; ++i) cloud.push_back({n(rng), n(rng), n(rng)});
  for (int i = 0; i < 3000; ++i) {  // two tight clusters far apart: most cells empty
    const float off = i % 2 ? 50.f : -50.f;
    clusters.push_back({off + 0.01f * n(rng), 0.01f * n(rng), 0.01f * n(rng)});
  }
  for (int i = 0; i < 2000; ++i) flat.push_back({n(rng), n(rng), 0.f});  // zero extent in z
  expect_same_as_brute_force(cloud, rng, 4.0);
  expect_same_as_brute_force(clusters, rng, 80.0);
  expect_same_as_brute_force(flat, rng, 3.0);
  std::vector<glm::vec3> line;  // zero extent in y and z: its cells are shared along x alone
  for (int i = 0; i < 500; ++i) line.push_back({n(rng), 0.f, 0.f});
  expect_same_as_brute_force(line, rng, 3.0);
}

TEST(PointGrid, FewerPointsThanAskedAndEmpty) {
  std::vector<glm::vec3> pts = {{0, 0, 0}, {1, 0, 0}, {5, 5, 5}};
  PointGrid grid(pts);
  std::vector<std::pair<double, uint32_t>> got;
  grid.nearest({0.9, 0, 0}, 10, got);
  ASSERT_EQ(got.size(), 3u);
  EXPECT_EQ(got[0].second, 1u);
  EXPECT_EQ(got[1].second, 0u);
  EXPECT_EQ(got[2].second, 2u);
  PointGrid empty(std::span<const glm::vec3>{});
  empty.nearest({0, 0, 0}, 4, got);
  EXPECT_TRUE(got.empty());
}

}  // namespace
}  // namespace cagewrap
