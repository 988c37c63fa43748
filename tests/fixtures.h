// Generated test geometry: skins, cages and cage poses with known answers.
#pragma once

#include <cmath>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat3x3.hpp>

#include "core/deform/binding.h"
#include "core/cage/cage.h"
#include "core/geometry/mesh.h"

namespace cagewrap::fixtures {

// Set edits that empty the set of every `every`-th of `points` skin points ("only these elements", and
// none named), so that those points follow their nearest valid element rigidly (the fallback).
inline std::vector<SetEdit> empty_set_edits(size_t points, size_t every) {
  std::vector<SetEdit> edits;
  for (size_t i = 0; i < points; i += every) edits.push_back({static_cast<uint32_t>(i), {}, {}, true});
  return edits;
}

// Closed capped cylinder along +x from 0 to length, `around` x `along` quads split into triangles.
inline PolyMesh cylinder_skin(double radius = 0.5, double length = 4.0, int around = 32, int along = 40) {
  PolyMesh m;
  for (int j = 0; j <= along; ++j)
    for (int i = 0; i < around; ++i) {
      double a = 2 * M_PI * i / around;
      m.positions.emplace_back(length * j / along, radius * std::cos(a), radius * std::sin(a));
    }
  auto at = [&](int i, int j) { return static_cast<uint32_t>(j * around + (i % around)); };
  for (int j = 0; j < along; ++j)
    for (int i = 0; i < around; ++i) {
      m.add_face({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      m.add_face({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  uint32_t c0 = static_cast<uint32_t>(m.positions.size());
  m.positions.emplace_back(0, 0, 0);
  uint32_t c1 = c0 + 1;
  m.positions.emplace_back(length, 0, 0);
  for (int i = 0; i < around; ++i) {
    m.add_face({c0, at(i + 1, 0), at(i, 0)});
    m.add_face({c1, at(i, along), at(i + 1, along)});
  }
  return m;
}

// A coarse closed octagonal prism around the cylinder: quads along, octagons as end caps (polygons
// that the cage triangulates internally).
inline Cage cylinder_cage(double radius = 0.8, double x0 = -0.3, double x1 = 4.3, int rings = 6, int sides = 8) {
  PolyMesh m;
  for (int j = 0; j < rings; ++j)
    for (int i = 0; i < sides; ++i) {
      double a = 2 * M_PI * (i + 0.5) / sides;
      m.positions.emplace_back(x0 + (x1 - x0) * j / (rings - 1), radius * std::cos(a), radius * std::sin(a));
    }
  auto at = [&](int i, int j) { return static_cast<uint32_t>(j * sides + (i % sides)); };
  for (int j = 0; j + 1 < rings; ++j)
    for (int i = 0; i < sides; ++i) m.add_face({at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
  std::vector<uint32_t> cap0, cap1;
  for (int i = sides - 1; i >= 0; --i) cap0.push_back(at(i, 0));
  for (int i = 0; i < sides; ++i) cap1.push_back(at(i, rings - 1));
  m.add_face(cap0);
  m.add_face(cap1);
  return std::move(make_cage(std::move(m), "cylinder cage")).value();
}

// UV sphere (poles shared), radius r, centred at the origin.
inline PolyMesh sphere_skin(double r = 0.6, int rings = 16, int segments = 32) {
  PolyMesh m;
  m.positions.emplace_back(0, r, 0);
  for (int j = 1; j < rings; ++j)
    for (int i = 0; i < segments; ++i) {
      double t = M_PI * j / rings, p = 2 * M_PI * i / segments;
      m.positions.emplace_back(r * std::sin(t) * std::cos(p), r * std::cos(t), r * std::sin(t) * std::sin(p));
    }
  uint32_t south = static_cast<uint32_t>(m.positions.size());
  m.positions.emplace_back(0, -r, 0);
  auto at = [&](int i, int j) { return static_cast<uint32_t>(1 + (j - 1) * segments + (i % segments)); };
  for (int i = 0; i < segments; ++i) m.add_face({0, at(i + 1, 1), at(i, 1)});
  for (int j = 1; j + 1 < rings; ++j)
    for (int i = 0; i < segments; ++i) m.add_face({at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
  for (int i = 0; i < segments; ++i) m.add_face({south, at(i, rings - 1), at(i + 1, rings - 1)});
  return m;
}

// Axis-aligned cube [-s, s]^3, each side split into n x n quads, shared vertices, outward faces.
inline Cage box_cage(double s = 1.0, int n = 2) {
  PolyMesh m;
  std::vector<glm::vec3> verts;
  auto index_of = [&](glm::vec3 p) {
    for (size_t i = 0; i < m.positions.size(); ++i)
      if (glm::length(m.positions[i] - p) < 1e-6f) return static_cast<uint32_t>(i);
    m.positions.push_back(p);
    return static_cast<uint32_t>(m.positions.size() - 1);
  };
  for (int axis = 0; axis < 3; ++axis)
    for (int sign = -1; sign <= 1; sign += 2) {
      int u = (axis + 1) % 3, v = (axis + 2) % 3;
      auto corner = [&](int a, int b) {
        glm::vec3 p(0.f);
        p[axis] = static_cast<float>(sign * s);
        p[u] = static_cast<float>(-s + 2 * s * a / n);
        p[v] = static_cast<float>(-s + 2 * s * b / n);
        return index_of(p);
      };
      for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) {
          uint32_t q[4] = {corner(a, b), corner(a + 1, b), corner(a + 1, b + 1), corner(a, b + 1)};
          if (sign > 0) m.add_face({q[0], q[1], q[2], q[3]});
          else m.add_face({q[0], q[3], q[2], q[1]});
        }
    }
  return std::move(make_cage(std::move(m), "box cage")).value();
}

inline std::vector<glm::vec3> transformed(std::span<const glm::vec3> pts, const glm::dmat3& m, const glm::dvec3& t) {
  std::vector<glm::vec3> out(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) out[i] = glm::vec3(m * glm::dvec3(pts[i]) + t);
  return out;
}

inline glm::dmat3 rotation(double degrees, glm::dvec3 axis) {
  return glm::dmat3(glm::rotate(glm::dmat4(1.0), glm::radians(degrees), glm::normalize(axis)));
}

// Bends everything with x > pivot about the z axis through (pivot, 0, 0) by `degrees`.
inline std::vector<glm::vec3> bent(std::span<const glm::vec3> pts, double pivot, double degrees) {
  glm::dmat3 r = rotation(degrees, {0, 0, 1});
  std::vector<glm::vec3> out(pts.begin(), pts.end());
  for (auto& p : out)
    if (p.x > pivot) p = glm::vec3(glm::dvec3(pivot, 0, 0) + r * (glm::dvec3(p) - glm::dvec3(pivot, 0, 0)));
  return out;
}

inline double max_distance(std::span<const glm::vec3> a, std::span<const glm::vec3> b) {
  double m = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    double d = glm::length(glm::dvec3(a[i]) - glm::dvec3(b[i]));
    if (!std::isfinite(d)) return INFINITY;  // a NaN must never hide behind std::max
    m = std::max(m, d);
  }
  return m;
}

}  // namespace cagewrap::fixtures
