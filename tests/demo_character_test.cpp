#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <numeric>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "core/demo_character.h"
#include "core/gltf_loader.h"
#include "core/gltf_writer.h"
#include "core/joint_angles.h"
#include "core/skinning.h"
#include "tests/gltf_builder.h"

namespace cagewrap {
namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;

const Character& demo() {
  static const Character c = make_demo_character();
  return c;
}

uint32_t joint(const Character& c, const std::string& name) {
  int32_t j = c.skeleton.find(name);
  EXPECT_GE(j, 0) << name;
  return static_cast<uint32_t>(std::max(j, 0));
}

TEST(DemoCharacter, IsOneSmoothClosedSurfaceOfTheRightSize) {
  const Character& c = demo();
  ASSERT_EQ(c.primitives.size(), 1u);
  const Primitive& p = c.primitives[0];
  EXPECT_GE(p.num_vertices(), 20000u);
  EXPECT_LE(p.num_vertices(), 50000u);
  // Closed, consistently oriented 2-manifold: every directed edge once, its twin once.
  std::map<std::pair<uint32_t, uint32_t>, int> directed;
  for (const Tri& t : p.triangles)
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  size_t bad = 0;
  for (const auto& [e, n] : directed)
    if (n != 1 || !directed.count({e.second, e.first})) ++bad;
  EXPECT_EQ(bad, 0u) << "edges that are not shared by exactly two consistently oriented triangles";
  // One connected component of genus 0 (V - E + F = 2).
  std::vector<uint32_t> parent(p.num_vertices());
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](uint32_t v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (const Tri& t : p.triangles) {
    parent[find(t[0])] = find(t[1]);
    parent[find(t[1])] = find(t[2]);
  }
  size_t components = 0;
  for (uint32_t v = 0; v < parent.size(); ++v) components += find(v) == v;
  EXPECT_EQ(components, 1u);
  long euler = long(p.num_vertices()) - long(directed.size() / 2) + long(p.triangles.size());
  EXPECT_EQ(euler, 2);
  // Smooth: neighbouring faces meet at small angles (99% under 25 degrees), outward normals.
  std::vector<glm::dvec3> fn(p.triangles.size());
  std::map<std::pair<uint32_t, uint32_t>, uint32_t> edge_face;
  glm::dvec3 center(0.0);
  for (const glm::vec3& v : p.positions) center += glm::dvec3(v);
  center /= double(p.num_vertices());
  for (size_t f = 0; f < p.triangles.size(); ++f) {
    const Tri& t = p.triangles[f];
    glm::dvec3 a(p.positions[t[0]]), b(p.positions[t[1]]), cc(p.positions[t[2]]);
    fn[f] = glm::normalize(glm::cross(b - a, cc - a));
    for (int k = 0; k < 3; ++k) edge_face[{t[k], t[(k + 1) % 3]}] = static_cast<uint32_t>(f);
  }
  std::vector<double> angles;
  for (const auto& [e, f] : edge_face)
    if (e.first < e.second) angles.push_back(std::acos(std::clamp(glm::dot(fn[f], fn[edge_face[{e.second, e.first}]]), -1.0, 1.0)) * kDeg);
  std::sort(angles.begin(), angles.end());
  EXPECT_LT(angles[angles.size() * 99 / 100], 25.0);
  // The top of the head faces up.
  size_t top = 0;
  for (size_t v = 0; v < p.num_vertices(); ++v)
    if (p.positions[v].y > p.positions[top].y) top = v;
  EXPECT_GT(p.positions[top].y, 1.6f);
  EXPECT_LT(p.positions[top].y, 1.9f);
}

TEST(DemoCharacter, HasAHumanoidSkeletonAndNormalizedWeights) {
  const Character& c = demo();
  ASSERT_EQ(c.skins.size(), 1u);
  EXPECT_EQ(c.num_joints(), 21u);
  // Chains: spine to head, shoulder to hand, hip to toes.
  auto parent_of = [&](const char* child, const char* parent) {
    EXPECT_EQ(c.skeleton.node(joint(c, child)).parent, static_cast<int32_t>(joint(c, parent))) << child;
  };
  parent_of("spine", "hips");
  parent_of("chest", "spine");
  parent_of("neck", "chest");
  parent_of("head", "neck");
  for (std::string s : {".L", ".R"}) {
    parent_of(("shoulder" + s).c_str(), "chest");
    parent_of(("upper_arm" + s).c_str(), ("shoulder" + s).c_str());
    parent_of(("forearm" + s).c_str(), ("upper_arm" + s).c_str());
    parent_of(("hand" + s).c_str(), ("forearm" + s).c_str());
    parent_of(("thigh" + s).c_str(), "hips");
    parent_of(("shin" + s).c_str(), ("thigh" + s).c_str());
    parent_of(("foot" + s).c_str(), ("shin" + s).c_str());
  }
  const Primitive& p = c.primitives[0];
  std::vector<double> total(c.skins[0].joints.size(), 0.0);
  for (size_t v = 0; v < p.num_vertices(); ++v) {
    ASSERT_GE(p.num_influences(v), 1u);
    ASSERT_LE(p.num_influences(v), 4u);
    float sum = 0;
    for (uint32_t k = p.influence_start[v]; k < p.influence_start[v + 1]; ++k) {
      sum += p.influence_weight[k];
      total[p.influence_joint[k]] += p.influence_weight[k];
    }
    ASSERT_NEAR(sum, 1.0f, 1e-5) << "vertex " << v;
  }
  for (size_t j = 0; j < total.size(); ++j) EXPECT_GT(total[j], 10.0) << c.skeleton.node(j).name << " drives no skin";
  // Blending at the elbow: vertices there are shared between upper arm and forearm.
  size_t blended = 0;
  const uint16_t ua = 6, fa = 7;  // upper_arm.L, forearm.L in skin order
  ASSERT_EQ(c.skeleton.node(c.skins[0].joints[ua]).name, "upper_arm.L");
  for (size_t v = 0; v < p.num_vertices(); ++v) {
    bool has_ua = false, has_fa = false;
    for (uint32_t k = p.influence_start[v]; k < p.influence_start[v + 1]; ++k) {
      has_ua |= p.influence_joint[k] == ua && p.influence_weight[k] > 0.2f;
      has_fa |= p.influence_joint[k] == fa && p.influence_weight[k] > 0.2f;
    }
    blended += has_ua && has_fa;
  }
  EXPECT_GT(blended, 50u);
}

double range_deg(const std::vector<double>& a) {
  auto [lo, hi] = std::minmax_element(a.begin(), a.end());
  return (*hi - *lo) * kDeg;
}

TEST(DemoCharacter, ClipsBendShouldersElbowsHipsAndKneesThroughLargeAngles) {
  const Character& c = demo();
  int32_t walk = c.find_clip("walk"), raise = c.find_clip("arm_raise");
  ASSERT_GE(walk, 0);
  ASSERT_GE(raise, 0);
  EXPECT_DOUBLE_EQ(c.clips[walk].duration, 1.0);
  EXPECT_DOUBLE_EQ(c.clips[raise].duration, 2.0);
  // Read back through the joint-angle read-outs (local X bends elbows and knees, local Z raises arms).
  for (std::string s : {".L", ".R"}) {
    EXPECT_GT(range_deg(clip_joint_angles(c, raise, joint(c, "upper_arm" + s), {0, 0, 1}, 121)), 120.0) << s;
    EXPECT_GT(range_deg(clip_joint_angles(c, raise, joint(c, "forearm" + s), {1, 0, 0}, 121)), 100.0) << s;
    EXPECT_GT(range_deg(clip_joint_angles(c, walk, joint(c, "thigh" + s), {1, 0, 0}, 61)), 60.0) << s;
    EXPECT_GT(range_deg(clip_joint_angles(c, walk, joint(c, "shin" + s), {1, 0, 0}, 61)), 55.0) << s;
    EXPECT_GT(range_deg(clip_joint_angles(c, walk, joint(c, "upper_arm" + s), {1, 0, 0}, 61)), 45.0) << s;
  }
  // At the top of the raise the hands are above the head; the walk loops seamlessly.
  auto g = c.skeleton.global_transforms(sample_pose(c, raise, 1.0));
  EXPECT_GT(g[joint(c, "hand.L")][3].y, g[joint(c, "head")][3].y);
  EXPECT_GT(g[joint(c, "hand.R")][3].y, g[joint(c, "head")][3].y);
  auto start = skin_character(c, sample_pose(c, walk, 0.0));
  auto end = skin_character(c, sample_pose(c, walk, 1.0));
  double gap = 0;
  for (size_t v = 0; v < start.size(); ++v) gap = std::max(gap, double(glm::length(start[v] - end[v])));
  EXPECT_LT(gap, 1e-4);
  // Skinned frames stay the same size (no vertex flies off).
  const double rest_diag = bounding_box(c.primitives[0].positions).diagonal();
  for (int32_t clip : {walk, raise})
    for (double t = 0; t <= c.clips[clip].duration; t += 0.25) {
      double d = bounding_box(skin_character(c, sample_pose(c, clip, t))).diagonal();
      EXPECT_GT(d, 0.7 * rest_diag);
      EXPECT_LT(d, 1.3 * rest_diag);
    }
}

TEST(DemoCharacter, IsDeterministicAndMatchesTheCommittedAsset) {
  std::vector<uint8_t> a = encode_glb(demo());
  std::vector<uint8_t> b = encode_glb(make_demo_character());
  EXPECT_TRUE(a == b) << "two generations differ";
  const std::string committed = std::string(CAGEWRAP_SOURCE_DIR) + "/assets/demo_character.glb";
  std::ifstream in(committed, std::ios::binary);
  ASSERT_TRUE(in) << committed << " is missing: run `cagewrap make-demo --out assets/demo_character.glb`";
  std::vector<uint8_t> file((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (file == a) return;  // byte-identical
  // Otherwise (another compiler's last bits) the content must agree closely.
  auto loaded = load_character(committed);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  const Primitive& p = loaded->primitives.at(0);
  const Primitive& q = demo().primitives[0];
  ASSERT_EQ(p.num_vertices(), q.num_vertices()) << "regenerate assets/demo_character.glb with make-demo";
  ASSERT_EQ(p.triangles, q.triangles);
  for (size_t v = 0; v < p.num_vertices(); ++v) ASSERT_LT(glm::length(p.positions[v] - q.positions[v]), 1e-5f);
  ADD_FAILURE() << committed << " has the same content but not the same bytes as a fresh make-demo";
}

TEST(DemoCharacter, RoundTripsThroughGlb) {
  const Character& c = demo();
  auto dir = test::temp_dir("demo_roundtrip");
  ASSERT_TRUE(write_glb(dir + "/demo.glb", c).ok());
  auto r = load_character(dir + "/demo.glb");
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_TRUE(r->warnings.empty());
  ASSERT_EQ(r->primitives.size(), 1u);
  EXPECT_EQ(r->primitives[0].positions, c.primitives[0].positions);
  EXPECT_EQ(r->primitives[0].triangles, c.primitives[0].triangles);
  EXPECT_EQ(r->primitives[0].influence_start, c.primitives[0].influence_start);
  EXPECT_EQ(r->primitives[0].influence_joint, c.primitives[0].influence_joint);
  ASSERT_EQ(r->clips.size(), 2u);
  for (int32_t clip : {0, 1})
    for (double t : {0.1, 0.55, 0.9}) {
      auto a = skin_character(c, sample_pose(c, clip, t));
      auto b = skin_character(*r, sample_pose(*r, clip, t));
      double d = 0;
      for (size_t v = 0; v < a.size(); ++v) d = std::max(d, double(glm::length(a[v] - b[v])));
      EXPECT_LT(d, 1e-5) << "clip " << clip << " t " << t;
    }
}

}  // namespace
}  // namespace cagewrap
