// Small exact geometric kernels in double precision.
#pragma once

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace cagewrap {

struct ClosestPoint {
  glm::dvec3 point;
  glm::dvec3 bary;  // barycentric coordinates of `point` in (A, B, C)
  double dist2;
};

// Closest point of triangle ABC to P (Ericson, Real-Time Collision Detection, 5.1.5).
inline ClosestPoint closest_point_on_triangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                                              const glm::dvec3& c) {
  using glm::dot;
  auto make = [&](double u, double v, double w) {
    glm::dvec3 q = u * a + v * b + w * c;
    glm::dvec3 d = p - q;
    return ClosestPoint{q, {u, v, w}, dot(d, d)};
  };
  glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
  double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return make(1, 0, 0);
  glm::dvec3 bp = p - b;
  double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return make(0, 1, 0);
  double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    double v = d1 / (d1 - d3);
    return make(1 - v, v, 0);
  }
  glm::dvec3 cp = p - c;
  double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return make(0, 0, 1);
  double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    double w = d2 / (d2 - d6);
    return make(1 - w, 0, w);
  }
  double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return make(0, 1 - w, w);
  }
  double denom = 1.0 / (va + vb + vc);
  double v = vb * denom, w = vc * denom;
  return make(1 - v - w, v, w);
}

// Barycentric coordinates of the projection of P on the plane of ABC (may be outside [0,1]).
inline glm::dvec3 plane_barycentric(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                                    const glm::dvec3& c) {
  glm::dvec3 e1 = b - a, e2 = c - a, d = p - a;
  double d11 = glm::dot(e1, e1), d12 = glm::dot(e1, e2), d22 = glm::dot(e2, e2);
  double r1 = glm::dot(d, e1), r2 = glm::dot(d, e2);
  double det = d11 * d22 - d12 * d12;
  double u = (d22 * r1 - d12 * r2) / det, v = (d11 * r2 - d12 * r1) / det;
  return {1 - u - v, u, v};
}

}  // namespace cagewrap
