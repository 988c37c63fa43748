// A half-line, for ray casts (core/geometry/triangle_bvh.h) and picking (app/workspace/picking.h).
#pragma once

#include <glm/vec3.hpp>

namespace cagewrap {

// A half-line: origin + t * direction, t >= 0; direction has unit length.
struct Ray {
  glm::dvec3 origin{0.0};
  glm::dvec3 direction{0.0, 0.0, -1.0};
  glm::dvec3 at(double t) const { return origin + t * direction; }
};

}  // namespace cagewrap
