// Two legs side by side: the smallest scene where the paper's Figure 5 happens (the cage of one leg
// reaches the skin of the other), with part labels, symmetric across x = 0.
#pragma once

#include <cmath>
#include <vector>

#include "core/cage/cage.h"
#include "core/geometry/mesh.h"
#include "core/deform/registration.h"

namespace cagewrap::fixtures {

// A closed tube along +y centred on (cx, *, 0): `around` x `along` quads split into triangles, capped.
inline PolyMesh leg_skin(double cx, double radius = 0.5, double length = 3.0, int around = 24,
                         int along = 30) {
  PolyMesh m;
  for (int j = 0; j <= along; ++j)
    for (int i = 0; i < around; ++i) {
      double a = 2 * M_PI * i / around;
      m.positions.emplace_back(cx + radius * std::cos(a), length * j / along, radius * std::sin(a));
    }
  auto at = [&](int i, int j) { return static_cast<uint32_t>(j * around + (i % around)); };
  for (int j = 0; j < along; ++j)
    for (int i = 0; i < around; ++i) {
      m.add_face({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
      m.add_face({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
    }
  uint32_t c0 = static_cast<uint32_t>(m.positions.size());
  m.positions.emplace_back(cx, 0, 0);
  m.positions.emplace_back(cx, length, 0);
  for (int i = 0; i < around; ++i) {
    m.add_face({c0, at(i, 0), at(i + 1, 0)});
    m.add_face({c0 + 1, at(i + 1, along), at(i, along)});
  }
  return m;
}

// An octagonal prism along +y around (cx, *, 0): quads along, octagon caps.
inline PolyMesh leg_cage(double cx, double radius = 0.6, double y0 = -0.2, double y1 = 3.2, int rings = 6,
                         int sides = 8) {
  PolyMesh m;
  for (int j = 0; j < rings; ++j)
    for (int i = 0; i < sides; ++i) {
      double a = 2 * M_PI * (i + 0.5) / sides;
      m.positions.emplace_back(cx + radius * std::cos(a), y0 + (y1 - y0) * j / (rings - 1),
                               radius * std::sin(a));
    }
  auto at = [&](int i, int j) { return static_cast<uint32_t>(j * sides + (i % sides)); };
  for (int j = 0; j + 1 < rings; ++j)
    for (int i = 0; i < sides; ++i) m.add_face({at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)});
  std::vector<uint32_t> cap0, cap1;
  for (int i = 0; i < sides; ++i) cap0.push_back(at(i, 0));
  for (int i = sides - 1; i >= 0; --i) cap1.push_back(at(i, rings - 1));
  m.add_face(cap0);
  m.add_face(cap1);
  return m;
}

inline PolyMesh joined(const PolyMesh& a, const PolyMesh& b) {
  PolyMesh m = a;
  const auto base = static_cast<uint32_t>(a.positions.size());
  m.positions.insert(m.positions.end(), b.positions.begin(), b.positions.end());
  for (size_t f = 0; f < b.num_faces(); ++f) {
    std::vector<uint32_t> c;
    for (uint32_t v : b.face(f)) c.push_back(v + base);
    m.add_face(c);
  }
  return m;
}

struct TwoLegs {
  PolyMesh skin;      // left leg (x < 0) points first, then the right leg
  Cage cage;          // left prism's faces first
  PartLabels labels;  // 0 = hips (root), 1 = left leg, 2 = right leg
  uint32_t left_points = 0, left_vertices = 0;
  size_t left_faces = 0;
};

// Legs 1.3 apart (skins 0.3 apart, cages 0.1 apart): without separation the points on the inside of one
// leg take elements of the other's cage.
inline TwoLegs two_legs(double half_spacing = 0.65) {
  TwoLegs t;
  PolyMesh left = leg_skin(-half_spacing), right = leg_skin(half_spacing);
  t.left_points = static_cast<uint32_t>(left.num_vertices());
  t.skin = joined(left, right);
  PolyMesh lc = leg_cage(-half_spacing), rc = leg_cage(half_spacing);
  t.left_vertices = static_cast<uint32_t>(lc.num_vertices());
  t.left_faces = lc.num_faces();
  t.cage = std::move(make_cage(joined(lc, rc), "two legs")).value();
  t.labels.parent = {-1, 0, 0};
  for (uint32_t i = 0; i < t.skin.num_vertices(); ++i) t.labels.point.push_back(i < t.left_points ? 1 : 2);
  for (uint32_t v = 0; v < t.cage.num_vertices(); ++v)
    t.labels.cage_vertex.push_back(v < t.left_vertices ? 1 : 2);
  return t;
}

}  // namespace cagewrap::fixtures
