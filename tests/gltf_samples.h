// Hand-built glTF files with known answers, written by the tests' own GltfBuilder; shared by
// the loader, skinning and animation tests and checked by the Khronos validator.
#pragma once

#include <cmath>
#include <string>

#include <glm/gtc/quaternion.hpp>

#include "core/character/character.h"
#include "tests/gltf_builder.h"

namespace cagewrap::test {

using nlohmann::json;

// Two joints: j0 at the origin, j1 at (0,1,0). Vertices on the y axis: (0,0.5,0) on j0,
// (0,1.5,0) on j1, (0,2,0) half and half. A clip turns j1 by 90 degrees about z over 1 s.
inline std::string write_two_joint_file(const std::string& name, bool rest_differs_from_bind = false) {
  GltfBuilder b;
  int pos = b.add_floats({0, 0.5f, 0, 0, 1.5f, 0, 0, 2, 0}, "VEC3", true);
  std::vector<uint8_t> joints = {0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0};
  std::vector<float> weights = {1, 0, 0, 0, 1, 0, 0, 0, 0.5f, 0.5f, 0, 0};
  int j = b.add_accessor(joints, "VEC4", test::kUnsignedByte);
  int w = b.add_floats(weights, "VEC4");
  std::vector<uint16_t> tri = {0, 1, 2};
  int ix = b.add_accessor(tri, "SCALAR", test::kUnsignedShort);
  b.doc["meshes"].push_back(
      {{"name", "arm"}, {"primitives", {{{"attributes", {{"POSITION", pos}, {"JOINTS_0", j}, {"WEIGHTS_0", w}}}, {"indices", ix}}}}});
  // The rest pose of the nodes can differ from the bind pose the inverse bind matrices define.
  json j1 = {{"name", "j1"}, {"translation", {0, rest_differs_from_bind ? 3 : 1, 0}}};
  int child = b.add_node(j1);
  int root = b.add_node({{"name", "j0"}, {"children", {child}}});
  std::vector<float> ibm = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1,   // j0 bound at the origin
                            1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -1, 0, 1};  // j1 bound at (0,1,0)
  b.doc["skins"].push_back({{"joints", {root, child}}, {"inverseBindMatrices", b.add_floats(ibm, "MAT4")}});
  int mesh_node = b.add_node({{"name", "arm_mesh"}, {"mesh", 0}, {"skin", 0}});
  b.set_scene({root, mesh_node});
  const float s = std::sqrt(0.5f);
  int times = b.add_floats({0, 1}, "SCALAR", true);
  int rot = b.add_floats({0, 0, 0, 1, 0, 0, s, s}, "VEC4");
  b.doc["animations"].push_back({{"name", "bend"},
                                 {"samplers", {{{"input", times}, {"output", rot}}}},
                                 {"channels", {{{"sampler", 0}, {"target", {{"node", child}, {"path", "rotation"}}}}}}});
  auto dir = test::temp_dir(name);
  b.write_embedded(dir + "/two_joints.gltf");
  return dir + "/two_joints.gltf";
}

// One animated node "n" and three clips, one per interpolation mode plus a rotation.
// Translation x keys: times 0, 1, 3 with values 0, 10, 30.
inline std::string write_interpolation_file(const std::string& name) {
  GltfBuilder b;
  b.set_scene({b.add_node({{"name", "n"}, {"translation", {0, 0, 0}}})});
  int times = b.add_floats({0, 1, 3}, "SCALAR", true);
  int values = b.add_floats({0, 0, 0, 10, 0, 0, 30, 0, 0}, "VEC3");
  // LINEAR rotation: identity to 90 degrees about z over 0..2 s.
  const float s = std::sqrt(0.5f);
  int rot_times = b.add_floats({0, 2}, "SCALAR", true);
  int rot_values = b.add_floats({0, 0, 0, 1, 0, 0, s, s}, "VEC4");
  // CUBICSPLINE: two keys at 0 and 2 s, x from 0 to 1, out-tangent of key 0 = (1,0,0), in-tangent
  // of key 1 = (0,0,0). Per key: in-tangent, value, out-tangent.
  int cubic_times = b.add_floats({0, 2}, "SCALAR", true);
  int cubic_values = b.add_floats({9, 9, 9, 0, 0, 0, 1, 0, 0, /**/ 0, 0, 0, 1, 0, 0, 9, 9, 9}, "VEC3");
  auto clip = [&](const std::string& clip_name, const std::string& interp, int in, int out, const std::string& path) {
    return json{{"name", clip_name},
                {"samplers", {{{"input", in}, {"output", out}, {"interpolation", interp}}}},
                {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", path}}}}}}};
  };
  b.doc["animations"].push_back(clip("step", "STEP", times, values, "translation"));
  b.doc["animations"].push_back(clip("linear", "LINEAR", times, values, "translation"));
  b.doc["animations"].push_back(clip("cubic", "CUBICSPLINE", cubic_times, cubic_values, "translation"));
  b.doc["animations"].push_back(clip("turn", "LINEAR", rot_times, rot_values, "rotation"));
  auto dir = test::temp_dir(name);
  b.write_embedded(dir + "/anim.gltf");
  return dir + "/anim.gltf";
}

// A character exercising what the writer supports: a six-joint chain, a matrix node with a rigid
// mesh, a skinned mesh of two primitives with six influences on some vertices (two JOINTS/WEIGHTS
// sets), a morph target, and STEP / CUBICSPLINE / weights channels.
inline Character sample_character() {
  std::vector<SkeletonNode> nodes(7);
  nodes[0].name = "root";
  nodes[0].rest.translation = {0, 1, 0};
  for (int i = 1; i < 6; ++i) {
    nodes[i].name = "bone" + std::to_string(i);
    nodes[i].parent = i - 1;
    nodes[i].rest.translation = {0, 0.5f, 0};
    nodes[i].rest.rotation = glm::angleAxis(0.1f * i, glm::vec3(0, 0, 1));
  }
  nodes[6].name = "prop";
  nodes[6].has_matrix = true;
  nodes[6].matrix = glm::mat4(2.0f);
  nodes[6].matrix[3] = glm::vec4(1, 2, 3, 1);
  Character c;
  c.skeleton = Skeleton::create(nodes, "sample").value();
  Skin skin;
  skin.name = "chain";
  auto g = c.skeleton.global_transforms(c.skeleton.rest_pose());
  for (uint32_t j = 0; j < 6; ++j) {
    skin.joints.push_back(j);
    skin.inverse_bind.push_back(glm::inverse(g[j]));
  }
  c.skins.push_back(skin);
  for (uint32_t k = 0; k < 2; ++k) {
    Primitive p;
    p.mesh_name = "tube";
    p.mesh = 0;
    p.primitive = k;
    p.node = 0;
    p.skin = 0;
    for (int v = 0; v < 6; ++v) p.positions.push_back({float(v % 2), 1.0f + 0.4f * v + k, 0.0f});
    p.triangles = {{0, 1, 2}, {2, 1, 3}, {2, 3, 4}, {4, 3, 5}};
    p.influence_start = {0};
    for (int v = 0; v < 6; ++v) {
      int n = v < 3 ? 1 : 6;  // six influences spill into JOINTS_1/WEIGHTS_1
      for (int i = 0; i < n; ++i) {
        p.influence_joint.push_back(static_cast<uint16_t>((v + i) % 6));
        p.influence_weight.push_back(n == 1 ? 1.0f : (6 - i) / 21.0f);  // distinct, decreasing
      }
      p.influence_start.push_back(static_cast<uint32_t>(p.influence_joint.size()));
    }
    if (k == 0) {
      p.morph_targets.push_back(std::vector<glm::vec3>(6, glm::vec3(0, 0, 0.5f)));
      p.morph_weights = {0.2f};
    }
    c.primitives.push_back(p);
  }
  // The second primitive has no morph target in this mesh: glTF needs the same count per mesh.
  c.primitives[1].morph_targets.push_back(std::vector<glm::vec3>(6, glm::vec3(0.0f)));
  c.primitives[1].morph_weights = {0.2f};
  Primitive rigid;
  rigid.mesh_name = "box";
  rigid.mesh = 1;
  rigid.node = 6;
  rigid.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  rigid.triangles = {{0, 1, 2}};
  c.primitives.push_back(rigid);
  Clip clip;
  clip.name = "mixed";
  AnimationSampler step{Interpolation::kStep, {0, 1}, {0, 1, 0, 0, 2, 0}, 3};
  AnimationSampler cubic{Interpolation::kCubicSpline, {0, 2}, {0, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0}, 4};
  // cubic rotation keys: in-tangent, value, out-tangent per key (x, y, z, w)
  cubic.values = {0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0.5f, 0, /**/ 0, 0, 0, 0, 0, 0, 0.7071068f, 0.7071068f, 0, 0, 0, 0};
  AnimationSampler weights{Interpolation::kLinear, {0, 1}, {0, 1}, 1};
  clip.samplers = {step, cubic, weights};
  clip.channels = {{1, ChannelPath::kTranslation, 0}, {2, ChannelPath::kRotation, 1}, {0, ChannelPath::kWeights, 2}};
  clip.duration = 2.0;
  c.clips.push_back(clip);
  return c;
}

}  // namespace cagewrap::test
