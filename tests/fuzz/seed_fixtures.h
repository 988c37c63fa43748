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

}  // namespace cagewrap::fuzz
