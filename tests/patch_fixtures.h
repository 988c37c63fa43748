// Small parametric drivers and skins for the patch tests.
#pragma once

#include <cmath>
#include <glm/vec3.hpp>
#include <random>
#include <vector>

#include "core/deform/patch_surface.h"
#include "core/geometry/mesh.h"

namespace cagewrap::test {

// A gently curved B-spline sheet: rows x cols control points over x in [0, cols - 1], z in
// [0, rows - 1], with y a smooth bump (so the normals vary).
inline PatchGrid wavy_grid(uint32_t rows = 7, uint32_t cols = 8, PatchBasis basis = PatchBasis::kBSpline) {
  PatchGrid g;
  g.basis = basis;
  g.rows = rows;
  g.cols = cols;
  for (uint32_t r = 0; r < rows; ++r)
    for (uint32_t c = 0; c < cols; ++c)
      g.points.push_back({double(c), 0.4 * std::sin(0.9 * c) * std::cos(0.7 * r), double(r)});
  return g;
}

inline PatchSurface wavy_surface(uint32_t rows = 7, uint32_t cols = 8) {
  return PatchSurface{{wavy_grid(rows, cols)}};
}

// `n` points in a slab around the sheet of wavy_grid(rows, cols): x, z inside the grid's extent (a
// margin of 0.5 in), y in [-0.6, 0.6] about the bump.
inline std::vector<glm::vec3> slab_skin(size_t n, uint32_t rows = 7, uint32_t cols = 8, unsigned seed = 7) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> ux(0.5f, float(cols) - 1.5f), uz(0.5f, float(rows) - 1.5f),
      uy(-0.6f, 0.6f);
  std::vector<glm::vec3> out(n);
  for (auto& p : out) p = {ux(rng), uy(rng), uz(rng)};
  return out;
}

// A 5 x 4 quad sheet in the plane z = 0.1, x in [-0.25, 0.25], y in [0.95, 1.45]: a cage in front of
// the demo character's chest, to fit a parametric driver to.
inline PolyMesh chest_sheet() {
  PolyMesh m;
  const uint32_t nx = 5, ny = 4;
  for (uint32_t j = 0; j <= ny; ++j)
    for (uint32_t i = 0; i <= nx; ++i) m.positions.push_back(glm::vec3(-0.25f + 0.5f * i / nx, 0.95f + 0.5f * j / ny, 0.1f));
  for (uint32_t j = 0; j < ny; ++j)
    for (uint32_t i = 0; i < nx; ++i) {
      const uint32_t a = j * (nx + 1) + i;
      m.add_face({a, a + 1, a + nx + 2, a + nx + 1});
    }
  return m;
}

}  // namespace cagewrap::test
