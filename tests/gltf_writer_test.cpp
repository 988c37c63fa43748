#include <cmath>

#include <gtest/gtest.h>

#include "core/io/gltf_loader.h"
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

}  // namespace
}  // namespace cagewrap
