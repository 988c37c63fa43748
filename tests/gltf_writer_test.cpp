#include <cmath>

#include <gtest/gtest.h>

#include "core/io/gltf_loader.h"
#include "core/io/gltf_quantize.h"
#include "core/io/gltf_writer.h"
#include "core/character/skinning.h"
#include "tests/gltf_samples.h"

namespace cagewrap {
namespace {

using test::sample_character;

TEST(GltfWriter, RoundTripKeepsEverythingTheLoaderReads) {
  Character c = sample_character();
  auto dir = test::temp_dir("writer");
  ASSERT_TRUE(write_glb(dir + "/sample.glb", c).ok());
  auto r = load_character(dir + "/sample.glb");
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_TRUE(r->warnings.empty()) << r->warnings.front();
  ASSERT_EQ(r->skeleton.size(), c.skeleton.size());
  for (size_t i = 0; i < c.skeleton.size(); ++i) {
    EXPECT_EQ(r->skeleton.node(i).name, c.skeleton.node(i).name);
    EXPECT_EQ(r->skeleton.node(i).parent, c.skeleton.node(i).parent);
    EXPECT_EQ(r->skeleton.node(i).has_matrix, c.skeleton.node(i).has_matrix);
  }
  ASSERT_EQ(r->primitives.size(), 3u);
  for (size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(r->primitives[k].positions, c.primitives[k].positions);
    EXPECT_EQ(r->primitives[k].triangles, c.primitives[k].triangles);
    EXPECT_EQ(r->primitives[k].influence_start, c.primitives[k].influence_start);
    EXPECT_EQ(r->primitives[k].skin, c.primitives[k].skin);
  }
  EXPECT_EQ(r->primitives[2].node, 6u);
  EXPECT_EQ(r->primitives[0].influence_weight, c.primitives[0].influence_weight);
  EXPECT_EQ(r->primitives[0].num_influences(4), 6u);
  EXPECT_EQ(r->primitives[0].morph_weights, std::vector<float>{0.2f});
  ASSERT_EQ(r->clips.size(), 1u);
  EXPECT_EQ(r->clips[0].samplers.size(), 3u);
  EXPECT_EQ(r->clips[0].samplers[1].interpolation, Interpolation::kCubicSpline);
  // The same skinned positions at several times, morphs and the rigid matrix node included.
  for (double t : {0.0, 0.5, 1.0, 1.5, 2.0}) {
    auto a = skin_character(c, sample_pose(c, 0, t));
    auto b = skin_character(*r, sample_pose(*r, 0, t));
    ASSERT_EQ(a.size(), b.size());
    for (size_t v = 0; v < a.size(); ++v) EXPECT_LT(glm::length(a[v] - b[v]), 1e-6f) << "t " << t << " vertex " << v;
  }
  // The rigid box: matrix node scales by 2 and moves by (1,2,3).
  auto rest = skin_character(*r, r->skeleton.rest_pose());
  EXPECT_EQ(rest[12 + 1], glm::vec3(3, 2, 3));
  // Deterministic bytes.
  EXPECT_EQ(encode_glb(c), encode_glb(c));
}

// An inverse bind matrix whose last row a product rounded off (0.99999994) is written affine, as glTF requires.
TEST(GltfWriter, InverseBindMatricesAreWrittenAffine) {
  Character c = sample_character();
  ASSERT_FALSE(c.skins.empty());
  ASSERT_FALSE(c.skins[0].inverse_bind.empty());
  c.skins[0].inverse_bind[0][3][3] = 0.99999994f;
  c.skins[0].inverse_bind[0][0][3] = 1e-9f;
  auto dir = test::temp_dir("writer_affine");
  ASSERT_TRUE(write_glb(dir + "/affine.glb", c).ok());
  auto r = load_character(dir + "/affine.glb");
  ASSERT_TRUE(r.ok()) << r.error().message;
  for (const glm::mat4& m : r->skins[0].inverse_bind) {
    EXPECT_EQ(m[0][3], 0.0f);
    EXPECT_EQ(m[1][3], 0.0f);
    EXPECT_EQ(m[2][3], 0.0f);
    EXPECT_EQ(m[3][3], 1.0f);
  }
}

// The largest distance between the skinned positions of two characters at the clip's times.
float largest_gap(const Character& a, const Character& b) {
  float gap = 0.0f;
  for (double t : {0.0, 0.5, 1.0, 1.5, 2.0}) {
    auto x = skin_character(a, sample_pose(a, 0, t));
    auto y = skin_character(b, sample_pose(b, 0, t));
    EXPECT_EQ(x.size(), y.size());
    for (size_t v = 0; v < x.size() && v < y.size(); ++v) gap = std::max(gap, glm::length(x[v] - y[v]));
  }
  return gap;
}

std::string json_of(const std::vector<uint8_t>& glb) {
  auto text = glb_json_chunk(std::string(glb.begin(), glb.end()), "quantized.glb");
  EXPECT_TRUE(text.ok());
  return text ? *text : std::string();
}

TEST(GltfQuantize, WeightsSumToExactlyOne) {
  for (std::vector<float> w : {std::vector<float>{1.0f}, {0.5f, 0.5f}, {1 / 3.0f, 1 / 3.0f, 1 / 3.0f}, {0.7f, 0.2f, 0.1f, 1e-6f},
                               {6 / 21.0f, 5 / 21.0f, 4 / 21.0f, 3 / 21.0f, 2 / 21.0f, 1 / 21.0f}, {0.0f, 0.0f}}) {
    const std::vector<uint16_t> q = quantized_weights(w);
    ASSERT_EQ(q.size(), w.size());
    long sum = 0;
    for (size_t k = 0; k < q.size(); ++k) {
      sum += q[k];
      if (w[0] + w.back() > 0.0f) EXPECT_NEAR(q[k] / 65535.0, w[k], 1.0 / 65535.0) << "weight " << k;
    }
    EXPECT_EQ(sum, 65535);
  }
}

// A quantized file read back poses like the snapped character (what the export measures), within the
// quantization of the unsnapped one; positions and targets are SHORT and the extension is required.
TEST(GltfQuantize, ReadBackPosesLikeTheSnappedCharacter) {
  const Character c = sample_character();
  const GlbQuantization q = plan_glb_quantization(c);
  ASSERT_EQ(q.skins.size(), 1u);
  EXPECT_NEAR(q.skins[0].step, 1.5 / kQuantizedRange, 1e-9) << "the tube spans y 1..4: half of 3 units";
  ASSERT_EQ(q.nodes.count(6), 1u);
  Character snapped = c;
  snap_to_glb_quantization(snapped, q);
  EXPECT_NE(snapped.primitives[0].positions, c.primitives[0].positions) << "y steps of 0.4 are not on the grid";
  const std::vector<uint8_t> bytes = encode_glb(snapped, "test", &q);
  auto r = load_character_bytes(std::string(bytes.begin(), bytes.end()), "quantized.glb");
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_LT(largest_gap(*r, snapped), 1e-5f);
  EXPECT_LT(largest_gap(*r, c), 2 * q.skins[0].step * std::sqrt(3.0f) + 1e-5f);
  EXPECT_GT(largest_gap(*r, c), 0.0f) << "quantized positions differ from the floats";
  const std::string text = json_of(bytes);
  EXPECT_NE(text.find(R"("extensionsRequired":["KHR_mesh_quantization"])"), std::string::npos) << text;
  EXPECT_EQ(text.find(R"("componentType":5126,"count":6,"max")"), std::string::npos) << "a float POSITION is left";
  EXPECT_LT(glb_part_sizes(snapped, &q).mesh, glb_part_sizes(c).mesh * 2 / 3) << "8 + 4 bytes a vertex against 12 + 12";
  EXPECT_EQ(bytes, encode_glb(snapped, "test", &q)) << "deterministic";
}

// An unskinned mesh on a node that others see (a child, an animated transform) keeps its node: the
// dequantization goes on a child made to hold the mesh, and the node's weights channels go with it.
TEST(GltfQuantize, UnskinnedMeshOnANodeWithChildrenGetsAHolder) {
  Character c = sample_character();
  std::vector<SkeletonNode> nodes;
  for (size_t i = 0; i < c.skeleton.size(); ++i) nodes.push_back(c.skeleton.node(i));
  SkeletonNode child;
  child.name = "prop_child";
  child.parent = 6;
  child.rest.translation = {0, 1, 0};
  nodes.push_back(child);
  c.skeleton = Skeleton::create(nodes, "sample").value();
  c.primitives[2].morph_targets = {std::vector<glm::vec3>(3, glm::vec3(0, 0, 2)), std::vector<glm::vec3>(3, glm::vec3(1e-3f, 0, 0))};
  c.primitives[2].morph_weights = {0.0f, 1.0f};
  c.clips[0].samplers.push_back({Interpolation::kLinear, {0, 2}, {0, 1, 1, 0}, 2});  // two weights a key
  c.clips[0].channels.push_back({6, ChannelPath::kWeights, 3});
  const GlbQuantization q = plan_glb_quantization(c);
  ASSERT_EQ(q.target_scale.at(6).size(), 2u);
  EXPECT_GT(q.target_scale.at(6)[0], 100 * q.target_scale.at(6)[1]) << "each target its own step";
  Character snapped = c;
  snap_to_glb_quantization(snapped, q);
  EXPECT_NEAR(snapped.primitives[2].morph_targets[1][0].x, 1e-3f, 1e-7f) << "a small target keeps its precision";
  const std::vector<uint8_t> bytes = encode_glb(snapped, "test", &q);
  auto r = load_character_bytes(std::string(bytes.begin(), bytes.end()), "quantized.glb");
  ASSERT_TRUE(r.ok()) << r.error().message;
  ASSERT_EQ(r->skeleton.size(), c.skeleton.size() + 1);
  EXPECT_EQ(r->skeleton.node(c.skeleton.size()).name, "prop_dequantized");
  EXPECT_EQ(r->skeleton.node(7).name, "prop_child");
  EXPECT_EQ(r->primitives[2].node, c.skeleton.size()) << "the mesh moved to the holder";
  // the child still sits 1 above prop's (unchanged) transform
  auto g = r->skeleton.global_transforms(r->skeleton.rest_pose());
  EXPECT_NEAR(glm::length(glm::vec3(g[7][3]) - glm::vec3(1, 4, 3)), 0.0f, 1e-6f);
  EXPECT_LT(largest_gap(*r, snapped), 1e-5f);
}

}  // namespace
}  // namespace cagewrap
