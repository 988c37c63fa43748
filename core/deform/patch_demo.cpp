#include "core/deform/patch_demo.h"

#include <algorithm>
#include <cmath>

namespace cagewrap {

namespace {
double wave(double x, double z) {
  return 0.35 * std::sin(0.7 * x) * std::cos(0.9 * z);
}
}  // namespace

PatchDemo make_patch_demo(uint32_t resolution) {
  PatchDemo d;
  const uint32_t rows = 6, cols = 12;
  PatchGrid g;
  g.rows = rows;
  g.cols = cols;
  for (uint32_t r = 0; r < rows; ++r)
    for (uint32_t c = 0; c < cols; ++c) g.points.push_back({double(c), wave(c, r), double(r)});
  d.driver.grids.push_back(g);
  // the skin: the sheet's surface offset by +-0.3 along y, on a regular (x, z) lattice inside the driver
  const uint32_t res = std::max<uint32_t>(resolution, 1);
  const uint32_t nx = 10 * res + 1, nz = 4 * res + 1;  // x in [0.5, 10.5], z in [0.5, 4.5]
  for (double side : {-0.3, 0.3})
    for (uint32_t i = 0; i < nz; ++i)
      for (uint32_t j = 0; j < nx; ++j) {
        const double x = 0.5 + 10.0 * j / (nx - 1), z = 0.5 + 4.0 * i / (nz - 1);
        d.skin.positions.push_back(glm::vec3(x, wave(x, z) + side, z));
      }
  auto v = [&](uint32_t s, uint32_t i, uint32_t j) { return s * nx * nz + i * nx + j; };
  for (uint32_t s = 0; s < 2; ++s)
    for (uint32_t i = 0; i + 1 < nz; ++i)
      for (uint32_t j = 0; j + 1 < nx; ++j) {
        // outward: the lower sheet faces -y, the upper +y
        if (s == 1) {
          d.skin.add_face({v(s, i, j), v(s, i + 1, j), v(s, i + 1, j + 1)});
          d.skin.add_face({v(s, i, j), v(s, i + 1, j + 1), v(s, i, j + 1)});
        } else {
          d.skin.add_face({v(s, i, j), v(s, i + 1, j + 1), v(s, i + 1, j)});
          d.skin.add_face({v(s, i, j), v(s, i, j + 1), v(s, i + 1, j + 1)});
        }
      }
  d.twist.axis = 0;
  d.twist.center = glm::dvec3(0.0, 0.0, 2.5);
  d.twist.lo = 0.0;
  d.twist.hi = 11.0;
  d.twist.degrees = 90.0;
  return d;
}

PatchSurface twisted(const PatchSurface& driver, const Twist& twist) {
  PatchSurface out = driver;
  for (PatchGrid& g : out.grids)
    for (glm::dvec3& p : g.points) p = twist.apply(p);
  return out;
}

}  // namespace cagewrap
