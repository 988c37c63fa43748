// Tests for core/geometry/subdivide.h (uniform edge refinement used by the bench) and core/deform/twist.h (the analytic
// twist of the bench triplets and the fidelity measure against it).
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "core/geometry/subdivide.h"
#include "core/deform/twist.h"
#include "tests/expect_error.h"
#include "tests/test_assets.h"

namespace cagewrap {
namespace {

namespace fs = std::filesystem;

// ------------------------------------------------------------------------------------------ subdivide

PolyMesh tetrahedron() {  // closed, outward faces, non-equilateral
  PolyMesh m;
  m.positions = {{0.f, 0.f, 0.f}, {2.f, 0.f, 0.f}, {0.f, 1.5f, 0.f}, {0.3f, 0.2f, 1.f}};
  m.add_face({0, 2, 1});
  m.add_face({0, 1, 3});
  m.add_face({1, 2, 3});
  m.add_face({2, 0, 3});
  return m;
}

PolyMesh open_square() {  // two triangles, four boundary edges and one inner edge
  PolyMesh m;
  m.positions = {{0.f, 0.f, 0.f}, {1.f, 0.f, 0.f}, {1.f, 1.f, 0.5f}, {0.f, 1.f, 0.f}};
  m.add_face({0, 1, 2});
  m.add_face({0, 2, 3});
  return m;
}

glm::dvec3 pos(const PolyMesh& m, uint32_t v) { return glm::dvec3(m.positions[v]); }

glm::dvec3 face_cross(const PolyMesh& m, size_t f) {  // |.| = twice the area, direction = normal
  auto c = m.face(f);
  return glm::cross(pos(m, c[1]) - pos(m, c[0]), pos(m, c[2]) - pos(m, c[0]));
}

double total_area(const PolyMesh& m) {
  double a = 0;
  for (size_t f = 0; f < m.num_faces(); ++f) a += 0.5 * glm::length(face_cross(m, f));
  return a;
}

// Distance from p to the triangle abc (Ericson, Real-Time Collision Detection 5.1.5).
double distance_to_triangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
  double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return glm::length(p - a);
  glm::dvec3 bp = p - b;
  double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return glm::length(p - b);
  double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return glm::length(p - (a + ab * (d1 / (d1 - d3))));
  glm::dvec3 cp = p - c;
  double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return glm::length(p - c);
  double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return glm::length(p - (a + ac * (d2 / (d2 - d6))));
  double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return glm::length(p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))));
  double denom = 1.0 / (va + vb + vc);
  return glm::length(p - (a + ab * (vb * denom) + ac * (vc * denom)));
}

// Directed edge -> how many faces use it; undirected edge -> how many faces.
struct EdgeUse {
  std::map<std::pair<uint32_t, uint32_t>, int> directed, undirected;
};
EdgeUse edge_use(const PolyMesh& m) {
  EdgeUse u;
  for (size_t f = 0; f < m.num_faces(); ++f) {
    auto c = m.face(f);
    for (size_t i = 0; i < c.size(); ++i) {
      uint32_t a = c[i], b = c[(i + 1) % c.size()];
      ++u.directed[{a, b}];
      ++u.undirected[{std::min(a, b), std::max(a, b)}];
    }
  }
  return u;
}

struct Counts {
  size_t v, e, t;
};

void check_subdivision(const PolyMesh& in, Counts k, bool closed) {
  const double area = total_area(in);
  for (uint32_t n = 0; n <= 4; ++n) {
    SCOPED_TRACE("n = " + std::to_string(n));
    PolyMesh out = subdivide_edges_uniform(in, n);
    const size_t m = n, interior = m == 0 ? 0 : m * (m - 1) / 2;  // new points inside each triangle
    EXPECT_EQ(out.num_vertices(), k.v + k.e * m + k.t * interior);
    EXPECT_EQ(out.num_faces(), k.t * (m + 1) * (m + 1));
    EXPECT_TRUE(out.all_triangles());
    EXPECT_TRUE(validate_mesh(out, "subdivided").ok());
    // the original vertices keep their indices and positions
    for (size_t v = 0; v < in.num_vertices(); ++v) EXPECT_EQ(out.positions[v], in.positions[v]) << "vertex " << v;

    // connectivity: no cracks, no doubled edges, orientation kept (each directed edge at most once)
    EdgeUse u = edge_use(out);
    size_t boundary = 0;
    for (const auto& [e, count] : u.undirected) {
      EXPECT_TRUE(count == 1 || count == 2) << "edge " << e.first << "-" << e.second << " has " << count << " faces";
      if (count == 1) ++boundary;
    }
    for (const auto& [e, count] : u.directed) EXPECT_EQ(count, 1) << "directed edge " << e.first << "-" << e.second;
    if (closed) {
      EXPECT_EQ(boundary, 0u);
    } else {
      EXPECT_EQ(boundary, 4u * (n + 1));  // the open square's four sides, each cut into n + 1
    }
    // Euler: V - E + F is unchanged by refinement
    EXPECT_EQ(long(out.num_vertices()) - long(u.undirected.size()) + long(out.num_faces()),
              long(k.v) - long(k.e) + long(k.t));

    // geometry: every point on the input surface, every face inside one input triangle with the same
    // orientation, and no area gained or lost
    for (size_t v = 0; v < out.num_vertices(); ++v) {
      double best = 1e300;
      for (size_t f = 0; f < in.num_faces(); ++f) {
        auto c = in.face(f);
        best = std::min(best, distance_to_triangle(pos(out, uint32_t(v)), pos(in, c[0]), pos(in, c[1]), pos(in, c[2])));
      }
      EXPECT_LT(best, 1e-6) << "vertex " << v << " is off the surface";
    }
    for (size_t f = 0; f < out.num_faces(); ++f) {
      auto c = out.face(f);
      bool inside_one = false;
      for (size_t g = 0; g < in.num_faces() && !inside_one; ++g) {
        auto t = in.face(g);
        bool all = true;
        for (uint32_t v : c)
          all = all && distance_to_triangle(pos(out, v), pos(in, t[0]), pos(in, t[1]), pos(in, t[2])) < 1e-6;
        inside_one = all && glm::dot(face_cross(out, f), face_cross(in, g)) > 0;
      }
      EXPECT_TRUE(inside_one) << "face " << f << " is not inside one input triangle with its orientation";
      EXPECT_GT(glm::length(face_cross(out, f)), 0.0) << "face " << f << " is degenerate";
    }
    EXPECT_NEAR(total_area(out), area, 1e-6 * area);
  }
}

TEST(SubdivideEdgesUniform, ClosedTetrahedronStaysClosedAndOnTheSurface) {
  check_subdivision(tetrahedron(), {4, 6, 4}, true);
}

TEST(SubdivideEdgesUniform, OpenSquareKeepsItsBoundary) { check_subdivision(open_square(), {4, 5, 2}, false); }

TEST(SubdivideEdgesUniform, PolygonsAreTriangulatedFirst) {
  PolyMesh quad;
  quad.positions = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {0, 1, 0}};
  quad.add_face({0, 1, 2, 3});
  PolyMesh n0 = subdivide_edges_uniform(quad, 0);
  EXPECT_EQ(n0.num_faces(), 2u);
  EXPECT_EQ(n0.num_vertices(), 4u);
  PolyMesh n2 = subdivide_edges_uniform(quad, 2);
  EXPECT_EQ(n2.num_faces(), 2u * 9u);
  EXPECT_EQ(n2.num_vertices(), 4u + 5u * 2u + 2u * 1u);  // the diagonal is cut too
  EXPECT_NEAR(total_area(n2), 2.0, 1e-6);
}

TEST(SubdivideEdgesUniform, EdgePointsAreEvenlySpaced) {
  PolyMesh m = open_square();
  const uint32_t n = 3;
  PolyMesh out = subdivide_edges_uniform(m, n);
  // the points on the side 0-1 (y = 0, z = 0) are at x = 1/4, 2/4, 3/4
  std::vector<float> xs;
  for (const auto& p : out.positions)
    if (p.y == 0.f && p.z == 0.f && p.x > 0.f && p.x < 1.f) xs.push_back(p.x);
  std::sort(xs.begin(), xs.end());
  ASSERT_EQ(xs.size(), n);
  for (uint32_t j = 0; j < n; ++j) EXPECT_FLOAT_EQ(xs[j], float(j + 1) / (n + 1));
}

// ------------------------------------------------------------------------------------------ twist

// Angle of p about the axis through `center`, in the plane (i, j) = ((axis+1)%3, (axis+2)%3).
double angle_about(const Twist& t, const glm::dvec3& p) {
  int i = (t.axis + 1) % 3, j = (t.axis + 2) % 3;
  return std::atan2(p[j] - t.center[j], p[i] - t.center[i]);
}
double radius_about(const Twist& t, const glm::dvec3& p) {
  int i = (t.axis + 1) % 3, j = (t.axis + 2) % 3;
  return std::hypot(p[i] - t.center[i], p[j] - t.center[j]);
}
double wrap_degrees(double d) {  // to (-180, 180]
  d = std::fmod(d, 360.0);
  if (d > 180) d -= 360;
  if (d <= -180) d += 360;
  return d;
}

// Samples around the axis: various radii and angles, at a given axial coordinate.
std::vector<glm::dvec3> ring_samples(const Twist& t, double along) {
  std::vector<glm::dvec3> out;
  int i = (t.axis + 1) % 3, j = (t.axis + 2) % 3;
  for (double r : {0.05, 0.3, 1.7})
    for (int k = 0; k < 7; ++k) {
      double a = 2 * M_PI * k / 7 + 0.1;
      glm::dvec3 p = t.center;
      p[t.axis] = along;
      p[i] += r * std::cos(a);
      p[j] += r * std::sin(a);
      out.push_back(p);
    }
  return out;
}

void check_twist_profile(const Twist& t) {
  const double span = t.hi - t.lo;
  // at or below lo: identity
  for (double along : {t.lo - 2 * span, t.lo - 1e-3, t.lo})
    for (const auto& p : ring_samples(t, along)) {
      glm::dvec3 q = t.apply(p);
      EXPECT_NEAR(glm::length(q - p), 0.0, 1e-12) << "at " << along;
    }
  // at or above hi: a rotation by exactly `degrees` about the axis
  for (double along : {t.hi, t.hi + 1e-3, t.hi + 3 * span})
    for (const auto& p : ring_samples(t, along)) {
      glm::dvec3 q = t.apply(p);
      EXPECT_EQ(q[t.axis], p[t.axis]);
      EXPECT_NEAR(radius_about(t, q), radius_about(t, p), 1e-12);
      EXPECT_NEAR(wrap_degrees((angle_about(t, q) - angle_about(t, p)) * 180 / M_PI), wrap_degrees(t.degrees), 1e-9)
          << "at " << along;
    }
  // half way: the smoothstep profile gives half the angle; in between the angle grows monotonically
  double last = -1;
  for (int k = 0; k <= 20; ++k) {
    double along = t.lo + span * k / 20.0;
    glm::dvec3 p = ring_samples(t, along)[3];
    glm::dvec3 q = t.apply(p);
    EXPECT_EQ(q[t.axis], p[t.axis]);
    EXPECT_NEAR(radius_about(t, q), radius_about(t, p), 1e-12);
    double turned = std::abs(wrap_degrees((angle_about(t, q) - angle_about(t, p)) * 180 / M_PI));
    EXPECT_GE(turned, last - 1e-12) << "at " << along;
    last = turned;
    if (k == 10) {
      EXPECT_NEAR(turned, std::abs(wrap_degrees(t.degrees)) / 2, 1e-9);
    }
    double s = k / 20.0;
    EXPECT_NEAR(turned, std::abs(wrap_degrees(t.degrees)) * s * s * (3 - 2 * s), 1e-9) << "at " << along;
  }
}

TEST(Twist, HandMadeTwistOnEveryAxis) {
  for (int axis = 0; axis < 3; ++axis) {
    SCOPED_TRACE("axis " + std::to_string(axis));
    Twist t;
    t.axis = axis;
    t.center = {0.25, -1.0, 2.0};
    t.lo = -0.5;
    t.hi = 1.5;
    t.degrees = 75;
    check_twist_profile(t);
  }
}

// Positive degrees turn the (axis+1) direction towards the (axis+2) direction (right-handed).
TEST(Twist, PositiveAngleIsRightHanded) {
  Twist t;
  t.axis = 1;  // about y: z turns towards x
  t.center = {0, 0, 0};
  t.lo = 0;
  t.hi = 1;
  t.degrees = 90;
  glm::dvec3 q = t.apply({0, 2, 1});
  EXPECT_NEAR(q.x, 1, 1e-12);
  EXPECT_NEAR(q.y, 2, 1e-12);
  EXPECT_NEAR(q.z, 0, 1e-12);
}

std::string write_twist_text(const std::string& name, const std::string& text) {
  fs::path p = fs::temp_directory_path() / ("cagewrap-twist-" + std::to_string(::getpid()) + "-" + name);
  std::ofstream(p) << text;
  return p.string();
}

TEST(Twist, LoadsTheBenchInputs) {
  CAGEWRAP_REQUIRE_ASSETS(assets);
  int found = 0;
  for (const char* asset : {"mannequiny", "armadillo"}) {
    const std::string path = assets + "/bench/" + asset + "/inputs.json";
    if (!fs::exists(path)) continue;
    ++found;
    SCOPED_TRACE(path);
    auto t = load_twist(path);
    ASSERT_TRUE(t.ok()) << t.error().message;
    std::ifstream in(path);
    auto j = nlohmann::json::parse(in)["twist"];
    EXPECT_EQ(t->axis, j["axis"].get<int>());
    for (int k = 0; k < 3; ++k) EXPECT_EQ(t->center[k], j["center"][k].get<double>());
    EXPECT_EQ(t->lo, j["lo"].get<double>());
    EXPECT_EQ(t->hi, j["hi"].get<double>());
    EXPECT_EQ(t->degrees, j["twist_deg"].get<double>());
    check_twist_profile(*t);
  }
  if (found == 0) GTEST_SKIP() << "no bench inputs.json under " << assets << "/bench";
}

TEST(Twist, LoadErrorsNameTheFile) {
  const std::string missing = (fs::temp_directory_path() / "cagewrap-no-such-inputs.json").string();
  EXPECT_TRUE(Fails(load_twist(missing), ErrorCode::kFileNotFound, {missing}));

  const std::string no_twist = write_twist_text("no_twist.json", R"({"base": {"verts": 3}})");
  EXPECT_TRUE(Fails(load_twist(no_twist), ErrorCode::kParse, {no_twist, "twist"}));

  const std::string no_hi = write_twist_text("no_hi.json", R"({"twist": {"axis": 1, "center": [0, 0, 0], "lo": 0, "twist_deg": 60}})");
  EXPECT_TRUE(Fails(load_twist(no_hi), ErrorCode::kParse, {no_hi, "hi"}));

  const std::string bad_axis =
      write_twist_text("bad_axis.json", R"({"twist": {"axis": 3, "center": [0, 0, 0], "lo": 0, "hi": 1, "twist_deg": 60}})");
  EXPECT_TRUE(Fails(load_twist(bad_axis), ErrorCode::kParse, {bad_axis, "axis"}));

  const std::string empty_range =
      write_twist_text("empty_range.json", R"({"twist": {"axis": 0, "center": [0, 0, 0], "lo": 1, "hi": 1, "twist_deg": 60}})");
  EXPECT_TRUE(Fails(load_twist(empty_range), ErrorCode::kParse, {empty_range, "lo, hi"}));

  const std::string not_json = write_twist_text("not_json.json", "twist: yes\n");
  EXPECT_TRUE(Fails(load_twist(not_json), ErrorCode::kParse, {not_json}));

  for (const auto& p : {no_twist, no_hi, bad_axis, empty_range, not_json}) fs::remove(p);
}

// ------------------------------------------------------------------------------------------ fidelity

TEST(RelativeDistance, KnownRmsAndMax) {
  // distances 0, 5, 3, 4: RMS sqrt(50 / 4), max 5
  std::vector<glm::vec3> a = {{0, 0, 0}, {1, 1, 1}, {2, 0, 0}, {0, 0, 0}};
  std::vector<glm::vec3> b = {{0, 0, 0}, {1, 4, 5}, {2, 0, 3}, {0, -4, 0}};
  Fidelity f = relative_distance(a, b, 2.0);
  EXPECT_DOUBLE_EQ(f.rms, std::sqrt(12.5) / 2.0);
  EXPECT_DOUBLE_EQ(f.max, 2.5);
  Fidelity g = relative_distance(b, a, 1.0);  // symmetric, scales with 1 / diagonal
  EXPECT_DOUBLE_EQ(g.rms, std::sqrt(12.5));
  EXPECT_DOUBLE_EQ(g.max, 5.0);
}

TEST(RelativeDistance, IdenticalAndEmptySetsAreZero) {
  std::vector<glm::vec3> a = {{1, 2, 3}, {-4, 5, 6}};
  Fidelity f = relative_distance(a, a, 3.0);
  EXPECT_EQ(f.rms, 0.0);
  EXPECT_EQ(f.max, 0.0);
  Fidelity e = relative_distance({}, {}, 1.0);
  EXPECT_EQ(e.rms, 0.0);
  EXPECT_EQ(e.max, 0.0);
}

TEST(RelativeDistance, OneOutlierAmongMany) {
  // 99 exact points and one off by 10: RMS = 10 / sqrt(100) = 1, max = 10
  std::vector<glm::vec3> a(100, glm::vec3(0.5f)), b = a;
  b[37] += glm::vec3(6, 8, 0);
  Fidelity f = relative_distance(a, b, 1.0);
  EXPECT_NEAR(f.rms, 1.0, 1e-6);
  EXPECT_NEAR(f.max, 10.0, 1e-6);
}

}  // namespace
}  // namespace cagewrap
