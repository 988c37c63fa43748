// Properties of the surface-oriented deformer (algorithm.md, "Properties to test"), for every variant,
// on generated fixtures and, when present, the real bench triplets.
#include <gtest/gtest.h>

#include <cstdio>

#include <Eigen/Dense>

#include "core/deform/deformer.h"
#include "core/geometry/geometry.h"
#include "core/geometry/mesh_io.h"
#include "core/deform/registration.h"
#include "tests/fixtures.h"
#include "tests/test_assets.h"

namespace cagewrap {
namespace {

using fixtures::max_distance;

struct Scene {
  std::string name;
  PolyMesh skin;
  Cage cage;
};

Scene arm() { return {"arm", fixtures::cylinder_skin(), fixtures::cylinder_cage()}; }
Scene ball() { return {"ball", fixtures::sphere_skin(), fixtures::box_cage()}; }
// A cube of 6 quads: every vertex's one-ring spans 3-D (the 2 x 2 box has flat face-centre vertices).
Scene coarse_ball() { return {"coarse ball", fixtures::sphere_skin(), fixtures::box_cage(1.0, 1)}; }

std::vector<glm::vec3> deform_with(const Binding& b, std::span<const glm::vec3> skin, std::span<const glm::vec3> posed,
                                   std::span<const glm::dmat3> frames = {}) {
  auto d = Deformer::create(b, skin);
  EXPECT_TRUE(d.ok()) << (d.ok() ? "" : d.error().message);
  std::vector<glm::vec3> out(skin.size(), glm::vec3(NAN));
  auto s = d->deform(posed, out, frames);
  EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().message);
  return out;
}

Binding bind_or_die(const Scene& s, BindParams p, std::span<const SetEdit> edits = {}) {
  auto b = bind_skin(s.skin.positions, s.cage, s.cage.polygons.positions, p, edits);
  EXPECT_TRUE(b.ok()) << (b.ok() ? "" : b.error().message);
  return std::move(b).value();
}

class EveryVariant : public ::testing::TestWithParam<std::tuple<Variant, int>> {
 protected:
  Scene scene() const { return std::get<1>(GetParam()) == 0 ? arm() : ball(); }
  BindParams params() const {
    BindParams p;
    p.variant = std::get<0>(GetParam());
    return p;
  }
};

// 1. Binding does not move the skin.
TEST_P(EveryVariant, RestCageReproducesSkin) {
  Scene s = scene();
  Binding b = bind_or_die(s, params());
  auto out = deform_with(b, s.skin.positions, s.cage.polygons.positions);
  double diag = bounding_box(s.skin.positions).diagonal();
  EXPECT_LE(max_distance(out, s.skin.positions), 1e-5 * diag);
}

// 2. Rotations and translations of the whole driver are imparted exactly.
TEST_P(EveryVariant, RigidMotionMovesSkinRigidly) {
  Scene s = scene();
  Binding b = bind_or_die(s, params());
  glm::dmat3 r = fixtures::rotation(70, {1, 2, 3});
  glm::dvec3 t(5, -2, 1);
  auto posed = fixtures::transformed(s.cage.polygons.positions, r, t);
  auto expected = fixtures::transformed(s.skin.positions, r, t);
  auto out = deform_with(b, s.skin.positions, posed);
  double diag = bounding_box(s.skin.positions).diagonal();
  EXPECT_LE(max_distance(out, expected), 1e-5 * diag);
}

// 5. Weights in each set sum to one, sets have at most K members, more only where the (K+1)-th nearest
// element nearly ties the nearest (the tie band of registration.h Taper).
TEST_P(EveryVariant, WeightsSumToOneAndSetsAreBounded) {
  Scene s = scene();
  BindParams p = params();
  p.max_elements = 5;
  Binding b = bind_or_die(s, p);
  ASSERT_EQ(b.offsets.size(), s.skin.num_vertices() + 1);
  size_t over_k = 0;
  for (size_t i = 0; i < b.num_points; ++i) {
    double sum = 0;
    for (uint32_t e = b.offsets[i]; e < b.offsets[i + 1]; ++e) {
      EXPECT_GE(b.weights[e], 0.f);
      sum += b.weights[e];
    }
    if (b.offsets[i + 1] > b.offsets[i]) {
      EXPECT_NEAR(sum, 1.0, 1e-6) << "point " << i;
    }
    if (p.variant != Variant::kExtended) {
      EXPECT_LE(b.offsets[i + 1] - b.offsets[i], kMaxTiedMembers);
      if (b.offsets[i + 1] - b.offsets[i] > p.max_elements) {  // more than K: only elements in the tie band
        glm::dvec3 P(s.skin.positions[i]);
        std::vector<double> d;
        for (uint32_t e = b.offsets[i]; e < b.offsets[i + 1]; ++e) {
          const Tri& t = b.elements[b.ids[e]];
          const auto& c = s.cage.polygons.positions;
          d.push_back(std::sqrt(
              closest_point_on_triangle(P, glm::dvec3(c[t[0]]), glm::dvec3(c[t[1]]), glm::dvec3(c[t[2]])).dist2));
        }
        const double d1 = *std::min_element(d.begin(), d.end());
        const double band = std::sqrt(tie_band2(p, b.h, d1 * d1));
        EXPECT_LE(*std::max_element(d.begin(), d.end()), band * (1 + 1e-9)) << "point " << i;
        ++over_k;
      }
    }
  }
  EXPECT_LE(b.max_set_size, kMaxTiedMembers);
  std::printf("%zu of %u points have more than K = %u elements (the tie band)\n", over_k, b.num_points, p.max_elements);
  EXPECT_GT(b.max_set_size, 1u) << "the fixture should give points several elements";
}

// 5. The hierarchy gives the same sets and weights as a loop over all elements.
TEST_P(EveryVariant, RegistrationEqualsBruteForce) {
  Scene s = scene();
  for (double eps : {0.02, 0.1, 0.5, 1.0}) {
    BindParams p = params();
    p.epsilon = eps;
    Binding fast = bind_or_die(s, p);
    auto slow = bind_skin_brute_force(s.skin.positions, s.cage, s.cage.polygons.positions, p);
    ASSERT_TRUE(slow.ok());
    EXPECT_EQ(fast.offsets, slow->offsets) << "epsilon " << eps;
    EXPECT_EQ(fast.ids, slow->ids) << "epsilon " << eps;
    EXPECT_EQ(fast.weights, slow->weights) << "epsilon " << eps;
    EXPECT_EQ(fast.bary, slow->bary) << "epsilon " << eps;
    EXPECT_EQ(fast.rigid_points, slow->rigid_points);
    EXPECT_EQ(fast.quality_inside, slow->quality_inside);
    // the points failing the quality test: as many as the figure misses, the same for both
    auto fast_failures = quality_failures(fast, s.skin.positions);
    auto slow_failures = quality_failures(*slow, s.skin.positions);
    ASSERT_TRUE(fast_failures.ok() && slow_failures.ok());
    EXPECT_EQ(fast_failures->size(), fast.num_points - fast.quality_inside) << "epsilon " << eps;
    EXPECT_EQ(*fast_failures, *slow_failures) << "epsilon " << eps;
    EXPECT_TRUE(std::is_sorted(fast_failures->begin(), fast_failures->end()));
  }
}

// 6. Continuity: points along a segment that crosses many element boundaries stay a continuous curve.
TEST_P(EveryVariant, DeformationIsContinuousAlongASegment) {
  Scene s = arm();
  Binding b = bind_or_die(s, params());
  const int n = 4000;
  std::vector<glm::vec3> line(n);
  glm::dvec3 a(0.1, 0.45, -0.2), z(3.9, -0.3, 0.45);  // inside the cage, crossing many elements' regions
  for (int i = 0; i < n; ++i) line[i] = glm::vec3(a + (z - a) * (double(i) / (n - 1)));
  Binding lb = bind_or_die({"line", PolyMesh{line, {0}, {}}, s.cage}, params());
  auto posed = fixtures::bent(s.cage.polygons.positions, 2.0, 60);
  auto out = deform_with(lb, line, posed);
  const double spacing = glm::length(z - a) / (n - 1);
  double worst = 0;
  for (int i = 0; i + 1 < n; ++i) worst = std::max(worst, double(glm::length(out[i + 1] - out[i])));
  // The 60-degree bend stretches the outside of the elbow (measured: up to 2.3x the spacing); a gap
  // beyond 3 spacings would be a tear, as the untapered weights gave (up to 72 spacings).
  EXPECT_LE(worst, 3.0 * spacing) << "largest gap " << worst / spacing << " sample spacings";
  RecordProperty("largest_gap_in_spacings", std::to_string(worst / spacing));
}

INSTANTIATE_TEST_SUITE_P(Deformer, EveryVariant,
                         ::testing::Combine(::testing::Values(Variant::kBasic, Variant::kClamped, Variant::kExtended),
                                            ::testing::Values(0, 1)),
                         [](const auto& info) {
                           return std::string(variant_name(std::get<0>(info.param))) +
                                  (std::get<1>(info.param) == 0 ? "_arm" : "_ball");
                         });

// Eq. 2 and 3 written out directly: local coordinates (a, b, c) in each element's frame on R, rebuilt
// on D, blended with the table's weights. The kernel's folded affine maps must agree.
TEST(DeformerReference, BasicAndClampedMatchEquationsTwoAndThree) {
  Scene s = arm();
  auto posed = fixtures::bent(s.cage.polygons.positions, 2.0, 45);
  for (size_t v = 0; v < posed.size(); ++v) posed[v] += glm::vec3(0.05f * std::sin(float(v)), 0.03f * std::cos(3.f * v), 0.f);
  const auto& rest = s.cage.polygons.positions;
  auto frame = [](const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    glm::dvec3 e1 = b - a, e2 = c - a, e3 = glm::normalize(glm::cross(e1, e2));
    Eigen::Matrix3d q;
    q << e1.x, e2.x, e3.x, e1.y, e2.y, e3.y, e1.z, e2.z, e3.z;
    return q;
  };
  for (Variant v : {Variant::kBasic, Variant::kClamped}) {
    BindParams p;
    p.variant = v;
    Binding b = bind_or_die(s, p);
    auto out = deform_with(b, s.skin.positions, posed);
    double worst = 0;
    for (size_t i = 0; i < b.num_points; ++i) {
      glm::dvec3 sum(0.0), P(s.skin.positions[i]);
      for (uint32_t e = b.offsets[i]; e < b.offsets[i + 1]; ++e) {
        const Tri& t = b.elements[b.ids[e]];
        glm::dvec3 A(rest[t[0]]), B(rest[t[1]]), C(rest[t[2]]);
        glm::dvec3 A2(posed[t[0]]), B2(posed[t[1]]), C2(posed[t[2]]);
        glm::dvec3 pk;
        if (v == Variant::kBasic) {
          Eigen::Vector3d d(P.x - A.x, P.y - A.y, P.z - A.z);
          Eigen::Vector3d l = frame(A, B, C).colPivHouseholderQr().solve(d);
          Eigen::Vector3d q = frame(A2, B2, C2) * l;
          pk = A2 + glm::dvec3(q.x(), q.y(), q.z());
        } else {
          ClosestPoint cp = closest_point_on_triangle(P, A, B, C);
          glm::dvec3 close2 = cp.bary.x * A2 + cp.bary.y * B2 + cp.bary.z * C2;
          // the rotation of the element's eq. 2 map (its polar decomposition), carried rigidly
          const Eigen::Matrix3d map = frame(A2, B2, C2) * frame(A, B, C).inverse();
          Eigen::JacobiSVD<Eigen::Matrix3d> svd(map, Eigen::ComputeFullU | Eigen::ComputeFullV);
          const Eigen::Matrix3d rot = svd.matrixU() * svd.matrixV().transpose();
          ASSERT_GT(rot.determinant(), 0.0);
          const glm::dvec3 off = P - cp.point;
          const Eigen::Vector3d r = rot * Eigen::Vector3d(off.x, off.y, off.z);
          pk = close2 + glm::dvec3(r.x(), r.y(), r.z());
        }
        sum += double(b.weights[e]) * pk;
      }
      worst = std::max(worst, glm::length(sum - glm::dvec3(out[i])));
    }
    EXPECT_LE(worst, 1e-5 * bounding_box(s.skin.positions).diagonal()) << variant_name(v);
  }
}

// Section 4.2: the basic variant scales in-plane under uniform scale but keeps the normal offset c.
TEST(DeformerBasic, UniformScaleKeepsNormalOffsets) {
  Scene s = ball();
  BindParams p;
  p.variant = Variant::kBasic;
  p.max_elements = 1;  // one element per point: c is that element's offset
  p.epsilon = 1.0;     // the nearest only (no tie band: points that tie keep one element by id)
  Binding b = bind_or_die(s, p);
  size_t single = 0;
  const double k = 2.0;
  auto posed = fixtures::transformed(s.cage.polygons.positions, glm::dmat3(k), glm::dvec3(0.0));
  auto out = deform_with(b, s.skin.positions, posed);
  double worst_c = 0, worst_plane = 0, moved = 0;
  for (size_t i = 0; i < b.num_points; ++i) {
    if (b.offsets[i + 1] - b.offsets[i] != 1u) continue;
    ++single;
    const Tri& t = b.elements[b.ids[b.offsets[i]]];
    glm::dvec3 A(s.cage.polygons.positions[t[0]]), B(s.cage.polygons.positions[t[1]]), C(s.cage.polygons.positions[t[2]]);
    glm::dvec3 n = glm::normalize(glm::cross(B - A, C - A));
    glm::dvec3 P(s.skin.positions[i]), Q(out[i]);
    double c = glm::dot(P - A, n), c2 = glm::dot(Q - k * A, n);
    worst_c = std::max(worst_c, std::abs(c2 - c));
    // the in-plane part scales by k
    worst_plane = std::max(worst_plane, glm::length((Q - c2 * n) - k * (P - c * n)));
    moved = std::max(moved, glm::length(Q - k * P));
  }
  EXPECT_GT(single, b.num_points / 2) << "most points have one element with K = 1";
  EXPECT_LE(worst_c, 1e-5);
  EXPECT_LE(worst_plane, 1e-5);
  EXPECT_GT(moved, 0.1) << "the basic variant must not reproduce the scale in the normal direction";
}

// 4. Extended variant: any affine map of a closed cage, shear and non-uniform scale included.
TEST(DeformerExtended, AffineMapsAreReproducedWithFittedAndSuppliedFrames) {
  glm::dmat3 m(1.2, 0.0, 0.2, 0.3, 0.8, 0.0, 0.0, 0.1, 1.5);  // columns: shear + non-uniform scale
  glm::dvec3 t(0.3, -1, 2);
  for (Scene s : {arm(), coarse_ball()}) {
    BindParams p;
    p.variant = Variant::kExtended;
    Binding b = bind_or_die(s, p);
    auto posed = fixtures::transformed(s.cage.polygons.positions, m, t);
    auto expected = fixtures::transformed(s.skin.positions, m, t);
    double diag = bounding_box(s.skin.positions).diagonal();
    auto fitted = deform_with(b, s.skin.positions, posed);
    EXPECT_LE(max_distance(fitted, expected), 1e-5 * diag) << s.name << " one-ring fit";
    std::vector<glm::dmat3> frames(s.cage.num_vertices(), m);
    auto supplied = deform_with(b, s.skin.positions, posed, frames);
    EXPECT_LE(max_distance(supplied, expected), 1e-5 * diag) << s.name << " supplied frames";
    // and the other variants do not (the property is the extended variant's own)
    p.variant = Variant::kBasic;
    Binding basic = bind_or_die(s, p);
    EXPECT_GT(max_distance(deform_with(basic, s.skin.positions, posed), expected), 1e-3 * diag) << s.name;
  }
}

// Extended variant against its definition: P_def_k = sum_i b_i F'_vi(local_i), blended by u_k.
TEST(DeformerExtended, MatchesVertexFrameDefinition) {
  Scene s = ball();
  const auto& rest = s.cage.polygons.positions;
  std::vector<glm::vec3> posed(rest.begin(), rest.end());
  std::vector<glm::dmat3> frames(rest.size());
  for (size_t v = 0; v < rest.size(); ++v) {
    posed[v] += glm::vec3(0.1f * std::sin(2.f * v), 0.07f * std::cos(float(v)), 0.05f * std::sin(5.f * v));
    frames[v] = fixtures::rotation(10.0 * std::sin(double(v)), {1, double(v % 3), 0.5}) * (1.0 + 0.05 * std::cos(double(v)));
  }
  BindParams p;
  p.variant = Variant::kBasic;  // same sets and weights as the extended binding, per element
  Binding basic = bind_or_die(s, p);
  p.variant = Variant::kExtended;
  Binding ext = bind_or_die(s, p);
  auto out = deform_with(ext, s.skin.positions, posed, frames);
  double worst = 0;
  for (size_t i = 0; i < basic.num_points; ++i) {
    glm::dvec3 P(s.skin.positions[i]), sum(0.0);
    for (uint32_t e = basic.offsets[i]; e < basic.offsets[i + 1]; ++e) {
      const Tri& t = basic.elements[basic.ids[e]];
      ClosestPoint cp = closest_point_on_triangle(P, glm::dvec3(rest[t[0]]), glm::dvec3(rest[t[1]]), glm::dvec3(rest[t[2]]));
      glm::dvec3 pk(0.0);
      for (int c = 0; c < 3; ++c) {
        uint32_t v = t[static_cast<size_t>(c)];
        glm::dvec3 local = P - glm::dvec3(rest[v]);  // rest axes are the world axes
        pk += cp.bary[c] * (glm::dvec3(posed[v]) + frames[v] * local);
      }
      sum += double(basic.weights[e]) * pk;
    }
    worst = std::max(worst, glm::length(sum - glm::dvec3(out[i])));
  }
  EXPECT_LE(worst, 1e-5 * bounding_box(s.skin.positions).diagonal());
}

// Bad cages: bind what can be bound, name what could not.
TEST(DeformerBadCage, DegenerateNonFiniteAndDuplicateElementsGetNoWeight) {
  Scene s = ball();
  PolyMesh poly = s.cage.polygons;
  const uint32_t nv = static_cast<uint32_t>(poly.num_vertices());
  poly.positions.push_back({0.2f, 0.2f, 1.0f});       // nv: collinear with the next two
  poly.positions.push_back({0.4f, 0.4f, 1.0f});       // nv + 1
  poly.positions.push_back({0.6f, 0.6f, 1.0f});       // nv + 2
  poly.positions.push_back({NAN, 0.0f, 0.0f});        // nv + 3: non-finite
  poly.add_face({nv, nv + 1, nv + 2});                 // zero area
  const Tri e0 = s.cage.elements[0];
  poly.add_face({e0[1], e0[2], e0[0]});                // element 0 again, rotated
  poly.add_face({nv + 3, 0, 1});                       // non-finite
  Cage cage = std::move(make_cage(poly, "bad cage")).value();
  const uint32_t ne = static_cast<uint32_t>(cage.num_elements());
  auto b = bind_skin(s.skin.positions, cage, cage.polygons.positions, BindParams{});
  ASSERT_TRUE(b.ok()) << b.error().message;
  EXPECT_EQ(b->invalid_elements, (std::vector<uint32_t>{ne - 3, ne - 2, ne - 1}));
  EXPECT_EQ(b->element_status[ne - 3], ElementStatus::kDegenerate);
  EXPECT_EQ(b->element_status[ne - 2], ElementStatus::kDuplicate);
  EXPECT_EQ(b->element_status[ne - 1], ElementStatus::kNonFinite);
  for (Variant v : {Variant::kBasic, Variant::kClamped, Variant::kExtended}) {
    BindParams p;
    p.variant = v;
    Binding bv = std::move(bind_skin(s.skin.positions, cage, cage.polygons.positions, p)).value();
    for (uint32_t id : bv.ids) {
      if (v == Variant::kExtended) EXPECT_LT(id, nv);
      else EXPECT_LT(id, ne - 3);
    }
    auto rest_out = deform_with(bv, s.skin.positions, cage.polygons.positions);
    EXPECT_LE(max_distance(rest_out, s.skin.positions), 1e-5);
    // a NaN on a vertex that valid elements use is refused, naming the vertex
    auto d = Deformer::create(bv, s.skin.positions);
    std::vector<glm::vec3> out(s.skin.num_vertices());
    auto posed = cage.polygons.positions;
    posed[5].y = NAN;
    auto st = d->deform(posed, out);
    ASSERT_FALSE(st.ok());
    EXPECT_EQ(st.error().code, ErrorCode::kNonFinite);
    EXPECT_NE(st.error().message.find("vertex 5 "), std::string::npos) << st.error().message;
    posed = cage.polygons.positions;
    posed[nv + 3] = glm::vec3(0.f);  // a finite value: the element stays excluded, skin moves rigidly
    glm::dmat3 r = fixtures::rotation(30, {0, 1, 0});
    auto moved = fixtures::transformed(posed, r, {1, 2, 3});
    auto expected = fixtures::transformed(s.skin.positions, r, {1, 2, 3});
    EXPECT_LE(max_distance(deform_with(bv, s.skin.positions, moved), expected), 1e-5) << variant_name(v);
  }
}

TEST(DeformerBadCage, NoValidElementIsAnError) {
  PolyMesh poly;
  poly.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  poly.add_face({0, 1, 2});
  Cage cage = std::move(make_cage(poly, "flat")).value();
  std::vector<glm::vec3> skin = {{0, 1, 0}};
  auto b = bind_skin(skin, cage, cage.polygons.positions, BindParams{});
  ASSERT_FALSE(b.ok());
  EXPECT_EQ(b.error().code, ErrorCode::kNoValidElements);
  EXPECT_NE(b.error().message.find("1 triangles"), std::string::npos) << b.error().message;
}

// A point whose set is empty follows its nearest valid element rigidly and never becomes NaN.
TEST(DeformerFallback, EmptySetsFollowNearestElementRigidly) {
  Scene s = arm();
  for (Variant v : {Variant::kBasic, Variant::kClamped, Variant::kExtended}) {
    BindParams p;
    p.variant = v;
    const auto edits = fixtures::empty_set_edits(s.skin.num_vertices(), 7);
    Binding b = bind_or_die(s, p, edits);
    ASSERT_FALSE(b.rigid_points.empty());
    ASSERT_LT(b.rigid_points.size(), b.num_points);
    for (uint32_t i : b.rigid_points) EXPECT_EQ(b.offsets[i], b.offsets[i + 1]);
    auto rest_out = deform_with(b, s.skin.positions, s.cage.polygons.positions);
    EXPECT_LE(max_distance(rest_out, s.skin.positions), 1e-5);
    glm::dmat3 r = fixtures::rotation(50, {1, 1, 0});
    auto out = deform_with(b, s.skin.positions, fixtures::transformed(s.cage.polygons.positions, r, {0, 3, 0}));
    EXPECT_LE(max_distance(out, fixtures::transformed(s.skin.positions, r, {0, 3, 0})), 1e-5) << variant_name(v);
    // each fallback point's element is its nearest valid one
    for (size_t k = 0; k < b.rigid_points.size(); ++k) {
      glm::dvec3 P(s.skin.positions[b.rigid_points[k]]);
      double best = 1e300;
      uint32_t arg = 0;
      for (uint32_t e = 0; e < b.elements.size(); ++e) {
        const Tri& t = b.elements[e];
        const auto& c = s.cage.polygons.positions;
        double d2 = closest_point_on_triangle(P, glm::dvec3(c[t[0]]), glm::dvec3(c[t[1]]), glm::dvec3(c[t[2]])).dist2;
        if (d2 < best) best = d2, arg = e;
      }
      const Tri& t = b.elements[b.rigid_element[k]];
      const auto& c = s.cage.polygons.positions;
      double d2 = closest_point_on_triangle(P, glm::dvec3(c[t[0]]), glm::dvec3(c[t[1]]), glm::dvec3(c[t[2]])).dist2;
      EXPECT_NEAR(d2, best, 1e-12) << "point " << b.rigid_points[k] << " follows " << b.rigid_element[k] << " not " << arg;
    }
  }
}

// User edits of contributing sets are an input of registration.
TEST(Registration, ExclusionsAndInclusionsShapeTheSet) {
  Scene s = ball();
  BindParams p;
  p.variant = Variant::kBasic;
  Binding plain = bind_or_die(s, p);
  const uint32_t point = 7;
  ASSERT_GE(plain.offsets[point + 1] - plain.offsets[point], 2u);
  const uint32_t strongest = plain.ids[plain.offsets[point]];
  // an element far away: the one whose centroid is farthest from the point
  uint32_t far = 0;
  double far_d = -1;
  for (uint32_t e = 0; e < plain.elements.size(); ++e) {
    glm::dvec3 c(0.0);
    for (uint32_t v : plain.elements[e]) c += glm::dvec3(s.cage.polygons.positions[v]) / 3.0;
    double d = glm::length(c - glm::dvec3(s.skin.positions[point]));
    if (d > far_d) far_d = d, far = e;
  }
  std::vector<SetEdit> edits = {{point, {strongest}, {far}}};
  Binding edited = bind_or_die(s, p, edits);
  std::vector<uint32_t> set(edited.ids.begin() + edited.offsets[point], edited.ids.begin() + edited.offsets[point + 1]);
  EXPECT_EQ(std::count(set.begin(), set.end(), strongest), 0);
  EXPECT_EQ(std::count(set.begin(), set.end(), far), 1);
  // other points are untouched
  for (uint32_t i : {0u, 50u, 300u})
    EXPECT_TRUE(std::equal(plain.ids.begin() + plain.offsets[i], plain.ids.begin() + plain.offsets[i + 1],
                           edited.ids.begin() + edited.offsets[i]));
  auto slow = bind_skin_brute_force(s.skin.positions, s.cage, s.cage.polygons.positions, p, edits);
  ASSERT_TRUE(slow.ok());
  EXPECT_EQ(edited.ids, slow->ids);
  EXPECT_EQ(edited.weights, slow->weights);
  // excluding every element leaves the point to the nearest valid element, rigidly
  SetEdit all{point, {}, {}};
  for (uint32_t e = 0; e < plain.elements.size(); ++e) all.exclude.push_back(e);
  std::vector<SetEdit> all_edits = {all};
  Binding none = bind_or_die(s, p, all_edits);
  EXPECT_EQ(none.rigid_points, std::vector<uint32_t>{point});
  EXPECT_EQ(none.rigid_element[0], strongest);
  // rest is still reproduced with all these edits
  EXPECT_LE(max_distance(deform_with(edited, s.skin.positions, s.cage.polygons.positions), s.skin.positions), 1e-5);
}

TEST(Registration, BadEditsAndParametersAreNamed) {
  Scene s = ball();
  std::vector<SetEdit> bad_point = {{999999, {0}, {}}};
  auto b = bind_skin(s.skin.positions, s.cage, s.cage.polygons.positions, BindParams{}, bad_point);
  ASSERT_FALSE(b.ok());
  EXPECT_EQ(b.error().code, ErrorCode::kIndexOutOfRange);
  EXPECT_NE(b.error().message.find("999999"), std::string::npos);
  std::vector<SetEdit> bad_elem = {{3, {}, {4242}}};
  b = bind_skin(s.skin.positions, s.cage, s.cage.polygons.positions, BindParams{}, bad_elem);
  ASSERT_FALSE(b.ok());
  EXPECT_NE(b.error().message.find("4242"), std::string::npos);
  EXPECT_NE(b.error().message.find("point 3"), std::string::npos);
  BindParams p;
  p.epsilon = 0;
  b = bind_skin(s.skin.positions, s.cage, s.cage.polygons.positions, p);
  ASSERT_FALSE(b.ok());
  EXPECT_NE(b.error().message.find("epsilon"), std::string::npos);
  std::vector<glm::vec3> nan_skin = {{0, 0, 0}, {NAN, 0, 0}};
  b = bind_skin(nan_skin, s.cage, s.cage.polygons.positions, BindParams{});
  ASSERT_FALSE(b.ok());
  EXPECT_NE(b.error().message.find("skin vertex 1"), std::string::npos);
}

// The cage-quality figure (algorithm.md section 4) and the points it misses, on a cube of side 2
// made of 6 quads: h = 2 (the mean polygon edge), so "close" is within 2.
TEST(Registration, QualityFailuresNameThePointsTheFigureMisses) {
  const Cage cube = fixtures::box_cage(1.0, 1);
  PolyMesh skin;
  skin.positions = {
      {0, 0, 0.9f},         // 0: inside, near the top face
      {0, 0, 0},            // 1: the centre, 1 from every face: close, projects inside each
      {0, 0, 3.5f},         // 2: above the top face but 2.5 away: not close
      {1.5f, 1.5f, 1.5f},   // 3: outside a corner, 0.87 away: close, but projects inside no face
      {0.5f, 0.2f, 1.5f},   // 4: 0.5 above the top face, projecting inside it
  };
  for (bool brute : {false, true}) {
    auto b = brute ? bind_skin_brute_force(skin.positions, cube, cube.polygons.positions, BindParams{})
                   : bind_skin(skin.positions, cube, cube.polygons.positions, BindParams{});
    ASSERT_TRUE(b.ok()) << b.error().message;
    EXPECT_DOUBLE_EQ(b->h, 2.0);
    EXPECT_EQ(b->quality_inside, 3u);
    auto failures = quality_failures(*b, skin.positions);
    ASSERT_TRUE(failures.ok()) << failures.error().message;
    EXPECT_EQ(*failures, (std::vector<uint32_t>{2, 3}));
  }
  // the binding is not changed, and a skin of another size is named
  auto b = bind_skin(skin.positions, cube, cube.polygons.positions, BindParams{});
  ASSERT_TRUE(b.ok());
  const Binding before = *b;
  ASSERT_TRUE(quality_failures(*b, skin.positions).ok());
  EXPECT_EQ(b->ids, before.ids);
  EXPECT_EQ(b->weights, before.weights);
  skin.positions.pop_back();
  auto wrong = quality_failures(*b, skin.positions);
  ASSERT_FALSE(wrong.ok());
  EXPECT_EQ(wrong.error().code, ErrorCode::kTopologyMismatch);
  EXPECT_NE(wrong.error().message.find("5 points"), std::string::npos) << wrong.error().message;
}

TEST(Registration, ThresholdRadiusIsExact) {
  for (double local : {1.0, 2.0, 3.5, 4.0, 8.0})
    for (double eps : {0.01, 0.1, 0.5})
      for (double dmin : {0.0, 0.1, 0.7, 2.0}) {
        double r = threshold_radius(dmin, local, eps);
        // an element at the radius has exactly epsilon times the strongest weight
        EXPECT_NEAR(falloff(r, local), eps * falloff(dmin, local), 1e-12);
      }
  EXPECT_DOUBLE_EQ(falloff(1.0, 4.0), 0.5);
  EXPECT_DOUBLE_EQ(falloff(0.0, 4.0), 1.0);
  EXPECT_NEAR(falloff(2.0, 3.0), 1.0 / 9.0, 1e-15);
  EXPECT_NEAR(falloff(2.0, 2.5), 1.0 / (1.0 + std::pow(2.0, 2.5)), 1e-15);
}

TEST(Registration, ProgressReachesOneAndCancelStops) {
  Scene s = arm();
  std::atomic<int> calls{0};
  std::atomic<double> last{0};
  BindProgress progress;
  progress.on_progress = [&](double f) {
    calls++;
    double prev = last.load();
    while (f > prev && !last.compare_exchange_weak(prev, f)) {
    }
  };
  auto b = bind_skin(s.skin.positions, s.cage, s.cage.polygons.positions, BindParams{}, {}, progress);
  ASSERT_TRUE(b.ok());
  EXPECT_GT(calls.load(), 0);
  EXPECT_DOUBLE_EQ(last.load(), 1.0);
  std::atomic<bool> cancel{true};
  progress.cancel = &cancel;
  b = bind_skin(s.skin.positions, s.cage, s.cage.polygons.positions, BindParams{}, {}, progress);
  ASSERT_FALSE(b.ok());
  EXPECT_EQ(b.error().code, ErrorCode::kCancelled);
}

TEST(Deformer, PosedCageOfOtherTopologyNamesBothCounts) {
  Scene s = ball();
  Binding b = bind_or_die(s, BindParams{});
  auto d = Deformer::create(b, s.skin.positions);
  ASSERT_TRUE(d.ok());
  std::vector<glm::vec3> posed(s.cage.num_vertices() + 3, glm::vec3(0.f));
  std::vector<glm::vec3> out(s.skin.num_vertices());
  auto st = d->deform(posed, out);
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.error().code, ErrorCode::kTopologyMismatch);
  EXPECT_NE(st.error().message.find(std::to_string(s.cage.num_vertices() + 3)), std::string::npos);
  EXPECT_NE(st.error().message.find(std::to_string(s.cage.num_vertices())), std::string::npos);
}

// Section 6: several deformers on one skin.
TEST(Combine, SumAndMagnitudeWeightedBlend) {
  std::vector<glm::vec3> rest = {{0, 0, 0}, {1, 1, 1}};
  std::vector<glm::vec3> a = {{1, 0, 0}, {1, 1, 1}};   // dP = (1,0,0), (0,0,0)
  std::vector<glm::vec3> b = {{0, 3, 0}, {1, 1, 3}};   // dP = (0,3,0), (0,0,2)
  std::vector<std::span<const glm::vec3>> both = {a, b};
  std::vector<glm::vec3> out(2);
  ASSERT_TRUE(combine_displacements(rest, both, CombineMode::kSum, 0, out).ok());
  EXPECT_EQ(out[0], glm::vec3(1, 3, 0));
  EXPECT_EQ(out[1], glm::vec3(1, 1, 3));
  ASSERT_TRUE(combine_displacements(rest, both, CombineMode::kWeighted, 1.0, out).ok());
  // |dP| = 1 and 3: (1*(1,0,0) + 3*(0,3,0)) / 4
  EXPECT_NEAR(out[0].x, 0.25f, 1e-6f);
  EXPECT_NEAR(out[0].y, 2.25f, 1e-6f);
  EXPECT_EQ(out[1], glm::vec3(1, 1, 3));  // one deformer does not move it: the other wins fully
  ASSERT_TRUE(combine_displacements(rest, both, CombineMode::kWeighted, 0.0, out).ok());  // m = 0: the mean
  EXPECT_NEAR(out[0].x, 0.5f, 1e-6f);
  EXPECT_NEAR(out[0].y, 1.5f, 1e-6f);
  std::vector<glm::vec3> still = rest;
  std::vector<std::span<const glm::vec3>> none = {still, still};
  ASSERT_TRUE(combine_displacements(rest, none, CombineMode::kWeighted, 2.0, out).ok());
  EXPECT_EQ(out[0], rest[0]);  // no displacement anywhere: no division by zero
  // issue 18: a large m tends to the largest displacement (no overflow: before, float pow gave NaN or
  // inf), a negative m is refused with a message (before: NaN where a deformer did not move the point)
  ASSERT_TRUE(combine_displacements(rest, both, CombineMode::kWeighted, 16.0, out).ok());
  EXPECT_NEAR(out[0].y, 3.f, 1e-6f);
  EXPECT_NEAR(out[0].x, std::pow(1.0 / 3.0, 16.0) * 1.0, 1e-6);
  std::vector<glm::vec3> tiny = {{1e-30f, 0, 0}, {1, 1, 1}}, huge = {{0, 1e30f, 0}, {1, 1, 1}};
  std::vector<std::span<const glm::vec3>> extreme = {tiny, huge};
  ASSERT_TRUE(combine_displacements(rest, extreme, CombineMode::kWeighted, 16.0, out).ok());
  EXPECT_TRUE(std::isfinite(out[0].x) && std::isfinite(out[0].y)) << out[0].x << " " << out[0].y;
  EXPECT_EQ(out[1], rest[1]);
  auto bad = combine_displacements(rest, both, CombineMode::kWeighted, -1.0, out);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("exponent m"), std::string::npos) << bad.error().message;
}

// The real bench triplets (skipped without ../shared/assets).
class RealTriplet : public ::testing::TestWithParam<std::string> {};

TEST_P(RealTriplet, RestAndRigidMotionForEveryVariant) {
  CAGEWRAP_REQUIRE_ASSETS(assets);
  const std::string dir = assets + "/bench/" + GetParam();
  std::string mesh_path;
  for (const auto& f : std::filesystem::directory_iterator(dir))
    if (f.path().filename().string().rfind("mesh_", 0) == 0) mesh_path = f.path().string();
  auto mesh = load_mesh(mesh_path);
  ASSERT_TRUE(mesh.ok()) << mesh.error().message;
  auto cage_mesh = load_mesh(dir + "/cage.obj");
  ASSERT_TRUE(cage_mesh.ok());
  Cage cage = std::move(make_cage(std::move(cage_mesh).value(), "cage")).value();
  const double diag = bounding_box(mesh->positions).diagonal();
  glm::dmat3 r = fixtures::rotation(35, {0.3, 1, -0.2});
  auto moved = fixtures::transformed(cage.polygons.positions, r, {0.5, -0.25, 2});
  auto expected = fixtures::transformed(mesh->positions, r, {0.5, -0.25, 2});
  for (Variant v : {Variant::kBasic, Variant::kClamped, Variant::kExtended}) {
    BindParams p;
    p.variant = v;
    auto b = bind_skin(mesh->positions, cage, cage.polygons.positions, p);
    ASSERT_TRUE(b.ok()) << b.error().message;
    EXPECT_LE(max_distance(deform_with(*b, mesh->positions, cage.polygons.positions), mesh->positions), 1e-5 * diag)
        << variant_name(v);
    EXPECT_LE(max_distance(deform_with(*b, mesh->positions, moved), expected), 1e-5 * diag) << variant_name(v);
  }
  // the hierarchy against brute force on every 7th point
  std::vector<glm::vec3> some;
  for (size_t i = 0; i < mesh->positions.size(); i += 7) some.push_back(mesh->positions[i]);
  BindParams p;
  auto fast = bind_skin(some, cage, cage.polygons.positions, p);
  auto slow = bind_skin_brute_force(some, cage, cage.polygons.positions, p);
  ASSERT_TRUE(fast.ok() && slow.ok());
  EXPECT_EQ(fast->ids, slow->ids);
  EXPECT_EQ(fast->weights, slow->weights);
}

INSTANTIATE_TEST_SUITE_P(Bench, RealTriplet, ::testing::Values("mannequiny", "armadillo"));

}  // namespace
}  // namespace cagewrap
