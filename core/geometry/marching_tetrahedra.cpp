#include "core/geometry/marching_tetrahedra.h"

#include <unordered_map>
#include <utility>

#include <glm/geometric.hpp>

namespace cagewrap {

IsoSurface marching_tetrahedra(const Grid3& grid, std::span<const double> values, double iso) {
  IsoSurface s;
  auto inside = [&](size_t i) { return values[i] < iso; };
  std::unordered_map<uint64_t, uint32_t> edge_vertex;
  auto vertex_on = [&](size_t a, size_t b) {  // a inside, b outside
    const uint64_t key = uint64_t(std::min(a, b)) * grid.count() + std::max(a, b);
    auto [it, fresh] = edge_vertex.try_emplace(key, static_cast<uint32_t>(s.positions.size()));
    if (fresh) {
      const double t = (iso - values[a]) / (values[b] - values[a]);
      s.positions.emplace_back(grid.point(a) + t * (grid.point(b) - grid.point(a)));
    }
    return it->second;
  };
  // Winding from the midpoints of the crossed grid edges, not from the interpolated positions:
  // those may coincide where the field passes through a sample, the midpoints never do.
  struct Corner {
    uint32_t id;
    glm::dvec3 mid;
  };
  auto crossing = [&](size_t a, size_t b) {
    return Corner{vertex_on(a, b), 0.5 * (grid.point(a) + grid.point(b))};
  };
  auto emit = [&](Corner a, Corner b, Corner c, const glm::dvec3& outward) {
    if (glm::dot(glm::cross(b.mid - a.mid, c.mid - a.mid), outward) < 0) std::swap(b, c);
    s.triangles.push_back({a.id, b.id, c.id});
  };
  static const int kPerm[6][2] = {{0, 1}, {0, 2}, {1, 0}, {1, 2}, {2, 0}, {2, 1}};
  const auto [nx, ny, nz] = grid.size;
  for (int z = 0; z + 1 < nz; ++z)
    for (int y = 0; y + 1 < ny; ++y)
      for (int x = 0; x + 1 < nx; ++x) {
        size_t corner[8];
        int n_in = 0;
        for (int c = 0; c < 8; ++c) {
          corner[c] = grid.index(x + (c & 1), y + ((c >> 1) & 1), z + ((c >> 2) & 1));
          n_in += inside(corner[c]);
        }
        if (n_in == 0 || n_in == 8) continue;
        for (const auto& perm : kPerm) {
          // Kuhn simplex 0 -> +e_a -> +e_a +e_b -> 7
          const int c1 = 1 << perm[0], c2 = c1 | (1 << perm[1]);
          const size_t tet[4] = {corner[0], corner[c1], corner[c2], corner[7]};
          size_t in[4], out[4];
          int ni = 0, no = 0;
          for (size_t v : tet) (inside(v) ? in[ni++] : out[no++]) = v;
          if (ni == 0 || no == 0) continue;
          glm::dvec3 ci(0.0), co(0.0);
          for (int k = 0; k < ni; ++k) ci += grid.point(in[k]);
          for (int k = 0; k < no; ++k) co += grid.point(out[k]);
          const glm::dvec3 outward = co / double(no) - ci / double(ni);
          // New vertices are numbered in the order they are made, so the calls are sequenced (as
          // function arguments their order would be the compiler's; these keep g++'s, last to first)
          if (ni == 1) {
            const Corner c = crossing(in[0], out[2]), b = crossing(in[0], out[1]), a = crossing(in[0], out[0]);
            emit(a, b, c, outward);
          } else if (no == 1) {
            const Corner c = crossing(in[2], out[0]), b = crossing(in[1], out[0]), a = crossing(in[0], out[0]);
            emit(a, b, c, outward);
          } else {
            const Corner q0 = crossing(in[0], out[0]), q1 = crossing(in[0], out[1]),
                         q2 = crossing(in[1], out[1]), q3 = crossing(in[1], out[0]);
            emit(q0, q1, q2, outward);
            emit(q0, q2, q3, outward);
          }
        }
      }
  return s;
}

}  // namespace cagewrap
