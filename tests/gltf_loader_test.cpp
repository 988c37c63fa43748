#include <chrono>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <gtest/gtest.h>

#include "core/io/gltf_loader.h"
#include "core/character/skinning.h"
#include "tests/gltf_builder.h"
#include "tests/test_assets.h"

namespace cagewrap {
namespace {

using nlohmann::json;
using test::GltfBuilder;

// A unit-square grid of n x n vertices in the z = 0 plane, as a flat position list.
std::vector<float> grid_positions(int n) {
  std::vector<float> p;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) p.insert(p.end(), {float(x), float(y), 0.0f});
  return p;
}

// One node instancing one mesh with a single primitive of `positions` and `indices`.
GltfBuilder single_primitive(const std::vector<float>& positions, const std::vector<uint16_t>& indices,
                             const std::string& mesh_name = "plate") {
  GltfBuilder b;
  int pos = b.add_floats(positions, "VEC3", true);
  json prim = {{"attributes", {{"POSITION", pos}}}};
  if (!indices.empty()) prim["indices"] = b.add_accessor(indices, "SCALAR", test::kUnsignedShort);
  b.doc["meshes"].push_back({{"name", mesh_name}, {"primitives", {prim}}});
  b.set_scene({b.add_node({{"name", "plate_node"}, {"mesh", 0}})});
  return b;
}

Character load_ok(const std::string& path) {
  auto c = load_character(path);
  EXPECT_TRUE(c.ok()) << (c.ok() ? "" : c.error().message);
  if (!c.ok()) return {};
  return std::move(c).value();
}

TEST(GltfLoader, ListsStripsAndFansBecomeTriangles) {
  GltfBuilder b;
  int pos = b.add_floats(grid_positions(3), "VEC3", true);  // 9 vertices
  std::vector<uint16_t> list = {0, 1, 4, 0, 4, 3};
  std::vector<uint16_t> strip = {0, 3, 1, 4, 2};
  std::vector<uint16_t> fan = {4, 0, 1, 2, 5};
  json prims = json::array();
  prims.push_back({{"attributes", {{"POSITION", pos}}}, {"indices", b.add_accessor(list, "SCALAR", test::kUnsignedShort)}});
  prims.push_back({{"attributes", {{"POSITION", pos}}}, {"indices", b.add_accessor(strip, "SCALAR", test::kUnsignedShort)}, {"mode", 5}});
  prims.push_back({{"attributes", {{"POSITION", pos}}}, {"indices", b.add_accessor(fan, "SCALAR", test::kUnsignedShort)}, {"mode", 6}});
  prims.push_back({{"attributes", {{"POSITION", pos}}}, {"mode", 1}});  // lines: vertices, no triangles
  b.doc["meshes"].push_back({{"name", "modes"}, {"primitives", prims}});
  b.set_scene({b.add_node({{"mesh", 0}})});
  auto dir = test::temp_dir("modes");
  b.write_embedded(dir + "/modes.gltf");
  Character c = load_ok(dir + "/modes.gltf");
  ASSERT_EQ(c.primitives.size(), 4u);
  EXPECT_EQ(c.primitives[0].triangles, (std::vector<Tri>{{0, 1, 4}, {0, 4, 3}}));
  // glTF strip: triangle i is (i, i+1, i+2) with the first two swapped on odd i.
  EXPECT_EQ(c.primitives[1].triangles, (std::vector<Tri>{{0, 3, 1}, {1, 3, 4}, {1, 4, 2}}));
  // glTF fan: triangle i is (i+1, i+2, 0).
  EXPECT_EQ(c.primitives[2].triangles, (std::vector<Tri>{{0, 1, 4}, {1, 2, 4}, {2, 5, 4}}));
  EXPECT_TRUE(c.primitives[3].triangles.empty());
  EXPECT_EQ(c.primitives[3].num_vertices(), 9u);
  ASSERT_EQ(c.warnings.size(), 1u);
  EXPECT_NE(c.warnings[0].find("1 primitive(s) are points or lines (e.g. mesh 0 ('modes') primitive 3)"), std::string::npos)
      << c.warnings[0];
  EXPECT_EQ(c.num_triangles(), 8u);
}

TEST(GltfLoader, NodeHierarchyWithTrsAndMatrixGivesGlobalTransforms) {
  GltfBuilder b = single_primitive({0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2});
  b.doc["nodes"].clear();
  // root: T(1,2,3) R(90 deg about z); middle: matrix = uniform scale 2 then translate (0,0,5);
  // leaf: T(1,0,0) with the mesh.
  const float s = std::sqrt(0.5f);
  int leaf = b.add_node({{"name", "leaf"}, {"translation", {1, 0, 0}}, {"mesh", 0}});
  json m = {2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 0, 0, 5, 1};
  int middle = b.add_node({{"name", "middle"}, {"matrix", m}, {"children", {leaf}}});
  int root = b.add_node({{"name", "root"}, {"translation", {1, 2, 3}}, {"rotation", {0, 0, s, s}}, {"children", {middle}}});
  b.set_scene({root});
  auto dir = test::temp_dir("hierarchy");
  b.write_glb(dir + "/h.glb");
  Character c = load_ok(dir + "/h.glb");
  ASSERT_EQ(c.skeleton.size(), 3u);
  EXPECT_EQ(c.skeleton.node(leaf).parent, middle);
  EXPECT_EQ(c.skeleton.node(middle).parent, root);
  EXPECT_TRUE(c.skeleton.node(middle).has_matrix);
  EXPECT_EQ(c.skeleton.find("leaf"), leaf);
  // Parents come before children in the FK order even though the file lists the leaf first.
  EXPECT_EQ(c.skeleton.order().front(), static_cast<uint32_t>(root));
  auto g = c.skeleton.global_transforms(c.skeleton.rest_pose());
  // The leaf origin: (1,0,0) -> scale 2 -> (2,0,0) + (0,0,5) -> rotate 90 about z -> (0,2,5) + (1,2,3).
  glm::vec3 o = g[leaf] * glm::vec4(0, 0, 0, 1);
  EXPECT_NEAR(o.x, 1.0f, 1e-5);
  EXPECT_NEAR(o.y, 4.0f, 1e-5);
  EXPECT_NEAR(o.z, 8.0f, 1e-5);
  // The unskinned primitive moves with its node: vertex (1,0,0) -> (2,0,0) scaled -> +leaf...
  auto posed = skin_character(c, c.skeleton.rest_pose());
  ASSERT_EQ(posed.size(), 3u);
  // vertex (1,0,0): leaf (2,0,0) -> middle (4,0,5) -> root rotate (0,4,5) + (1,2,3) = (1,6,8)
  EXPECT_NEAR(posed[1].x, 1.0f, 1e-5);
  EXPECT_NEAR(posed[1].y, 6.0f, 1e-5);
  EXPECT_NEAR(posed[1].z, 8.0f, 1e-5);
  // The raw POSITION data is the bind pose, untouched.
  EXPECT_EQ(c.primitives[0].positions[1], glm::vec3(1, 0, 0));
}

TEST(GltfLoader, EmbeddedExternalAndBinaryBuffersLoadAlike) {
  GltfBuilder b = single_primitive(grid_positions(2), {0, 1, 3, 0, 3, 2});
  auto dir = test::temp_dir("buffers");
  b.write_embedded(dir + "/a.gltf");
  b.write_external(dir + "/b.gltf", "b_data.bin");
  b.write_glb(dir + "/c.glb");
  Character a = load_ok(dir + "/a.gltf"), e = load_ok(dir + "/b.gltf"), g = load_ok(dir + "/c.glb");
  ASSERT_EQ(a.primitives.size(), 1u);
  ASSERT_EQ(e.primitives.size(), 1u);
  ASSERT_EQ(g.primitives.size(), 1u);
  EXPECT_EQ(a.primitives[0].positions, e.primitives[0].positions);
  EXPECT_EQ(a.primitives[0].positions, g.primitives[0].positions);
  EXPECT_EQ(a.primitives[0].triangles, g.primitives[0].triangles);
  EXPECT_EQ(a.primitives[0].positions[3], glm::vec3(1, 1, 0));
  EXPECT_TRUE(a.warnings.empty());
}

// Two joints along y; vertex weights given in `joints`/`weights` as 4 per vertex.
template <class J, class W>
GltfBuilder skinned_plate(const std::vector<J>& joints, int joint_type, const std::vector<W>& weights,
                          int weight_type, bool normalized, int vertices) {
  GltfBuilder b;
  std::vector<float> pos;
  for (int v = 0; v < vertices; ++v) pos.insert(pos.end(), {float(v), 0, 0});
  int p = b.add_floats(pos, "VEC3", true);
  int j = b.add_accessor(joints, "VEC4", joint_type);
  int w = b.add_accessor(weights, "VEC4", weight_type, normalized);
  std::vector<uint16_t> tri = {0, 0, 0};  // one (degenerate) triangle: the weights are what matters here
  int ix = b.add_accessor(tri, "SCALAR", test::kUnsignedShort);
  b.doc["meshes"].push_back({{"name", "messy"},
                             {"primitives", {{{"attributes", {{"POSITION", p}, {"JOINTS_0", j}, {"WEIGHTS_0", w}}},
                                              {"indices", ix}}}}});
  int child = b.add_node({{"name", "j1"}, {"translation", {0, 1, 0}}});
  int root = b.add_node({{"name", "j0"}, {"children", {child}}});
  std::vector<float> ibm = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -1, 0, 1};
  b.doc["skins"].push_back({{"name", "rig"}, {"joints", {root, child}}, {"inverseBindMatrices", b.add_floats(ibm, "MAT4")}});
  int mesh_node = b.add_node({{"name", "body"}, {"mesh", 0}, {"skin", 0}});
  b.set_scene({root, mesh_node});
  return b;
}

std::vector<std::pair<uint16_t, float>> influences(const Primitive& p, size_t v) {
  std::vector<std::pair<uint16_t, float>> out;
  for (uint32_t k = p.influence_start[v]; k < p.influence_start[v + 1]; ++k)
    out.emplace_back(p.influence_joint[k], p.influence_weight[k]);
  return out;
}

TEST(GltfLoader, WeightComponentTypesAndSecondSet) {
  auto dir = test::temp_dir("weight_types");
  // Unsigned-byte joints with normalized unsigned-byte weights: 191/255 + 64/255 = 1.
  {
    GltfBuilder b = skinned_plate<uint8_t, uint8_t>({0, 1, 0, 0}, test::kUnsignedByte, {191, 64, 0, 0},
                                                    test::kUnsignedByte, true, 1);
    b.write_embedded(dir + "/u8.gltf");
    Character c = load_ok(dir + "/u8.gltf");
    ASSERT_EQ(c.primitives.size(), 1u);
    auto inf = influences(c.primitives[0], 0);
    ASSERT_EQ(inf.size(), 2u);
    EXPECT_EQ(inf[0].first, 0);
    EXPECT_NEAR(inf[0].second, 191.0 / 255.0, 1e-6);
    EXPECT_NEAR(inf[1].second, 64.0 / 255.0, 1e-6);
    EXPECT_TRUE(c.warnings.empty()) << c.warnings[0];
  }
  // Unsigned-short joints with normalized unsigned-short weights.
  {
    GltfBuilder b = skinned_plate<uint16_t, uint16_t>({1, 0, 0, 0}, test::kUnsignedShort, {16384, 49151, 0, 0},
                                                      test::kUnsignedShort, true, 1);
    b.write_embedded(dir + "/u16.gltf");
    Character c = load_ok(dir + "/u16.gltf");
    auto inf = influences(c.primitives[0], 0);
    ASSERT_EQ(inf.size(), 2u);
    EXPECT_EQ(inf[0].first, 0);  // sorted by weight, heaviest first
    EXPECT_NEAR(inf[0].second, 49151.0 / 65535.0, 1e-6);
    EXPECT_EQ(inf[1].first, 1);
  }
  // Float weights over two sets (JOINTS_1/WEIGHTS_1): 8 slots.
  {
    GltfBuilder b = skinned_plate<uint8_t, float>({0, 0, 0, 0}, test::kUnsignedByte, {0.6f, 0, 0, 0}, test::kFloat,
                                                  false, 1);
    std::vector<uint8_t> j1 = {1, 0, 0, 0};
    std::vector<float> w1 = {0.4f, 0, 0, 0};
    b.doc["meshes"][0]["primitives"][0]["attributes"]["JOINTS_1"] = b.add_accessor(j1, "VEC4", test::kUnsignedByte);
    b.doc["meshes"][0]["primitives"][0]["attributes"]["WEIGHTS_1"] = b.add_floats(w1, "VEC4");
    b.write_embedded(dir + "/two_sets.gltf");
    Character c = load_ok(dir + "/two_sets.gltf");
    auto inf = influences(c.primitives[0], 0);
    ASSERT_EQ(inf.size(), 2u);
    EXPECT_EQ(inf[1].first, 1);
    EXPECT_FLOAT_EQ(inf[1].second, 0.4f);
    EXPECT_TRUE(c.warnings.empty());
  }
}

TEST(GltfLoader, MessyWeightsAreCleanedWithCountedWarnings) {
  // v0 fine; v1 sums to 0.5; v2 lists joint 1 with zero weight; v3 lists joint 1 twice; v4 sums to 2.
  std::vector<uint8_t> joints = {0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 0, 1, 0, 0};
  std::vector<float> weights = {0.5f, 0.5f, 0, 0, 0.25f, 0.25f, 0, 0, 1.0f, 0.0f, 0, 0, 0.5f, 0.5f, 0, 0, 1.0f, 1.0f, 0, 0};
  GltfBuilder b = skinned_plate(joints, test::kUnsignedByte, weights, test::kFloat, false, 5);
  auto dir = test::temp_dir("messy");
  b.write_embedded(dir + "/messy.gltf");
  Character c = load_ok(dir + "/messy.gltf");
  ASSERT_EQ(c.primitives.size(), 1u);
  const Primitive& p = c.primitives[0];
  for (size_t v = 0; v < 5; ++v) {
    float sum = 0;
    for (auto [j, w] : influences(p, v)) sum += w;
    EXPECT_NEAR(sum, 1.0f, 1e-6) << "vertex " << v;
  }
  EXPECT_EQ(influences(p, 1), (std::vector<std::pair<uint16_t, float>>{{0, 0.5f}, {1, 0.5f}}));
  EXPECT_EQ(influences(p, 2), (std::vector<std::pair<uint16_t, float>>{{0, 1.0f}}));
  EXPECT_EQ(influences(p, 3), (std::vector<std::pair<uint16_t, float>>{{1, 1.0f}}));
  ASSERT_EQ(c.warnings.size(), 3u);
  auto has = [&](const std::string& text) {
    for (const auto& w : c.warnings)
      if (w.find(text) != std::string::npos) return true;
    return false;
  };
  const std::string where = "mesh 0 ('messy') primitive 0: ";
  EXPECT_TRUE(has(where + "2 vertices have weights that do not sum to one (e.g. vertex 1 sums to 0.5")) << c.warnings[0];
  EXPECT_TRUE(has(where + "1 vertices list joints with zero weight (e.g. vertex 2); ignored"));
  // v3 lists joint 1 twice (merged); the renormalized count covers v1 and v4.
  EXPECT_TRUE(has(where + "1 vertices list the same joint more than once (e.g. vertex 3)"));
  for (const auto& w : c.warnings) EXPECT_EQ(w.rfind(dir + "/messy.gltf: ", 0), 0u) << w;
}

std::string load_error(const std::string& path) {
  auto c = load_character(path);
  EXPECT_FALSE(c.ok()) << path << " loaded but should not";
  return c.ok() ? "" : c.error().message;
}

TEST(GltfLoader, UnusableFilesNameTheObjectAndIndex) {
  auto dir = test::temp_dir("errors");
  // Missing external buffer.
  {
    GltfBuilder b = single_primitive(grid_positions(2), {0, 1, 3});
    b.write_external(dir + "/missing.gltf", "missing.bin");
    std::filesystem::remove(dir + "/missing.bin");
    std::string e = load_error(dir + "/missing.gltf");
    EXPECT_NE(e.find("buffer 0 refers to 'missing.bin', which does not exist"), std::string::npos) << e;
    EXPECT_EQ(e.rfind(dir + "/missing.gltf: ", 0), 0u) << e;
  }
  // Index out of range.
  {
    GltfBuilder b = single_primitive(grid_positions(2), {0, 1, 7}, "bad_indices");
    b.write_embedded(dir + "/index.gltf");
    std::string e = load_error(dir + "/index.gltf");
    EXPECT_NE(e.find("mesh 0 ('bad_indices') primitive 0: index 7 at position 2 of accessor 1 is out of range (the "
                     "primitive has 4 vertices)"),
              std::string::npos)
        << e;
  }
  // Geometry compressed with an extension the loader cannot decode: named, with what to do.
  {
    GltfBuilder b = single_primitive(grid_positions(2), {0, 1, 3});
    b.doc["extensionsUsed"] = {"KHR_draco_mesh_compression"};
    b.doc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
    b.write_embedded(dir + "/draco.gltf");
    std::string e = load_error(dir + "/draco.gltf");
    EXPECT_EQ(e.rfind(dir + "/draco.gltf: its meshes are compressed with KHR_draco_mesh_compression, which cagewrap does not "
                            "read; save it uncompressed",
                      0),
              0u)
        << e;
  }
  // Cyclic hierarchy: 0 -> 1 -> 2 -> 1.
  {
    GltfBuilder b = single_primitive(grid_positions(2), {0, 1, 3});
    b.doc["nodes"] = json::array({{{"name", "a"}, {"children", {1}}, {"mesh", 0}},
                                  {{"name", "b"}, {"children", {2}}},
                                  {{"name", "c"}, {"children", {1}}}});
    b.set_scene({0});
    b.write_embedded(dir + "/cycle.gltf");
    std::string e = load_error(dir + "/cycle.gltf");
    // Node 1 gets two parents (0 and 2): the hierarchy is not a tree.
    EXPECT_NE(e.find("node 1 ('b') is a child of both node 0 and node 2"), std::string::npos) << e;
  }
  {
    GltfBuilder b = single_primitive(grid_positions(2), {0, 1, 3});
    b.doc["nodes"] = json::array({{{"name", "a"}, {"children", {1}}, {"mesh", 0}}, {{"name", "b"}, {"children", {0}}}});
    b.set_scene({0});
    b.write_embedded(dir + "/cycle2.gltf");
    std::string e = load_error(dir + "/cycle2.gltf");
    EXPECT_NE(e.find("is its own ancestor (cycle 0 -> 1 -> 0)"), std::string::npos) << e;
  }
  // Accessor past its buffer view.
  {
    GltfBuilder b = single_primitive(grid_positions(2), {0, 1, 3});
    b.doc["accessors"][0]["count"] = 40;
    b.write_embedded(dir + "/past.gltf");
    std::string e = load_error(dir + "/past.gltf");
    EXPECT_NE(e.find("accessor 0 (mesh 0 ('plate') primitive 0 POSITION) needs 480 bytes but bufferView 0 holds 48 "
                     "(count 40, 12 bytes apart from byteOffset 0)"),
              std::string::npos)
        << e;
  }
  // A billion elements claimed by a file of a few hundred bytes: refused before anything is allocated,
  // with the sizes grouped by thousands.
  {
    GltfBuilder b = single_primitive(grid_positions(2), {0, 1, 3});
    b.doc["accessors"][0]["count"] = 1000000000;
    b.write_embedded(dir + "/billion.gltf");
    std::string e = load_error(dir + "/billion.gltf");
    EXPECT_NE(e.find("POSITION) needs 12,000,000,000 bytes but bufferView 0 holds 48"), std::string::npos) << e;
  }
  // No bufferView (zeros, a sparse accessor's base): the count is bounded by the file's buffers.
  {
    GltfBuilder b = single_primitive(grid_positions(2), {0, 1, 3});
    b.doc["accessors"][0].erase("bufferView");
    b.doc["accessors"][0]["count"] = 3000000000ull;
    b.write_embedded(dir + "/zeros.gltf");
    std::string e = load_error(dir + "/zeros.gltf");
    EXPECT_NE(e.find("has no bufferView and claims 3,000,000,000 elements"), std::string::npos) << e;
  }
  // Buffer view past its buffer.
  {
    GltfBuilder b = single_primitive(grid_positions(2), {0, 1, 3});
    b.doc["bufferViews"][1]["byteLength"] = 4000;
    b.write_glb(dir + "/view.glb");
    std::string e = load_error(dir + "/view.glb");
    EXPECT_NE(e.find("bufferView 1 spans bytes 48..4,048 of buffer 0, which holds only 54 bytes"), std::string::npos) << e;
  }
  // A GLB buffer of length 0: tinygltf throws (std::out_of_range) reading it; the loader reports it.
  {
    GltfBuilder b = single_primitive(grid_positions(2), {0, 1, 3});
    b.doc["buffers"] = json::array({{{"byteLength", 0}}});
    b.write_glb(dir + "/empty_buffer.glb");
    std::string e = load_error(dir + "/empty_buffer.glb");
    EXPECT_EQ(e.rfind(dir + "/empty_buffer.glb: ", 0), 0u) << e;
    EXPECT_NE(e.find("buffer 0 has no usable byteLength"), std::string::npos) << e;
  }
  // Joint index beyond the skin.
  {
    GltfBuilder b = skinned_plate<uint8_t, float>({0, 9, 0, 0}, test::kUnsignedByte, {0.5f, 0.5f, 0, 0}, test::kFloat,
                                                  false, 1);
    b.write_embedded(dir + "/joint.gltf");
    std::string e = load_error(dir + "/joint.gltf");
    EXPECT_NE(e.find("mesh 0 ('messy') primitive 0 vertex 0: JOINTS_0 lists joint 9, but skin 0 ('rig') has 2 joints"),
              std::string::npos)
        << e;
  }
  // Joints and indices of a signed component type (the spec allows only unsigned ones: a signed
  // type could hold a negative index, as the fuzzer found).
  {
    GltfBuilder b = skinned_plate<int8_t, float>({0, -128, 0, 0}, test::kByte, {0.5f, 0.5f, 0, 0}, test::kFloat,
                                                 false, 1);
    b.write_embedded(dir + "/negative_joint.gltf");
    std::string e = load_error(dir + "/negative_joint.gltf");
    EXPECT_NE(e.find("(mesh 0 ('messy') primitive 0 JOINTS_0) has component type 5120, expected an unsigned integer "
                     "type"),
              std::string::npos)
        << e;
  }
  {
    GltfBuilder b;
    int p = b.add_floats(grid_positions(2), "VEC3", true);
    int ix = b.add_accessor(std::vector<int16_t>{0, 1, -32768}, "SCALAR", test::kShort);
    b.doc["meshes"].push_back({{"name", "signed"}, {"primitives", {{{"attributes", {{"POSITION", p}}}, {"indices", ix}}}}});
    b.add_node({{"mesh", 0}});
    b.set_scene({0});
    b.write_embedded(dir + "/signed_indices.gltf");
    std::string e = load_error(dir + "/signed_indices.gltf");
    EXPECT_NE(e.find("(mesh 0 ('signed') primitive 0 indices) has component type 5122, expected an unsigned integer "
                     "type"),
              std::string::npos)
        << e;
  }
  // Not glTF at all, and no file.
  {
    std::ofstream(dir + "/junk.gltf") << "{ not json";
    std::string e = load_error(dir + "/junk.gltf");
    EXPECT_NE(e.find("junk.gltf: not a usable glTF 2.0 file"), std::string::npos) << e;
    auto c = load_character(dir + "/nothing.glb");
    ASSERT_FALSE(c.ok());
    EXPECT_EQ(c.error().code, ErrorCode::kFileNotFound);
  }
}

TEST(GltfLoader, SparseAccessorsAndMorphTargets) {
  GltfBuilder b;
  // Base positions (4 vertices), then a sparse override of vertices 1 and 3.
  int p = b.add_floats(grid_positions(2), "VEC3", true);
  std::vector<uint16_t> sp_idx = {1, 3};
  std::vector<float> sp_val = {5, 5, 5, 7, 7, 7};
  int iv = b.add_view(sp_idx.data(), sp_idx.size() * 2);
  int vv = b.add_view(sp_val.data(), sp_val.size() * 4);
  b.doc["accessors"][p]["sparse"] = {{"count", 2},
                                     {"indices", {{"bufferView", iv}, {"componentType", test::kUnsignedShort}}},
                                     {"values", {{"bufferView", vv}}}};
  // A morph target with no bufferView at all: zeros plus a sparse offset of vertex 2 by (0,0,1).
  std::vector<uint8_t> t_idx = {2, 0, 0, 0};
  std::vector<float> t_val = {0, 0, 1};
  int tiv = b.add_view(t_idx.data(), 1);
  int tvv = b.add_view(t_val.data(), 12);
  b.doc["accessors"].push_back({{"componentType", test::kFloat}, {"count", 4}, {"type", "VEC3"}, {"min", {0, 0, 0}},
                                {"max", {0, 0, 1}},
                                {"sparse", {{"count", 1},
                                            {"indices", {{"bufferView", tiv}, {"componentType", test::kUnsignedByte}}},
                                            {"values", {{"bufferView", tvv}}}}}});
  int target = static_cast<int>(b.doc["accessors"].size()) - 1;
  b.doc["meshes"].push_back({{"name", "morph"},
                             {"weights", {0.25}},
                             {"primitives", {{{"attributes", {{"POSITION", p}}}, {"targets", {{{"POSITION", target}}}}}}}});
  b.set_scene({b.add_node({{"mesh", 0}})});
  auto dir = test::temp_dir("sparse");
  b.write_embedded(dir + "/sparse.gltf");
  Character c = load_ok(dir + "/sparse.gltf");
  ASSERT_EQ(c.primitives.size(), 1u);
  const Primitive& prim = c.primitives[0];
  EXPECT_EQ(prim.positions[0], glm::vec3(0, 0, 0));
  EXPECT_EQ(prim.positions[1], glm::vec3(5, 5, 5));
  EXPECT_EQ(prim.positions[2], glm::vec3(0, 1, 0));
  EXPECT_EQ(prim.positions[3], glm::vec3(7, 7, 7));
  ASSERT_EQ(prim.morph_targets.size(), 1u);
  EXPECT_EQ(prim.morph_targets[0][2], glm::vec3(0, 0, 1));
  EXPECT_EQ(prim.morph_targets[0][0], glm::vec3(0, 0, 0));
  ASSERT_EQ(prim.morph_weights.size(), 1u);
  EXPECT_FLOAT_EQ(prim.morph_weights[0], 0.25f);
  // Default weights apply when posing; a pose's weights override them.
  Pose pose = c.skeleton.rest_pose();
  auto posed = skin_character(c, pose);
  EXPECT_FLOAT_EQ(posed[2].z, 0.25f);
  pose.morph_weights[prim.node] = {1.0f};
  posed = skin_character(c, pose);
  EXPECT_FLOAT_EQ(posed[2].z, 1.0f);
}

TEST(GltfLoader, MannequinyLoadsWithoutErrors) {
  auto path = test::shared_asset("mannequiny.glb");
  if (!path) GTEST_SKIP() << "shared assets folder (mannequiny.glb) not found; set CAGEWRAP_SHARED_ASSETS";
  auto start = std::chrono::steady_clock::now();
  auto c = load_character(*path);
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_TRUE(c.ok()) << c.error().message;
  EXPECT_EQ(c->primitives.size(), 3u);
  ASSERT_EQ(c->skins.size(), 1u);
  EXPECT_EQ(c->skins[0].joints.size(), 45u);
  EXPECT_EQ(c->num_joints(), 45u);
  EXPECT_EQ(c->clips.size(), 10u);
  EXPECT_GE(c->find_clip("run"), 0);
  EXPECT_EQ(c->num_vertices(), 10366u);  // stated by the asset's README
  for (const Primitive& p : c->primitives) {
    EXPECT_EQ(p.skin, 0);
    EXPECT_FALSE(p.triangles.empty());
    ASSERT_EQ(p.influence_start.size(), p.num_vertices() + 1);
    for (size_t v = 0; v < p.num_vertices(); ++v) {
      float sum = 0;
      for (uint32_t k = p.influence_start[v]; k < p.influence_start[v + 1]; ++k) sum += p.influence_weight[k];
      ASSERT_NEAR(sum, 1.0f, 1e-5) << p.label() << " vertex " << v;
    }
  }
  for (const Clip& clip : c->clips) EXPECT_GT(clip.duration, 0.0) << clip.name;
  for (const auto& w : c->warnings) std::printf("warning: %s\n", w.c_str());
  std::printf("mannequiny.glb loaded in %.3f s\n", seconds);
  RecordProperty("load_seconds", std::to_string(seconds));  // timing belongs to benchmarks, not assertions
}

TEST(GltfLoader, OtherRealAssetsLoad) {
  auto dir = test::shared_assets_dir();
  if (!dir) GTEST_SKIP() << "shared assets folder not found; set CAGEWRAP_SHARED_ASSETS";
  size_t loaded = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(*dir)) {
    auto ext = entry.path().extension().string();
    if (ext != ".glb" && ext != ".gltf") continue;
    auto c = load_character(entry.path().string());
    EXPECT_TRUE(c.ok()) << (c.ok() ? "" : c.error().message);
    ++loaded;
  }
  EXPECT_GE(loaded, 1u);
}

}  // namespace
}  // namespace cagewrap
