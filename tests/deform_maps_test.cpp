// What the GPU kernels are handed from core: Deformer::update_maps and the maps it exposes
// (core/deform/deformer.h), and the comparison of two normal fields (core/geometry/mesh_normals.h). The maps, applied
// through the stencil as shaders/deform.comp.glsl reads them, must give deform()'s result.
#include <gtest/gtest.h>

#include <cmath>

#include "core/deform/deformer.h"
#include "core/geometry/mesh_normals.h"
#include "core/deform/registration.h"
#include "tests/expect_error.h"
#include "tests/fixtures.h"

namespace cagewrap {
namespace {

// The deformed skin computed from the exposed maps alone, in double, the way the kernels read them.
std::vector<glm::vec3> apply_exposed_maps(const Deformer& d) {
  const Binding& b = d.binding();
  auto skin = d.skin_rest();
  std::vector<glm::vec3> out(skin.size());
  auto rigid = [&](uint32_t e, double b1, double b2, const glm::dvec3& p) {
    const RigidMap& r = d.rigid_maps()[e];
    glm::dvec3 y;
    for (int k = 0; k < 3; ++k)
      y[k] = r.g[3 * k] * p.x + r.g[3 * k + 1] * p.y + r.g[3 * k + 2] * p.z + r.q0[k] + b1 * r.d1[k] + b2 * r.d2[k];
    return y;
  };
  for (uint32_t i = 0; i < b.num_points; ++i) {
    const glm::dvec3 p = glm::dvec3(skin[i]) - b.origin;
    glm::dvec3 y(0.0);
    for (uint32_t e = b.offsets[i]; e < b.offsets[i + 1]; ++e) {
      if (b.params.variant == Variant::kClamped) {
        y += double(b.weights[e]) * rigid(b.ids[e], b.bary[2 * e], b.bary[2 * e + 1], p);
      } else {
        const Affine& a = d.affine_maps()[b.ids[e]];
        for (int r = 0; r < 3; ++r)
          y[r] += b.weights[e] * (a.m[4 * r] * p.x + a.m[4 * r + 1] * p.y + a.m[4 * r + 2] * p.z + a.m[4 * r + 3]);
      }
    }
    out[i] = glm::vec3(y + b.origin);
  }
  for (size_t k = 0; k < b.rigid_points.size(); ++k) {
    const uint32_t i = b.rigid_points[k];
    out[i] = glm::vec3(rigid(b.rigid_element[k], b.rigid_bary[2 * k], b.rigid_bary[2 * k + 1], glm::dvec3(skin[i]) - b.origin) +
                       b.origin);
  }
  return out;
}

class DeformMaps : public ::testing::TestWithParam<Variant> {};

TEST_P(DeformMaps, ExposedMapsThroughTheStencilGiveDeformsResult) {
  const PolyMesh skin = fixtures::cylinder_skin();
  const Cage cage = fixtures::cylinder_cage();
  // 0.27: the skin under the cage's edges is beyond it (its nearest element alone); with edits that
  // empty some points' sets: the rigid fallback
  for (double max_distance : {0.0, 0.27}) {
    BindParams params;
    params.variant = GetParam();
    params.max_distance = max_distance;
    const auto edits = max_distance > 0 ? fixtures::empty_set_edits(skin.num_vertices(), 11) : std::vector<SetEdit>{};
    auto b = bind_skin(skin.positions, cage, cage.polygons.positions, params, edits);
    ASSERT_TRUE(b.ok()) << b.error().message;
    if (max_distance > 0) {
      ASSERT_FALSE(b->rigid_points.empty());
    }
    auto d = Deformer::create(*b, skin.positions);
    ASSERT_TRUE(d.ok());
    // bent at the middle, stretched, moved: every element gets its own map
    auto posed = fixtures::transformed(fixtures::bent(cage.polygons.positions, 2.0, 70.0),
                                       glm::dmat3(1.3, 0.1, 0, 0, 0.9, 0, 0, 0.2, 1.1), glm::dvec3(0.5, -2, 3));
    std::vector<glm::vec3> expected(skin.positions.size());
    ASSERT_TRUE(d->deform(posed, expected).ok());
    const size_t maps = GetParam() == Variant::kBasic ? cage.num_elements() : cage.num_vertices();
    EXPECT_EQ(d->affine_maps().size(), GetParam() == Variant::kClamped ? 0u : maps);
    EXPECT_EQ(d->rigid_maps().empty(), GetParam() != Variant::kClamped && b->rigid_points.empty());
    // update_maps alone builds the same maps deform() used: reset them with another pose first
    ASSERT_TRUE(d->update_maps(cage.polygons.positions).ok());
    ASSERT_TRUE(d->update_maps(posed).ok());
    auto got = apply_exposed_maps(*d);
    EXPECT_LT(fixtures::max_distance(got, expected), 1e-5) << variant_name(GetParam()) << " max_distance " << max_distance;
  }
}

INSTANTIATE_TEST_SUITE_P(AllVariants, DeformMaps,
                         ::testing::Values(Variant::kBasic, Variant::kClamped, Variant::kExtended),
                         [](const auto& info) { return std::string(variant_name(info.param)); });

TEST(DeformMaps, UpdateMapsRefusesWhatDeformRefuses) {
  const PolyMesh skin = fixtures::cylinder_skin();
  const Cage cage = fixtures::cylinder_cage();
  BindParams params;
  params.variant = Variant::kBasic;
  auto b = bind_skin(skin.positions, cage, cage.polygons.positions, params);
  ASSERT_TRUE(b.ok());
  auto d = Deformer::create(*b, skin.positions);
  ASSERT_TRUE(d.ok());
  std::vector<glm::vec3> fewer(cage.polygons.positions.begin(), cage.polygons.positions.end() - 1);
  EXPECT_TRUE(Fails(d->update_maps(fewer), ErrorCode::kTopologyMismatch, {"posed cage has", "vertices"}));
  auto nan = cage.polygons.positions;
  nan[3].y = NAN;
  EXPECT_TRUE(Fails(d->update_maps(nan), ErrorCode::kNonFinite, {"posed cage vertex 3"}));
  std::vector<glm::dmat3> frames(cage.num_vertices(), glm::dmat3(1.0));
  EXPECT_TRUE(Fails(d->update_maps(cage.polygons.positions, frames), ErrorCode::kInvalidArgument, {"extended variant"}));
}

TEST(MaxNormalAngle, MeasuresTheWorstPair) {
  const std::vector<glm::vec3> a = {{0, 0, 1}, {1, 0, 0}, {0, 0, 0}, {0, 1, 0}};
  std::vector<glm::vec3> b = a;
  EXPECT_EQ(max_normal_angle(a, b), 0.0);  // zero against zero counts as agreement
  b[1] = glm::vec3(std::cos(0.01f), std::sin(0.01f), 0);
  EXPECT_NEAR(max_normal_angle(a, b), 0.01, 1e-6);  // small angles stay accurate
  b[3] = glm::vec3(0, 0, 1);
  EXPECT_NEAR(max_normal_angle(a, b), M_PI / 2, 1e-6);
  b[2] = glm::vec3(0, 1, 0);  // a normal where the other side has none
  EXPECT_DOUBLE_EQ(max_normal_angle(a, b), M_PI);
  b = a;
  b[0].x = NAN;
  EXPECT_DOUBLE_EQ(max_normal_angle(a, b), M_PI);
}

}  // namespace
}  // namespace cagewrap
