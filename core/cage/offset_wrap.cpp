#include "core/cage/offset_wrap.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <tbb/parallel_for.h>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "core/geometry/element_bvh.h"

namespace cagewrap {

namespace {
enum : uint8_t { kUnknown = 0, kShell = 1, kOutside = 2 };
constexpr double kClear = 0.02;  // samples stay this share of a cell off the iso-value
}  // namespace

IsoSurface offset_wrap(std::span<const glm::vec3> positions, std::span<const Tri> triangles, double offset,
                       double cell) {
  cell = std::min(cell, offset);
  const Aabb box = bounding_box(positions);
  const double pad = offset + 3.0 * cell;
  Grid3 grid;
  grid.spacing = cell;
  grid.origin = box.lo - glm::dvec3(pad);
  for (int a = 0; a < 3; ++a) grid.size[a] = int(std::ceil((box.hi[a] - box.lo[a] + 2 * pad) / cell)) + 1;
  const size_t n = grid.count();
  std::vector<uint8_t> state(n, kUnknown);

  // the shell: every grid cell a skin sample falls in marks its 8 corners
  for (const Tri& t : triangles) {
    const glm::dvec3 a(positions[t[0]]), b(positions[t[1]]), c(positions[t[2]]);
    const double longest = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
    const int steps = std::max(1, int(std::ceil(longest / (cell / 3.0))));
    for (int i = 0; i <= steps; ++i)
      for (int j = 0; i + j <= steps; ++j) {
        const glm::dvec3 p = a + (b - a) * (double(i) / steps) + (c - a) * (double(j) / steps);
        const glm::ivec3 q = glm::ivec3(glm::floor((p - grid.origin) / cell));
        for (int k = 0; k < 8; ++k)
          state[grid.index(q.x + (k & 1), q.y + ((k >> 1) & 1), q.z + ((k >> 2) & 1))] = kShell;
      }
  }
  std::vector<uint32_t> ids;  // triangles with an area (the closest-point kernel needs one)
  for (uint32_t t = 0; t < triangles.size(); ++t) {
    const glm::dvec3 a(positions[triangles[t][0]]), b(positions[triangles[t][1]]),
        c(positions[triangles[t][2]]);
    if (glm::length(glm::cross(b - a, c - a)) > 0.0) ids.push_back(t);
  }
  const ElementBvh bvh(positions, triangles, ids);
  std::vector<double> distance(n, -1.0);  // exact distance to the soup where computed
  std::vector<size_t> shell;
  for (size_t i = 0; i < n; ++i)
    if (state[i] == kShell) shell.push_back(i);
  tbb::parallel_for(size_t(0), shell.size(), [&](size_t k) {
    distance[shell[k]] = bvh.nearest_distance(grid.point(shell[k]));
  });
  // Only shell corners within the offset block the fill. A shell corner farther out (the cell may
  // be as large as the offset) is classified by the fill like any other: the fill cannot cross the
  // soup through such corners, because a grid edge crossing it with both ends more than the offset
  // away would be longer than twice the offset.
  for (size_t i : shell)
    if (distance[i] > offset) state[i] = kUnknown;

  // outside: flood fill from a corner (the padding keeps it clear of the shell), 6-connected
  auto neighbours = [&](size_t i, auto visit) {
    const int x = int(i % grid.size[0]), y = int((i / grid.size[0]) % grid.size[1]),
              z = int(i / (size_t(grid.size[0]) * grid.size[1]));
    if (x > 0) visit(i - 1);
    if (x + 1 < grid.size[0]) visit(i + 1);
    if (y > 0) visit(i - grid.size[0]);
    if (y + 1 < grid.size[1]) visit(i + grid.size[0]);
    if (z > 0) visit(i - size_t(grid.size[0]) * grid.size[1]);
    if (z + 1 < grid.size[2]) visit(i + size_t(grid.size[0]) * grid.size[1]);
  };
  std::vector<size_t> queue = {0};
  state[0] = kOutside;
  for (size_t head = 0; head < queue.size(); ++head)
    neighbours(queue[head], [&](size_t j) {
      if (state[j] == kUnknown) {
        state[j] = kOutside;
        queue.push_back(j);
      }
    });

  // the band: the blocking shell and the outside samples a few steps from the shell get exact
  // distances (minus the offset); deeper inside is -offset, farther outside +offset
  const int band =
      int(std::ceil(std::sqrt(3.0) * offset / cell)) + 3;  // 6-connected steps over-count diagonals
  std::vector<int> steps(n, -1);
  queue = shell;
  for (size_t i : shell) steps[i] = 0;
  std::vector<size_t> in_band;
  for (size_t head = 0; head < queue.size(); ++head) {
    const size_t i = queue[head];
    if (state[i] != kUnknown) in_band.push_back(i);  // blocking (kShell) or outside
    if (steps[i] >= band) continue;
    neighbours(i, [&](size_t j) {
      if (state[j] == kOutside && steps[j] < 0) {
        steps[j] = steps[i] + 1;
        queue.push_back(j);
      }
    });
  }
  std::vector<double> value(n);
  for (size_t i = 0; i < n; ++i) value[i] = state[i] == kOutside ? offset : -offset;
  tbb::parallel_for(size_t(0), in_band.size(), [&](size_t k) {
    const size_t i = in_band[k];
    const double d = distance[i] >= 0 ? distance[i] : bvh.nearest_distance(grid.point(i));
    const double v = d - offset;
    // nothing on or next to the surface: a sample there would pinch triangles to nothing
    value[i] = std::abs(v) < kClear * cell ? (v < 0 ? -kClear : kClear) * cell : v;
  });
  return marching_tetrahedra(grid, value, 0.0);
}

}  // namespace cagewrap
