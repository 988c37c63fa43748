#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <numeric>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "core/character/demo_character.h"
#include "core/io/gltf_loader.h"
#include "core/io/gltf_writer.h"
#include "core/character/joint_angles.h"
#include "core/cage/mesh_check.h"
#include "core/character/skinning.h"
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


// ---------------------------------------------------------------- hard test characters

// The skin joint with the largest weight on vertex v.
uint16_t dominant(const Primitive& p, size_t v) {
  uint32_t best = p.influence_start[v];
  for (uint32_t k = p.influence_start[v]; k < p.influence_start[v + 1]; ++k)
    if (p.influence_weight[k] > p.influence_weight[best]) best = k;
  return p.influence_joint[best];
}

float weight_of(const Primitive& p, size_t v, uint32_t joint) {
  for (uint32_t k = p.influence_start[v]; k < p.influence_start[v + 1]; ++k)
    if (p.influence_joint[k] == joint) return p.influence_weight[k];
  return 0.0f;
}

// Skin points (in `points`) dominated by the joint.
std::vector<glm::vec3> dominated_by(const Character& c, std::span<const glm::vec3> points, uint32_t joint) {
  std::vector<glm::vec3> out;
  const Primitive& p = c.primitives[0];
  for (size_t v = 0; v < p.num_vertices(); ++v)
    if (dominant(p, v) == joint) out.push_back(points[v]);
  return out;
}

double closest(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
  double d = 1e30;
  for (const glm::vec3& x : a)
    for (const glm::vec3& y : b) d = std::min(d, double(glm::distance(x, y)));
  return d;
}

void expect_closed_surface(const Character& c) {
  ASSERT_EQ(c.primitives.size(), 1u);
  const Primitive& p = c.primitives[0];
  MeshCheck m = check_mesh(p.positions, p.triangles, false);
  EXPECT_TRUE(m.closed()) << m.summary();
  EXPECT_TRUE(m.manifold()) << m.summary();
  EXPECT_TRUE(m.oriented()) << m.summary();
  EXPECT_GT(m.signed_volume, 0.0) << m.summary();
  EXPECT_EQ(m.components, 1u) << "one closed skin (a fused hand and thigh, fingers, a tail: all one piece)";
  for (size_t v = 0; v < p.num_vertices(); ++v) {
    ASSERT_GE(p.num_influences(v), 1u);
    float sum = 0;
    for (uint32_t k = p.influence_start[v]; k < p.influence_start[v + 1]; ++k) sum += p.influence_weight[k];
    ASSERT_NEAR(sum, 1.0f, 1e-5) << "vertex " << v;
  }
}

const Character& arms_down() {
  static const Character c = make_demo_character({.variant = DemoVariant::kArmsDown});
  return c;
}

const Character& tail_character() {
  static const Character c = make_demo_character({.variant = DemoVariant::kTail});
  return c;
}

TEST(DemoVariants, NamesParseAndTheDefaultOptionsAreUnchanged) {
  for (DemoVariant v : {DemoVariant::kDefault, DemoVariant::kArmsDown, DemoVariant::kTail, DemoVariant::kArmsDownTail,
                        DemoVariant::kQuadruped})
    EXPECT_EQ(parse_demo_variant(demo_variant_name(v)), v);
  EXPECT_FALSE(parse_demo_variant("arms_down").has_value());
  EXPECT_DOUBLE_EQ(demo_default_cell_size(DemoVariant::kDefault), 0.015);
  // Spelling the defaults out changes nothing.
  DemoCharacterOptions o;
  o.variant = DemoVariant::kDefault;
  o.cell_size = 0.015;
  o.unit_scale = 1.0;
  EXPECT_TRUE(encode_glb(make_demo_character(o)) == encode_glb(demo()));
}

TEST(DemoVariants, ArmsDownHandsTouchTheThighsAndTheLegsAreTogether) {
  const Character& c = arms_down();
  expect_closed_surface(c);  // one piece: the hands fuse with the thighs
  const Primitive& p = c.primitives[0];
  EXPECT_EQ(c.num_joints(), 21u);
  EXPECT_LT(p.num_vertices(), 80000u);
  auto g = c.skeleton.global_transforms(c.skeleton.rest_pose());
  for (std::string s : {".L", ".R"}) {
    // The arm hangs: the hand is below the hips, almost straight under the shoulder.
    glm::vec3 shoulder = g[joint(c, "upper_arm" + s)][3], hand = g[joint(c, "hand" + s)][3];
    EXPECT_LT(hand.y, g[joint(c, "hips")][3].y);
    EXPECT_LT(std::abs(hand.x - shoulder.x), 0.1f) << s;
    // The hand's skin touches the thigh's skin, yet each keeps its own weights.
    const uint32_t hd = joint(c, "hand" + s), fa = joint(c, "forearm" + s), th = joint(c, "thigh" + s);
    auto hand_points = dominated_by(c, p.positions, hd);
    auto thigh_points = dominated_by(c, p.positions, th);
    ASSERT_GT(hand_points.size(), 100u);
    ASSERT_GT(thigh_points.size(), 100u);
    EXPECT_LT(closest(hand_points, thigh_points), 0.015) << s;
    for (size_t v = 0; v < p.num_vertices(); ++v) {
      uint16_t d = dominant(p, v);
      if (d == th) {
        ASSERT_LT(weight_of(p, v, hd) + weight_of(p, v, fa), 0.01f) << "thigh vertex " << v << " follows the arm";
      } else if (d == hd) {
        ASSERT_LT(weight_of(p, v, th), 0.01f) << "hand vertex " << v << " follows the thigh";
      }
    }
  }
  // Legs together: the inner thighs touch (and the legs keep their own weights).
  const uint32_t tl = joint(c, "thigh.L"), tr = joint(c, "thigh.R");
  EXPECT_LT(closest(dominated_by(c, p.positions, tl), dominated_by(c, p.positions, tr)), 0.015);
  for (size_t v = 0; v < p.num_vertices(); ++v) {
    if (p.positions[v].y > 0.75f) continue;  // below the crotch, where the pelvis blends both in
    if (dominant(p, v) == tl) {
      ASSERT_LT(weight_of(p, v, tr), 0.01f) << v;
    } else if (dominant(p, v) == tr) {
      ASSERT_LT(weight_of(p, v, tl), 0.01f) << v;
    }
  }
  // arm_raise lifts the hands off the thighs: 125 degrees of abduction, the hands above the shoulders.
  int32_t raise = c.find_clip("arm_raise"), walk = c.find_clip("walk");
  ASSERT_GE(raise, 0);
  ASSERT_GE(walk, 0);
  auto top = c.skeleton.global_transforms(sample_pose(c, raise, 1.0));
  auto skinned = skin_character(c, sample_pose(c, raise, 1.0));
  for (std::string s : {".L", ".R"}) {
    EXPECT_GT(range_deg(clip_joint_angles(c, raise, joint(c, "upper_arm" + s), {0, 0, 1}, 121)), 120.0) << s;
    EXPECT_GT(top[joint(c, "hand" + s)][3].y, top[joint(c, "upper_arm" + s)][3].y) << s;
    EXPECT_GT(closest(dominated_by(c, skinned, joint(c, "hand" + s)), dominated_by(c, skinned, joint(c, "thigh" + s))), 0.3)
        << s;
    EXPECT_GT(range_deg(clip_joint_angles(c, walk, joint(c, "thigh" + s), {1, 0, 0}, 61)), 60.0) << s;
  }
}

TEST(DemoVariants, TailHasFiveFingersPerHandAndATwelveBoneTail) {
  const Character& c = tail_character();
  expect_closed_surface(c);
  const Primitive& p = c.primitives[0];
  EXPECT_GT(p.num_vertices(), 40000u);
  EXPECT_LT(p.num_vertices(), 80000u);
  EXPECT_EQ(c.num_joints(), 21u + 30u + 12u);
  auto g = c.skeleton.global_transforms(c.skeleton.rest_pose());
  // The fingers: three phalanges chained to the hand, side by side within a few millimetres.
  std::map<uint32_t, std::string> finger_of;
  for (std::string s : {".L", ".R"}) {
    std::vector<glm::vec3> knuckles;
    for (std::string f : {"thumb", "index", "middle", "ring", "little"}) {
      std::string parent = "hand" + s;
      for (int k = 1; k <= 3; ++k) {
        std::string name = "finger_" + f + "_" + std::to_string(k) + s;
        uint32_t j = joint(c, name);
        EXPECT_EQ(c.skeleton.node(j).parent, static_cast<int32_t>(joint(c, parent))) << name;
        finger_of[j] = f + s;
        parent = name;
      }
      if (f != "thumb") knuckles.push_back(g[joint(c, "finger_" + f + "_1" + s)][3]);
    }
    for (size_t k = 1; k < knuckles.size(); ++k) EXPECT_NEAR(glm::distance(knuckles[k - 1], knuckles[k]), 0.026, 0.003);
  }
  // Each finger's skin is its own: the other fingers weigh little on it.
  size_t finger_vertices = 0;
  for (size_t v = 0; v < p.num_vertices(); ++v) {
    auto it = finger_of.find(dominant(p, v));
    if (it == finger_of.end()) continue;
    ++finger_vertices;
    float others = 0;
    for (uint32_t k = p.influence_start[v]; k < p.influence_start[v + 1]; ++k) {
      auto o = finger_of.find(p.influence_joint[k]);
      if (o != finger_of.end() && o->second != it->second) others += p.influence_weight[k];
    }
    ASSERT_LT(others, 0.1f) << "vertex " << v << " of " << it->second;
  }
  EXPECT_GT(finger_vertices, 1000u);
  // The tail: 12 bones chained from the hips, about a metre long, thinning to the tip.
  std::string parent = "hips";
  double length = 0;
  for (int i = 1; i <= 12; ++i) {
    char name[16];
    std::snprintf(name, sizeof name, "tail_%02d", i);
    uint32_t j = joint(c, name);
    EXPECT_EQ(c.skeleton.node(j).parent, static_cast<int32_t>(joint(c, parent))) << name;
    if (i > 1) length += glm::distance(glm::vec3(g[j][3]), glm::vec3(g[joint(c, parent)][3]));
    parent = name;
    EXPECT_GT(dominated_by(c, p.positions, j).size(), 20u) << name << " drives no skin";
  }
  EXPECT_GT(length, 0.85);
  EXPECT_LT(g[joint(c, "tail_12")][3].z, -0.7f);
  for (const char* clip : {"walk", "arm_raise", "tail_wave"}) EXPECT_GE(c.find_clip(clip), 0) << clip;
}

TEST(DemoVariants, TailWaveCurlsEveryTailBoneAndEveryFinger) {
  const Character& c = tail_character();
  int32_t wave = c.find_clip("tail_wave");
  ASSERT_GE(wave, 0);
  EXPECT_DOUBLE_EQ(c.clips[wave].duration, 2.0);
  for (int i = 1; i <= 12; ++i) {
    char name[16];
    std::snprintf(name, sizeof name, "tail_%02d", i);
    double r = range_deg(clip_joint_angles(c, wave, joint(c, name), {1, 0, 0}, 121));
    EXPECT_GT(r, 30.0) << name;
    EXPECT_LT(r, 40.0) << name;
  }
  auto start = c.skeleton.global_transforms(sample_pose(c, wave, 0.0));
  auto mid = c.skeleton.global_transforms(sample_pose(c, wave, 1.0));
  for (std::string s : {".L", ".R"})
    for (std::string f : {"thumb", "index", "middle", "ring", "little"})
      for (int k = 1; k <= 3; ++k) {
        std::string name = "finger_" + f + "_" + std::to_string(k) + s;
        EXPECT_GT(range_deg(clip_joint_angles(c, wave, joint(c, name), {1, 0, 0}, 121)), 65.0) << name;
        if (k == 3 && f != "thumb") {  // the fingertips curl toward the palm, which faces +Z
          EXPECT_GT(mid[joint(c, name)][3].z - start[joint(c, name)][3].z, 0.02f) << name;
        }
      }
  // The whole tail moves: its tip sweeps more than 20 cm between two times of the wave.
  double sweep = 0;
  for (double t : {0.25, 0.5, 0.75, 1.0, 1.5}) {
    auto g = c.skeleton.global_transforms(sample_pose(c, wave, t));
    sweep = std::max(sweep, double(glm::distance(glm::vec3(g[joint(c, "tail_12")][3]), glm::vec3(start[joint(c, "tail_12")][3]))));
  }
  EXPECT_GT(sweep, 0.2);
  // Skinned frames stay the same size (no vertex flies off) and the loop closes.
  const double rest_diag = bounding_box(c.primitives[0].positions).diagonal();
  for (double t = 0; t <= 2.0; t += 0.5) {
    double d = bounding_box(skin_character(c, sample_pose(c, wave, t))).diagonal();
    EXPECT_GT(d, 0.7 * rest_diag);
    EXPECT_LT(d, 1.3 * rest_diag);
  }
}

TEST(DemoVariants, CombinedArmsDownAndTailIsOneClosedSkin) {
  const Character& c = make_demo_character({.cell_size = 0.012, .variant = DemoVariant::kArmsDownTail});
  expect_closed_surface(c);
  EXPECT_EQ(c.num_joints(), 63u);
  EXPECT_EQ(c.clips.size(), 3u);
}

// The quadruped: one closed skin over a level body, four legs standing on the ground, each leg's
// skin its own (the left legs carry no weight of the right ones), an 8-bone tail; the walk swings
// every leg and the sit folds the hind legs under the body.
TEST(DemoVariants, QuadrupedStandsOnFourLegsThatKeepTheirOwnWeights) {
  const Character c = make_demo_character({.cell_size = 0.014, .variant = DemoVariant::kQuadruped});
  expect_closed_surface(c);
  const Primitive& p = c.primitives[0];
  EXPECT_EQ(c.num_joints(), 29u);
  auto g = c.skeleton.global_transforms(c.skeleton.rest_pose());
  const glm::vec3 hips = g[joint(c, "hips")][3], chest = g[joint(c, "chest")][3];
  EXPECT_NEAR(hips.y, chest.y, 0.05f) << "a level body";
  EXPECT_GT(chest.z - hips.z, 0.3f) << "facing +Z";
  const Aabb box = bounding_box(p.positions);
  EXPECT_LT(box.lo.y, 0.03) << "the paws reach the ground";
  EXPECT_GT(box.hi.z - box.lo.z, 1.0);
  for (const char* paw : {"hand.L", "hand.R", "toes.L", "toes.R"})
    EXPECT_LT(g[joint(c, paw)][3].y, 0.1f) << paw;
  // Each leg's skin is its own: no weight of the other side's leg of the same pair.
  const std::pair<const char*, const char*> pairs[] = {{"upper_arm", "forearm"}, {"thigh", "shin"}};
  for (const auto& [upper, lower] : pairs) {
    const uint32_t ul = joint(c, std::string(upper) + ".L"), ll = joint(c, std::string(lower) + ".L");
    const uint32_t ur = joint(c, std::string(upper) + ".R"), lr = joint(c, std::string(lower) + ".R");
    size_t leg_vertices = 0;
    for (size_t v = 0; v < p.num_vertices(); ++v) {
      const uint16_t d = dominant(p, v);
      if (d == ll || d == lr) {
        ++leg_vertices;
        const bool left = d == ll;
        ASSERT_LT(weight_of(p, v, left ? ur : ul) + weight_of(p, v, left ? lr : ll), 0.01f)
            << "vertex " << v << " of " << lower << (left ? ".L" : ".R") << " follows the other leg";
      }
    }
    EXPECT_GT(leg_vertices, 500u) << lower;
  }
  for (int i = 1; i <= 8; ++i) {
    char name[16];
    std::snprintf(name, sizeof name, "tail_%02d", i);
    EXPECT_GT(dominated_by(c, p.positions, joint(c, name)).size(), 20u) << name << " drives no skin";
  }
  const int32_t walk = c.find_clip("walk"), sit = c.find_clip("sit");
  ASSERT_GE(walk, 0);
  ASSERT_GE(sit, 0);
  for (const char* leg : {"thigh.L", "thigh.R", "upper_arm.L", "upper_arm.R"})
    EXPECT_GT(range_deg(clip_joint_angles(c, walk, joint(c, leg), {1, 0, 0}, 81)), 40.0) << leg;
  for (const char* hock : {"shin.L", "shin.R"})
    EXPECT_GT(range_deg(clip_joint_angles(c, sit, joint(c, hock), {1, 0, 0}, 121)), 110.0) << hock;
  // Sitting lifts the chest: the front of the body rises by more than 20 cm.
  auto seated = c.skeleton.global_transforms(sample_pose(c, sit, 1.0));
  EXPECT_GT(seated[joint(c, "chest")][3].y - chest.y, 0.2f);
}

TEST(DemoVariants, CentimetresScaleTheWholeCharacterByAHundred) {
  const Character m = make_demo_character({.cell_size = 0.03, .variant = DemoVariant::kTail});
  const Character cm = make_demo_character({.cell_size = 0.03, .variant = DemoVariant::kTail, .unit_scale = 100.0});
  ASSERT_EQ(cm.primitives[0].num_vertices(), m.primitives[0].num_vertices());
  EXPECT_EQ(cm.primitives[0].triangles, m.primitives[0].triangles);
  EXPECT_EQ(cm.primitives[0].influence_joint, m.primitives[0].influence_joint);
  const double ratio = bounding_box(cm.primitives[0].positions).diagonal() / bounding_box(m.primitives[0].positions).diagonal();
  EXPECT_NEAR(ratio, 100.0, 1.0);
  // Joints, inverse bind matrices and animated translations (the walk's hip bob) scale too, so
  // every posed frame is the metre one times 100.
  for (size_t j = 0; j < m.skins[0].joints.size(); ++j) {
    glm::mat4 bind = glm::inverse(cm.skins[0].inverse_bind[j]);
    glm::mat4 bind_m = glm::inverse(m.skins[0].inverse_bind[j]);
    EXPECT_LT(glm::distance(glm::vec3(bind[3]), 100.0f * glm::vec3(bind_m[3])), 1e-3f) << j;
  }
  for (int32_t clip = 0; clip < int32_t(m.clips.size()); ++clip)
    for (double t : {0.0, 0.3, 0.75}) {
      auto a = skin_character(m, sample_pose(m, clip, t));
      auto b = skin_character(cm, sample_pose(cm, clip, t));
      double d = 0;
      for (size_t v = 0; v < a.size(); ++v) d = std::max(d, double(glm::distance(100.0f * a[v], b[v])));
      EXPECT_LT(d, 1e-3) << m.clips[clip].name << " t " << t;  // centimetres
    }
  // And the file holds it.
  auto dir = test::temp_dir("demo_cm");
  ASSERT_TRUE(write_glb(dir + "/cm.glb", cm).ok());
  auto r = load_character(dir + "/cm.glb");
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_NEAR(bounding_box(r->primitives.at(0).positions).diagonal(), bounding_box(cm.primitives[0].positions).diagonal(), 1e-3);
  EXPECT_EQ(r->clips.size(), 3u);
}

}  // namespace
}  // namespace cagewrap
