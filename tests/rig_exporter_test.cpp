// Tests for core/export/rig_json.h and core/export/rig_exporter.h: the JSON rig poses the driver cage exactly as
// core/rig/rig.h does (its attachment formula, with smooth blending, an override and sculpted
// offsets), carries the keyposes bit for bit and names nodes; the layout reads back as the same
// JSON; run_export writes each format, refuses bad paths before any work and never the document's
// own files.
#include "core/export/rig_exporter.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "core/base/json_reader.h"
#include "core/export/rig_json.h"
#include "core/character/skinning.h"
#include "tests/gltf_builder.h"
#include "tests/rig_fixtures.h"

namespace cagewrap {
namespace {

namespace fs = std::filesystem;

// The demo with a smooth attachment, one override, sculpted offsets and the biceps keypose.
const Document& rich_demo() {
  static const Document doc = [] {
    Document d = test::demo_document();
    AttachmentSettings a;
    a.mode = AttachmentMode::kSmooth;
    a.overrides = {{5, static_cast<uint32_t>(d.character->skeleton.find("hand.L"))}};
    d = with_attachment(d, a);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-0.01f, 0.01f);
    std::vector<glm::vec3> offsets(d.cage->num_vertices());
    for (glm::vec3& o : offsets) o = {u(rng), u(rng), u(rng)};
    d = with_cage_offsets(d, offsets);
    auto att = attach_cage(*d.character, d.cage_positions(), d.attachment);
    EXPECT_TRUE(att.ok());
    return with_keyposes(d, {test::demo_biceps_keypose(*d.character, d.cage_positions(), *att).set});
  }();
  return doc;
}

Json parsed(const RigJson& r) {
  return Json::parse(r.text);
}

glm::vec3 vec3_of(const Json& j) {
  return {j[0].get<float>(), j[1].get<float>(), j[2].get<float>()};
}

TEST(RigJson, PosesTheDriverCageAsTheRigDoes) {
  const Document& doc = rich_demo();
  auto r = rig_json(doc);
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_TRUE(r->attached);
  const Json j = parsed(*r);
  EXPECT_EQ(j["format"], "cagewrap-rig");
  EXPECT_EQ(j["version"], 1);
  EXPECT_EQ(j["attachment"]["mode"], "smooth");
  ASSERT_EQ(j["attachment"]["overrides"].size(), 1u);
  EXPECT_EQ(j["attachment"]["overrides"][0]["node"], "hand.L");
  const Character& ch = *doc.character;
  const Skeleton& sk = ch.skeleton;
  const size_t nv = doc.cage->num_vertices();
  ASSERT_EQ(j["cage"]["positions"].size(), nv);
  ASSERT_EQ(j["cage"]["faces"].size(), doc.cage->polygons.num_faces());
  ASSERT_EQ(j["cage"]["elements"].size(), doc.cage->num_elements());
  ASSERT_EQ(j["attachment"]["vertices"].size(), nv);
  EXPECT_EQ(j["attachment"]["vertices"][5]["nodes"], Json::array({"hand.L"}));
  EXPECT_EQ(j["attachment"]["vertices"][5]["override"], true);
  size_t blended = 0;
  // D_v = (sum_i w_i global(node_i) inverse_bind_i) (positions_v + offsets_v + keyposes_v), with the
  // keyposes' offsets at the pose from core (their interpolation is core/cage/keyposes.h's)
  for (double t : {0.6, 1.4}) {
    const Pose pose = compose_pose(ch, 1, t, false);  // arm_raise: the elbow bends
    PosedCage want;
    auto att = attach_cage(ch, doc.cage_positions(), doc.attachment);
    ASSERT_TRUE(att.ok());
    pose_document_cage(doc, &*att, pose, want);
    const auto globals = sk.global_transforms(pose);
    for (size_t v = 0; v < nv; ++v) {
      const Json& vj = j["attachment"]["vertices"][v];
      glm::mat4 m(0.0f);
      float sum = 0.0f;
      for (size_t i = 0; i < vj["weights"].size(); ++i) {
        const uint32_t joint = vj["joints"][i], node = vj["node_indices"][i];
        EXPECT_EQ(vj["nodes"][i], sk.node(node).name);
        EXPECT_EQ(j["skin"]["joints"][joint]["node_index"], node);
        glm::mat4 ib;
        for (int c = 0; c < 4; ++c)
          for (int row = 0; row < 4; ++row)
            ib[c][row] = j["skin"]["joints"][joint]["inverse_bind"][4 * c + row];
        const float w = vj["weights"][i];
        m += w * (globals[node] * ib);
        sum += w;
      }
      blended += vj["weights"].size() > 1;
      EXPECT_NEAR(sum, 1.0f, 1e-6f) << v;
      const glm::vec3 p =
          vec3_of(j["cage"]["positions"][v]) + vec3_of(j["cage"]["offsets"][v]) + want.keypose_offsets[v];
      const glm::vec3 d(m * glm::vec4(p, 1.0f));
      ASSERT_LT(glm::length(d - want.positions[v]), 1e-5f) << "cage vertex " << v << " at t " << t;
    }
  }
  EXPECT_GT(blended, 0u) << "the smooth attachment blends somewhere";
  // keyposes: names, nodes and every number as the document has them
  ASSERT_EQ(j["keyposes"].size(), 1u);
  const Json& set = j["keyposes"][0];
  const KeyposeSet& mine = doc.keyposes[0];
  EXPECT_EQ(set["name"], mine.name);
  EXPECT_EQ(set["active"], true);
  EXPECT_EQ(set["drivers"][0]["node"], "forearm.L");
  EXPECT_EQ(set["drivers"][0]["kind"], "rotation");
  ASSERT_EQ(set["keys"].size(), 1u);
  EXPECT_EQ(set["keys"][0]["values"].get<std::vector<double>>(), mine.keys[0].values);
  EXPECT_EQ(set["keys"][0]["vertices"].get<std::vector<uint32_t>>(), mine.keys[0].vertices);
  for (size_t i = 0; i < mine.keys[0].offsets.size(); ++i)
    EXPECT_EQ(vec3_of(set["keys"][0]["offsets"][i]), mine.keys[0].offsets[i]) << "bit for bit";
}

TEST(RigJson, NoCageIsRefusedAndNoSkinGivesNullAttachment) {
  Document none = test::demo_document();
  none.cage = nullptr;
  auto r = rig_json(none);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("no cage"), std::string::npos);
  Document skinless = test::demo_document();
  auto ch = std::make_shared<Character>(*skinless.character);
  ch->skins.clear();
  for (Primitive& p : ch->primitives) {
    p.skin = -1;
    p.influence_start.clear();
    p.influence_joint.clear();
    p.influence_weight.clear();
  }
  skinless.character = ch;
  auto s = rig_json(skinless);
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_FALSE(s->attached);
  const Json j = parsed(*s);
  EXPECT_TRUE(j["attachment"].is_null());
  EXPECT_TRUE(j["skin"].is_null());
}

TEST(JsonLayout, ReadsBackAndKeepsLinesShort) {
  Json j = Json::parse(R"({"a": [1, 2.5, -3], "b": {"c": "x", "d": [[0.1, 0.2], [0.3, 0.4]]},
                           "e": [], "f": {}, "g": [{"h": true}]})");
  for (size_t i = 0; i < 60; ++i) j["b"]["d"].push_back(Json::array({i, i + 1}));
  for (size_t i = 0; i < 500; ++i) j["many"].push_back(i);  // fills lines
  const std::string text = json_layout(j);
  EXPECT_EQ(Json::parse(text), j);
  EXPECT_NE(text.find("\"a\": [1, 2.5, -3]"), std::string::npos) << text;
  EXPECT_NE(text.find("\n      [0.1, 0.2],\n"), std::string::npos) << "one pair a line when too long:\n"
                                                                   << text;
  EXPECT_NE(text.find("\"many\": [\n    0, 1, 2, "), std::string::npos) << "long number lists fill lines:\n"
                                                                        << text;
  for (std::istringstream in(text); !in.eof();) {
    std::string line;
    std::getline(in, line);
    EXPECT_LE(line.size(), 100u) << line;
  }
  EXPECT_EQ(json_short_float(0.1f), 0.1);
  EXPECT_EQ(static_cast<float>(json_short_float(1.0f / 3.0f)), 1.0f / 3.0f);
}

TEST(RunExport, ChecksThePathFirst) {
  const std::string dir = test::temp_dir("run_export_paths");
  ExportRequest r;
  r.out = dir + "/x.obj";
  r.format = ExportFormat::kGlb;
  EXPECT_EQ(check_export_path(r), dir + "/x.obj: a glb export is written to a .glb file");
  r.format = ExportFormat::kJson;
  EXPECT_EQ(check_export_path(r), dir + "/x.obj: a json export is written to a .json file");
  r.format = ExportFormat::kObj;
  EXPECT_EQ(check_export_path(r), "");
  r.out = dir + "/frames";  // a folder to make
  EXPECT_EQ(check_export_path(r), "");
  r.out = dir + "/x.glb";
  EXPECT_EQ(check_export_path(r),
            dir + "/x.glb: an obj export is written to F.obj (as F_<clip>_<frame>.obj) or into a folder");
  r.format = ExportFormat::kGlb;
  r.out = dir + "/missing/x.glb";
  EXPECT_EQ(check_export_path(r), dir + "/missing/x.glb: the folder " + dir + "/missing does not exist");
  fs::create_directories(dir + "/d.glb");
  r.out = dir + "/d.glb";
  EXPECT_EQ(check_export_path(r), dir + "/d.glb: is a folder, not a file");
  // run_export says the same without doing anything
  auto e = run_export(test::demo_document(), nullptr, r);
  ASSERT_FALSE(e.ok());
  EXPECT_EQ(e.error().message, dir + "/d.glb: is a folder, not a file");
}

TEST(RunExport, WritesJsonAndRefusesTheDocumentsOwnFiles) {
  const std::string dir = test::temp_dir("run_export_json");
  Document doc = rich_demo();
  ExportRequest r;
  r.format = ExportFormat::kJson;
  r.out = dir + "/rig.json";
  auto rep = run_export(doc, nullptr, r);
  ASSERT_TRUE(rep.ok()) << rep.error().message;
  EXPECT_EQ(rep->what, "rig as JSON");
  EXPECT_EQ(rep->files, std::vector<std::string>{r.out});
  EXPECT_EQ(rep->bytes, fs::file_size(r.out));
  auto back = read_json_file(r.out);
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ((*back)["cage"]["positions"].size(), doc.cage->num_vertices());
  EXPECT_NE(rep->summary.find(std::to_string(doc.cage->num_vertices()) + " cage vertices"), std::string::npos)
      << rep->summary;
  // the character and the project are never exported over
  const std::string character = dir + "/hero.glb", project = dir + "/hero.json";
  std::ofstream(character) << "glb";
  std::ofstream(project) << "{}";
  doc.character_path = character;
  doc.project_path = project;
  r.out = project;
  auto own = run_export(doc, nullptr, r);
  ASSERT_FALSE(own.ok());
  EXPECT_EQ(own.error().message, project + ": is the document's own project file; export elsewhere");
  r.format = ExportFormat::kGlb;
  r.out = character;
  own = run_export(doc, nullptr, r);
  ASSERT_FALSE(own.ok());
  EXPECT_EQ(own.error().message, character + ": is the document's own character file; export elsewhere");
  // glb and obj need the rig
  r.out = dir + "/x.glb";
  own = run_export(doc, nullptr, r);
  ASSERT_FALSE(own.ok());
  EXPECT_NE(own.error().message.find("not bound"), std::string::npos);
}

}  // namespace
}  // namespace cagewrap
