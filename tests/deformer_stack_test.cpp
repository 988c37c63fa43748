// Several deformers on one skin (issue 21, core/rig/deformer_stack.h, docs/deformer-stack.md): the
// combination rules on small inputs, the demo's rig with layers (a copy of its own cage changes
// nothing in order and doubles the motion in a sum; a muted layer is left out; a sculpted layer under
// a head mask moves the head only), the project file (layers round-trip, version 4, errors name the
// layer; without layers the file is what it was), and the rig JSON refusing a stack.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/character/skin_mask.h"
#include "core/document/project_io.h"
#include "core/export/rig_exporter.h"
#include "core/rig/deformer_stack.h"
#include "core/rig/rig.h"
#include "tests/rig_fixtures.h"

namespace cagewrap {
namespace {

namespace fs = std::filesystem;

TEST(DeformerStack, CombinationRules) {
  const std::vector<glm::vec3> rest{{0, 0, 0}, {1, 0, 0}};
  const std::vector<glm::vec3> own{{0, 1, 0}, {1, 1, 0}};    // f_0: up by 1
  const std::vector<glm::vec3> layer{{0, 3, 0}, {1, 3, 0}};  // f_1: up by 3
  const std::vector<float> mask{0.5f, 0.0f};
  const std::vector<std::span<const glm::vec3>> layers{layer};
  const std::vector<std::span<const float>> masks{mask};
  auto run = [&](DeformerStack stack) {
    std::vector<glm::vec3> skin = own;
    EXPECT_TRUE(combine_stack(stack, rest, layers, masks, skin).ok());
    return skin;
  };
  // in order: s = f_0 + m (f_1 - f_0)
  auto in_order = run({StackMode::kInOrder, 2.0});
  EXPECT_FLOAT_EQ(in_order[0].y, 2.0f);
  EXPECT_FLOAT_EQ(in_order[1].y, 1.0f) << "mask 0: the earlier deformer keeps the point";
  // sum: s = p + (f_0 - p) + m (f_1 - p)
  auto sum = run({StackMode::kSum, 2.0});
  EXPECT_FLOAT_EQ(sum[0].y, 2.5f);
  EXPECT_FLOAT_EQ(sum[1].y, 1.0f);
  // blend (m = 2): displacements 1 and 1.5 -> (1 * 1 + 1.5 * 2.25) / (1 + 2.25)
  auto blend = run({StackMode::kBlend, 2.0});
  EXPECT_NEAR(blend[0].y, (1.0 + 1.5 * 2.25) / 3.25, 1e-6);
  EXPECT_FLOAT_EQ(blend[1].y, 1.0f) << "a masked-out layer has no weight (m > 0)";
  // the same displacement twice is not doubled by the blend, and is by the sum
  const std::vector<std::span<const glm::vec3>> same{own};
  const std::vector<std::span<const float>> no_mask{std::span<const float>()};
  std::vector<glm::vec3> skin = own;
  ASSERT_TRUE(combine_stack({StackMode::kBlend, 2.0}, rest, same, no_mask, skin).ok());
  EXPECT_FLOAT_EQ(skin[0].y, 1.0f);
  skin = own;
  ASSERT_TRUE(combine_stack({StackMode::kSum, 2.0}, rest, same, no_mask, skin).ok());
  EXPECT_FLOAT_EQ(skin[0].y, 2.0f);
  // errors name what is wrong
  const std::vector<float> short_mask{1.0f};
  const std::vector<std::span<const float>> bad_masks{short_mask};
  skin = own;
  auto e = combine_stack({}, rest, layers, bad_masks, skin);
  ASSERT_FALSE(e.ok());
  EXPECT_NE(e.error().message.find("layer 1's mask has 1 weights but the skin has 2 points"), std::string::npos) << e.error().message;
  auto neg = combine_stack({StackMode::kBlend, -1.0}, rest, layers, masks, skin);
  EXPECT_FALSE(neg.ok());
}

TEST(DeformerStack, JointRegionMaskFollowsTheSkinWeights) {
  const Document doc = test::demo_document();
  const Character& ch = *doc.character;
  auto head = joint_region_mask(ch, std::vector<std::string>{"head"});
  ASSERT_TRUE(head.ok()) << head.error().message;
  auto neck = joint_region_mask(ch, std::vector<std::string>{"neck"});  // the neck and its child, the head
  ASSERT_TRUE(neck.ok());
  size_t in_head = 0, partial = 0;
  for (size_t p = 0; p < head->size(); ++p) {
    EXPECT_GE((*neck)[p], (*head)[p] - 1e-6f) << "the neck's region holds the head's";
    in_head += (*head)[p] >= 0.999f;
    partial += (*head)[p] > 0.001f && (*head)[p] < 0.999f;
  }
  EXPECT_GT(in_head, 100u);
  EXPECT_GT(partial, 0u) << "feathered where the skinning blends";
  EXPECT_LT(in_head, head->size() / 4);
  auto bad = joint_region_mask(ch, std::vector<std::string>{"hed"});
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("has no node 'hed'"), std::string::npos) << bad.error().message;
  EXPECT_FALSE(primitive_mask(ch, std::vector<size_t>{7}).ok());
  // "-name" leaves a joint and its children out: the neck without the head is the neck's region minus the head's
  auto neck_only = joint_region_mask(ch, std::vector<std::string>{"neck", "-head"});
  ASSERT_TRUE(neck_only.ok()) << neck_only.error().message;
  double gap = 0.0;
  for (size_t p = 0; p < head->size(); ++p) gap = std::max(gap, std::abs(double((*neck_only)[p]) - double((*neck)[p] - (*head)[p])));
  EXPECT_LT(gap, 1e-6);
  auto only_out = joint_region_mask(ch, std::vector<std::string>{"-head"});
  ASSERT_FALSE(only_out.ok());
  EXPECT_NE(only_out.error().message.find("not only ones to leave out"), std::string::npos) << only_out.error().message;
  EXPECT_FALSE(joint_region_mask(ch, std::vector<std::string>{"neck", "-hed"}).ok());
}

class DemoStack : public ::testing::Test {
 protected:
  void SetUp() override {
    doc = test::demo_document();
    const int32_t walk = doc.character->find_clip("walk");
    ASSERT_GE(walk, 0);
    clip = walk;
    auto base = Rig::create(doc);
    ASSERT_TRUE(base.ok()) << base.error().message;
    plain = pose(*base, doc);
    rest.assign(base->skin_rest().begin(), base->skin_rest().end());
  }
  DeformerLayer copy_of_own_cage(const std::string& name) const {
    DeformerLayer l;
    l.name = name;
    l.cage = doc.cage;
    l.params = doc.params;
    l.attachment = doc.attachment;
    return l;
  }
  std::vector<glm::vec3> pose(Rig& rig, const Document& d) const {
    std::vector<glm::vec3> skin(rig.num_skin_points());
    PosedCage cage;
    EXPECT_TRUE(rig.pose_clip(d, clip, 0.4, {}, cage, skin).ok());
    return skin;
  }
  std::vector<glm::vec3> pose_stack(const Document& d) {
    auto rig = Rig::create(d);
    EXPECT_TRUE(rig.ok()) << rig.error().message;
    return rig.ok() ? pose(*rig, d) : std::vector<glm::vec3>{};
  }
  static double largest_difference(std::span<const glm::vec3> a, std::span<const glm::vec3> b) {
    double d = 0.0;
    for (size_t i = 0; i < a.size(); ++i) d = std::max(d, double(glm::length(a[i] - b[i])));
    return d;
  }
  Document doc;
  int32_t clip = -1;
  std::vector<glm::vec3> plain, rest;
};

TEST_F(DemoStack, ACopyOfTheOwnCageChangesNothingInOrderAndDoublesTheMotionInASum) {
  Document d = with_layers(doc, {copy_of_own_cage("copy")});
  const auto in_order = pose_stack(d);
  ASSERT_EQ(in_order.size(), plain.size());
  EXPECT_LT(largest_difference(in_order, plain), 1e-5);
  const auto summed = pose_stack(with_stack(d, {StackMode::kSum, 2.0}));
  double worst = 0.0, moved = 0.0;
  for (size_t i = 0; i < plain.size(); ++i) {
    const glm::vec3 twice = rest[i] + 2.0f * (plain[i] - rest[i]);
    worst = std::max(worst, double(glm::length(summed[i] - twice)));
    moved = std::max(moved, double(glm::length(plain[i] - rest[i])));
  }
  EXPECT_GT(moved, 0.05) << "the walk moves the skin";
  EXPECT_LT(worst, 1e-4) << "the sum counts the skeleton's motion twice";
  // blend: the same displacement twice is the displacement
  EXPECT_LT(largest_difference(pose_stack(with_stack(d, {StackMode::kBlend, 2.0})), plain), 1e-5);
  // muted: left out
  d.layers[0].muted = true;
  d = with_layers(d, d.layers);
  EXPECT_LT(largest_difference(pose_stack(with_stack(d, {StackMode::kSum, 2.0})), plain), 1e-6);
}

TEST_F(DemoStack, ASculptedLayerUnderAHeadMaskMovesTheHeadOnly) {
  DeformerLayer l = copy_of_own_cage("face");
  // the layer's cage sculpted: every vertex pushed 3 cm forward (bind space), the mask the head's
  l.cage_offsets.assign(l.cage->num_vertices(), glm::vec3(0.0f, 0.0f, 0.03f));
  auto mask = joint_region_mask(*doc.character, std::vector<std::string>{"head"});
  ASSERT_TRUE(mask.ok());
  l.mask = std::make_shared<const std::vector<float>>(*mask);
  l.mask_source = "joints head";
  const auto skin = pose_stack(with_layers(doc, {l}));
  double outside = 0.0, inside = 1e9;
  for (size_t i = 0; i < skin.size(); ++i) {
    const double d = glm::length(skin[i] - plain[i]);
    if ((*mask)[i] == 0.0f) outside = std::max(outside, d);
    if ((*mask)[i] >= 0.999f) inside = std::min(inside, d);
  }
  EXPECT_LT(outside, 1e-6) << "outside the mask the project's cage keeps the skin";
  EXPECT_GT(inside, 0.02) << "inside it the sculpted layer moves every head point";
  EXPECT_LT(inside, 0.04);
}

TEST_F(DemoStack, ARigMadeWithoutLayersDoesNotFitAStack) {
  auto base = Rig::create(doc);
  ASSERT_TRUE(base.ok());
  EXPECT_TRUE(base->fits(doc));
  EXPECT_FALSE(base->fits(with_layers(doc, {copy_of_own_cage("copy")})));
  // a layer whose mask does not cover the skin is refused by name
  DeformerLayer l = copy_of_own_cage("short");
  l.mask = std::make_shared<const std::vector<float>>(10, 1.0f);
  auto bad = Rig::create(with_layers(doc, {l}));
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("deformer 'short': its mask has 10 weights"), std::string::npos) << bad.error().message;
}

class StackProject : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = fs::temp_directory_path() / "cagewrap_deformer_stack_test" / ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string glb = std::string(CAGEWRAP_SOURCE_DIR) + "/assets/demo_character.glb";
    auto loaded = document_from_files(glb, std::string(CAGEWRAP_SOURCE_DIR) + "/assets/demo_cage.obj");
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    doc = *loaded;
  }
  fs::path dir;
  Document doc;
};

TEST_F(StackProject, LayersRoundTripAndOldFilesStayAsTheyWere) {
  const std::string plain = (dir / "plain.cagewrap").string(), stacked = (dir / "stacked.cagewrap").string();
  ASSERT_TRUE(save_project(plain, doc).ok());
  nlohmann::json p = nlohmann::json::parse(std::ifstream(plain));
  EXPECT_EQ(p["version"], 2) << "no layers: the file an older build reads";
  EXPECT_FALSE(p.contains("deformers"));
  EXPECT_FALSE(p.contains("deformer_stack"));

  DeformerLayer face;
  face.name = "face";
  face.cage = doc.cage;
  face.params.local = 8.0;
  face.cage_offsets.assign(doc.cage->num_vertices(), glm::vec3(0.0f, 0.01f, 0.0f));
  auto mask = joint_region_mask(*doc.character, std::vector<std::string>{"head"});
  ASSERT_TRUE(mask.ok());
  face.mask = std::make_shared<const std::vector<float>>(*mask);
  face.mask_source = "joints head";
  DeformerLayer coat = face;
  coat.name = "coat";
  coat.mask = nullptr;
  coat.mask_source.clear();
  coat.muted = true;
  coat.cage_offsets.clear();
  const Document d = with_stack(with_layers(doc, {face, coat}), {StackMode::kBlend, 3.0});
  ASSERT_TRUE(save_project(stacked, d).ok());
  nlohmann::json s = nlohmann::json::parse(std::ifstream(stacked));
  EXPECT_EQ(s["version"], 4);
  ASSERT_EQ(s["deformers"].size(), 2u);
  EXPECT_EQ(s["deformer_stack"]["mode"], "blend");
  auto back = load_project(stacked);
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_TRUE(same_content(back->document, d)) << "the layers, masks (float32) and stack round-trip";
  ASSERT_EQ(back->document.layers.size(), 2u);
  EXPECT_EQ(back->document.layers[0].params.local, 8.0);
  EXPECT_TRUE(back->document.layers[1].muted);

  // a damaged layer is named
  s["deformers"][1]["cage"]["faces"][3] = nlohmann::json::array({0, 1, 99999});
  std::ofstream(stacked) << s.dump(1);
  auto bad = load_project(stacked);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find(stacked + ": deformers[1]: cage.faces"), std::string::npos) << bad.error().message;
  s = nlohmann::json::parse(std::ifstream(plain));
  s["version"] = 4;
  s["deformers"] = nlohmann::json::array({nlohmann::json::object()});
  std::ofstream(stacked) << s.dump(1);
  bad = load_project(stacked);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("deformers[0]"), std::string::npos) << bad.error().message;
}

TEST_F(StackProject, TheRigJsonRefusesAStack) {
  DeformerLayer l;
  l.name = "face";
  l.cage = doc.cage;
  const Document d = with_layers(doc, {l});
  ExportRequest request;
  request.format = ExportFormat::kJson;
  request.out = (dir / "rig.json").string();
  auto r = run_export(d, nullptr, request, {});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("this project has 1 more deformer(s)"), std::string::npos) << r.error().message;
  EXPECT_FALSE(fs::exists(dir / "rig.json"));
}

}  // namespace
}  // namespace cagewrap
