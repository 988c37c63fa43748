// Fitting a patch grid to selected cage faces (core/deform/patch_fit.h): the rectangle of quads is found
// in any orientation, the fit follows the faces, and selections that are no rectangle are refused
// naming a face.
#include "core/deform/patch_fit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>

#include "tests/expect_error.h"

namespace cagewrap {
namespace {

// A quad mesh of nx x nz faces over x in [0, nx], z in [0, nz], y = height(x, z); then one triangle
// beside it (face nx * nz).
PolyMesh sheet(uint32_t nx, uint32_t nz, double (*height)(double, double)) {
  PolyMesh m;
  for (uint32_t i = 0; i <= nz; ++i)
    for (uint32_t j = 0; j <= nx; ++j) m.positions.push_back(glm::vec3(j, height(j, i), i));
  auto v = [&](uint32_t i, uint32_t j) { return i * (nx + 1) + j; };
  for (uint32_t i = 0; i < nz; ++i)
    for (uint32_t j = 0; j < nx; ++j) m.add_face({v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1)});
  m.positions.push_back(glm::vec3(-1, 0, 0));
  m.add_face({v(0, 0), v(1, 0), uint32_t(m.positions.size() - 1)});
  return m;
}
double flat(double, double) {
  return 0.0;
}
double bump(double x, double z) {
  return 0.3 * std::sin(0.8 * x) * std::cos(0.6 * z);
}

std::vector<uint32_t> block(uint32_t nx, uint32_t i0, uint32_t i1, uint32_t j0, uint32_t j1) {
  std::vector<uint32_t> out;
  for (uint32_t i = i0; i < i1; ++i)
    for (uint32_t j = j0; j < j1; ++j) out.push_back(i * nx + j);
  return out;
}

TEST(PatchFit, FindsTheRectangleOfQuads) {
  const PolyMesh m = sheet(6, 5, flat);
  const auto faces = block(6, 1, 4, 2, 6);  // 3 rows x 4 columns of faces
  auto g = quad_grid_of_faces(m, faces);
  ASSERT_TRUE(g.ok()) << g.error().message;
  EXPECT_EQ(std::min(g->rows, g->cols), 3u);
  EXPECT_EQ(std::max(g->rows, g->cols), 4u);
  EXPECT_EQ(g->vertices.size(), size_t(g->rows + 1) * (g->cols + 1));
  // neighbouring grid vertices are one unit apart, diagonal ones sqrt(2): a true grid
  for (uint32_t i = 0; i <= g->rows; ++i)
    for (uint32_t j = 0; j <= g->cols; ++j) {
      const glm::vec3 p = m.positions[g->vertices[i * (g->cols + 1) + j]];
      if (j < g->cols) {
        EXPECT_NEAR(glm::length(m.positions[g->vertices[i * (g->cols + 1) + j + 1]] - p), 1.0, 1e-6);
      }
      if (i < g->rows) {
        EXPECT_NEAR(glm::length(m.positions[g->vertices[(i + 1) * (g->cols + 1) + j]] - p), 1.0, 1e-6);
      }
    }
  std::vector<uint32_t> sorted = g->faces;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(sorted, faces);
}

TEST(PatchFit, FittedGridFollowsTheFaces) {
  const PolyMesh m = sheet(8, 7, bump);
  const auto faces = block(8, 0, 7, 0, 8);
  auto grid = fit_patch_to_faces(m, m.positions, faces);
  ASSERT_TRUE(grid.ok()) << grid.error().message;
  auto q = quad_grid_of_faces(m, faces);
  ASSERT_TRUE(q.ok());
  // one control point per vertex line: the surface passes (nearly: the smoothing) through every vertex
  EXPECT_EQ(grid->rows, q->rows + 1);
  EXPECT_EQ(grid->cols, q->cols + 1);
  const double su = grid->cols - 3, sv = grid->rows - 3;
  double worst = 0;
  for (uint32_t i = 0; i <= q->rows; ++i)
    for (uint32_t j = 0; j <= q->cols; ++j) {
      const glm::dvec3 s = evaluate(*grid, su * j / q->cols, sv * i / q->rows).position;
      worst = std::max(worst, glm::length(s - glm::dvec3(m.positions[q->vertices[i * (q->cols + 1) + j]])));
    }
  EXPECT_LT(worst, 0.02);  // faces are 1 unit wide; the bump is 0.3 high
  EXPECT_GT(worst, 0.0);
  // fewer control points: a smoother surface, still close
  auto coarse = fit_patch_to_faces(m, m.positions, faces, {.rows = 5, .cols = 5});
  ASSERT_TRUE(coarse.ok());
  EXPECT_EQ(coarse->rows, 5u);
  EXPECT_EQ(coarse->cols, 5u);
  EXPECT_TRUE(validate_patch_surface(PatchSurface{{*coarse}}, "fit").ok());
}

TEST(PatchFit, NarrowSelectionsGiveAnEvenGrid) {
  const PolyMesh m = sheet(6, 5, flat);
  const auto faces = block(6, 2, 3, 1, 5);  // one row of 4 faces
  auto grid = fit_patch_to_faces(m, m.positions, faces);
  ASSERT_TRUE(grid.ok()) << grid.error().message;
  EXPECT_EQ(std::min(grid->rows, grid->cols), 4u);  // 2 vertex lines across, at least 4 control points
  for (const glm::dvec3& p : grid->points) {
    EXPECT_NEAR(p.y, 0.0, 1e-9);  // on the plane of the faces
    EXPECT_GE(p.z, 2.0 - 1e-6);
    EXPECT_LE(p.z, 3.0 + 1e-6);
  }
}

TEST(PatchFit, SelectionsThatAreNoRectangleAreRefused) {
  const PolyMesh m = sheet(6, 5, flat);
  const uint32_t tri = 6 * 5;
  std::vector<uint32_t> with_tri = block(6, 0, 2, 0, 2);
  with_tri.push_back(tri);
  EXPECT_TRUE(
      Fails(quad_grid_of_faces(m, with_tri), ErrorCode::kInvalidArgument, {"cage face 30", "3 corners"}));
  std::vector<uint32_t> ell = block(6, 0, 2, 0, 3);  // 2 x 3 ...
  ell.push_back(2 * 6 + 0);                          // ... plus one face below its first column
  EXPECT_TRUE(
      Fails(quad_grid_of_faces(m, ell), ErrorCode::kInvalidArgument, {"not", "rectangle", "cage face"}));
  std::vector<uint32_t> apart = {0, 3};
  EXPECT_TRUE(
      Fails(quad_grid_of_faces(m, apart), ErrorCode::kInvalidArgument, {"cage face 3", "not in the"}));
  EXPECT_TRUE(Fails(quad_grid_of_faces(m, {}), ErrorCode::kInvalidArgument, {"no cage faces"}));
  std::vector<uint32_t> missing = {0, 99};
  EXPECT_TRUE(
      Fails(quad_grid_of_faces(m, missing), ErrorCode::kInvalidArgument, {"cage face 99", "does not exist"}));
  // a tube (the sheet's columns wrapped round): no corner
  PolyMesh tube;
  const uint32_t n = 6;
  for (uint32_t i = 0; i <= 2; ++i)
    for (uint32_t j = 0; j < n; ++j)
      tube.positions.push_back(glm::vec3(std::cos(2 * M_PI * j / n), i, std::sin(2 * M_PI * j / n)));
  for (uint32_t i = 0; i < 2; ++i)
    for (uint32_t j = 0; j < n; ++j)
      tube.add_face({i * n + j, (i + 1) * n + j, (i + 1) * n + (j + 1) % n, i * n + (j + 1) % n});
  std::vector<uint32_t> all(2 * n);
  for (uint32_t f = 0; f < all.size(); ++f) all[f] = f;
  EXPECT_TRUE(Fails(quad_grid_of_faces(tube, all), ErrorCode::kInvalidArgument, {"ring"}));
  EXPECT_TRUE(Fails(fit_patch_to_faces(m, m.positions, block(6, 0, 2, 0, 2), {.rows = 3}),
                    ErrorCode::kInvalidArgument, {"4 to 256"}));
}

}  // namespace
}  // namespace cagewrap
