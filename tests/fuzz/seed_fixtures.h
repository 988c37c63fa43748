// Small valid files for the fuzz harnesses and their seed corpora (tests/fuzz/make_seeds.cpp).
#pragma once

#include <string>
#include <vector>

#include "tests/gltf_builder.h"

namespace cagewrap::fuzz {

// A tetrahedron: 4 vertices, 4 triangles, one node.
inline test::GltfBuilder tet_builder() {
  test::GltfBuilder b;
  std::vector<float> positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  std::vector<uint16_t> indices = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
  int pos = b.add_floats(positions, "VEC3", true);
  nlohmann::json prim = {{"attributes", {{"POSITION", pos}}},
                         {"indices", b.add_accessor(indices, "SCALAR", test::kUnsignedShort)}};
  b.doc["meshes"].push_back({{"name", "tet"}, {"primitives", {prim}}});
  b.set_scene({b.add_node({{"name", "tet_node"}, {"mesh", 0}})});
  return b;
}

inline void write_tet_gltf(const std::string& path) { tet_builder().write_embedded(path); }

// The tetrahedron skinned to two joints, "root" and its child "tip", with inverse bind matrices and a
// clip "wave" that moves the tip (LINEAR translation, three keys). Accessors: 0 POSITION, 1 indices,
// 2 JOINTS_0, 3 WEIGHTS_0, 4 inverseBindMatrices (MAT4), 5 the key times, 6 the translations.
inline test::GltfBuilder rig_builder() {
  test::GltfBuilder b = tet_builder();
  std::vector<uint8_t> joints = {0, 1, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 1, 0, 0, 0};
  std::vector<float> weights = {0.5f, 0.5f, 0, 0, 1, 0, 0, 0, 0.25f, 0.75f, 0, 0, 1, 0, 0, 0};
  b.doc["meshes"][0]["primitives"][0]["attributes"]["JOINTS_0"] = b.add_accessor(joints, "VEC4", test::kUnsignedByte);
  b.doc["meshes"][0]["primitives"][0]["attributes"]["WEIGHTS_0"] = b.add_floats(weights, "VEC4");
  int tip = b.add_node({{"name", "tip"}, {"translation", {0, 1, 0}}});
  int root = b.add_node({{"name", "root"}, {"children", {tip}}});
  b.doc["nodes"][0]["skin"] = 0;
  // column-major: the root's is the identity, the tip's undoes its translation by (0, 1, 0)
  std::vector<float> inverse_bind = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1,
                                     1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -1, 0, 1};
  int ibm = b.add_floats(inverse_bind, "MAT4");
  b.doc["skins"] = nlohmann::json::array({{{"name", "rig"}, {"joints", {root, tip}}, {"inverseBindMatrices", ibm}}});
  int times = b.add_floats({0.0f, 0.5f, 1.0f}, "SCALAR", true);  // an input accessor needs min and max
  int moves = b.add_floats({0, 1, 0, 0.3f, 1, 0, 0, 1, 0}, "VEC3");
  b.doc["animations"] = nlohmann::json::array(
      {{{"name", "wave"},
        {"samplers", {{{"input", times}, {"output", moves}, {"interpolation", "LINEAR"}}}},
        {"channels", {{{"sampler", 0}, {"target", {{"node", tip}, {"path", "translation"}}}}}}}});
  b.set_scene({0, root});
  return b;
}

}  // namespace cagewrap::fuzz
