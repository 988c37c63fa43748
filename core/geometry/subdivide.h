// Uniform refinement of a triangle mesh for scale tests: every edge cut n times, each triangle split
// into (n+1)^2 triangles. Edge points are shared, so the result is as connected as the input.
#pragma once

#include "core/geometry/mesh.h"

namespace cagewrap {

// Non-triangle faces are triangulated first. n = 0 returns the triangulated mesh.
PolyMesh subdivide_edges_uniform(const PolyMesh& mesh, uint32_t n);

}  // namespace cagewrap
