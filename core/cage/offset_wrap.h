// One closed surface around everything a triangle soup encloses, at a distance: the zero set of
// (distance to the soup - offset) outside the soup's solid, polygonized on a grid. Separate,
// overlapping or open pieces (a character modelled as segments) come out as a single closed
// 2-manifold that bridges gaps narrower than twice the offset. The paper's "polygonize and weld
// the character's pieces" (section 5, step 1) for skins that are not one closed surface.
//
// Inside/outside comes from a flood fill of the grid from its border: the solid is everything the
// fill cannot reach through the grid samples within the offset of the sampled skin, so holes
// smaller than a grid cell are sealed.
#pragma once

#include <span>

#include <glm/vec3.hpp>

#include "core/geometry/marching_tetrahedra.h"
#include "core/geometry/mesh.h"

namespace cagewrap {

// positions #V x 3, triangles #T x 3; offset > 0 and cell > 0 in scene units. The cell is reduced
// to the offset when larger (the fill must not cross the soup between two grid samples). Samples
// exactly on the offset are nudged off it, so the result is closed and manifold.
IsoSurface offset_wrap(std::span<const glm::vec3> positions, std::span<const Tri> triangles, double offset,
                       double cell);

}  // namespace cagewrap
