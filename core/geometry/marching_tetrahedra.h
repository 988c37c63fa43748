// Iso-surface of a scalar field sampled on a regular grid, by marching tetrahedra: each cube is
// split into the six Kuhn (Freudenthal) tetrahedra around its main diagonal, so neighbouring cubes
// share their face diagonals and the surface is a closed 2-manifold wherever no sample lies
// exactly on the iso-value (samples equal to it count as outside).
//
// This work is based on: Bloomenthal, "Polygonization of Implicit Surfaces" (CAGD 1988).
#pragma once

#include <array>
#include <cstddef>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "core/geometry/mesh.h"

namespace cagewrap {

struct Grid3 {
  std::array<int, 3> size{0, 0, 0};  // samples along x, y, z
  glm::dvec3 origin{0.0};            // position of sample (0, 0, 0)
  double spacing = 1.0;
  size_t count() const { return size_t(size[0]) * size[1] * size[2]; }
  size_t index(int x, int y, int z) const { return (size_t(z) * size[1] + y) * size[0] + x; }
  glm::dvec3 point(size_t i) const {
    const int x = int(i % size[0]), y = int((i / size[0]) % size[1]),
              z = int(i / (size_t(size[0]) * size[1]));
    return origin + spacing * glm::dvec3(x, y, z);
  }
};

struct IsoSurface {
  std::vector<glm::vec3> positions;  // #V, one per grid edge crossed
  std::vector<Tri> triangles;        // #T, facing where the field is larger than the iso-value
};

// values: grid.count() samples, x fastest. Inside is values < iso.
IsoSurface marching_tetrahedra(const Grid3& grid, std::span<const double> values, double iso = 0.0);

}  // namespace cagewrap
