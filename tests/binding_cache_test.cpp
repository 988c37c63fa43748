// Tests that a saved project reproduces its deformation exactly, and for its cached binding
// (core/document/binding_cache.h). On the demo character (written to a .glb) with its cage, a keypose (the
// biceps bulge of rig_test.cpp), set edits, the smooth attachment and sculpted cage offsets: the
// skin and the posed cage after save + load equal those before, bit for bit, at clip frames, with a
// posed joint and with the keypose acting; a cached open deforms bit for bit like a fresh bind and
// skips the bind (timings recorded as properties); a cache made stale by editing the project file
// (parameters, cage, set edits, attachment), by a changed character, or by replacing the .cwb file
// is detected, names what changed, and is not used.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <optional>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "core/character/skin_mask.h"
#include "core/document/binding_cache.h"
#include "core/io/binding_io.h"
#include "core/character/demo_character.h"
#include "core/io/gltf_writer.h"
#include "core/document/project_io.h"
#include "core/rig/rig.h"
#include "tests/document_fixtures.h"
#include "tests/driver_fixtures.h"
#include "tests/expect_error.h"
#include "tests/rig_fixtures.h"

namespace cagewrap {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;
using Clock = std::chrono::steady_clock;
using test::read_text;
using test::write_text;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

struct PoseCase {
  const char* name;
  int32_t clip;   // -1: rest
  double time;
  double elbow;   // forearm.L about its local X, degrees, on top of the clip
};
// clip frames, a posed joint with the keypose fully acting (120 degrees), half acting on top of a walk
constexpr PoseCase kPoses[] = {{"walk 0", 0, 0.0, 0},      {"walk 0.37", 0, 0.37, 0}, {"walk 0.5", 0, 0.5, 0},
                               {"arm_raise 1.3", 1, 1.3, 0}, {"elbow 120", -1, 0.0, 120}, {"walk 0.5 + elbow 60", 0, 0.5, 60}};

Pose make_pose(const Character& ch, const PoseCase& c) {
  std::vector<glm::quat> overrides(ch.skeleton.size(), glm::quat(1, 0, 0, 0));
  overrides[ch.skeleton.find("forearm.L")] = rotation_xyz_degrees(c.elbow, 0, 0);
  return compose_pose(ch, c.clip, c.time, false, overrides);
}

bool same_bits(std::span<const glm::vec3> a, std::span<const glm::vec3> b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(glm::vec3)) == 0;
}

// The demo project, made once: the character written to a .glb, the demo cage, and everything a
// project holds set to something other than its default.
struct DemoProject {
  fs::path dir;
  Document doc;
  std::optional<Rig> rig;
  double bind_seconds = 0;
  std::string path(const std::string& name) const { return (dir / name).string(); }
};

DemoProject& demo_project() {
  static DemoProject d = [] {
    DemoProject d;
    d.dir = fs::temp_directory_path() / ("cagewrap-binding-cache-" + std::to_string(::getpid()));
    fs::remove_all(d.dir);
    fs::create_directories(d.dir);
    EXPECT_TRUE(write_glb(d.path("demo.glb"), make_demo_character()).ok());
    auto doc = document_from_files(d.path("demo.glb"), std::string(CAGEWRAP_SOURCE_DIR) + "/assets/demo_cage.obj");
    EXPECT_TRUE(doc.ok()) << doc.error().message;
    Document x = *doc;
    AttachmentSettings smooth;
    smooth.mode = AttachmentMode::kSmooth;
    smooth.smooth_width = 0.6;
    x = with_attachment(x, smooth);
    x = with_set_edits(x, {SetEdit{100, {0, 1}, {}}, SetEdit{2000, {}, {5}}});
    std::vector<glm::vec3> offsets(x.cage->num_vertices(), glm::vec3(0.f));
    for (size_t v = 0; v < offsets.size(); v += 7) offsets[v] = glm::vec3(0.003f * std::sin(float(v)), 0.001f, -0.002f);
    x = with_cage_offsets(x, offsets);
    auto attachment = attach_cage(*x.character, x.cage_positions(), x.attachment);
    EXPECT_TRUE(attachment.ok());
    x = with_keyposes(x, {test::demo_biceps_keypose(*x.character, x.cage_positions(), *attachment).set});
    x = with_cache_binding(x, true);
    d.doc = x;
    const auto t0 = Clock::now();
    auto rig = Rig::create(d.doc);
    d.bind_seconds = seconds_since(t0);
    EXPECT_TRUE(rig.ok()) << rig.error().message;
    d.rig.emplace(std::move(rig).value());
    SaveOptions options;
    options.binding = &d.rig->binding();
    EXPECT_TRUE(save_project(d.path("demo.cagewrap"), d.doc, options).ok());
    return d;
  }();
  return d;
}

class BindingCacheTest : public ::testing::Test {
 protected:
  static void TearDownTestSuite() {
    std::error_code ec;
    fs::remove_all(demo_project().dir, ec);
  }
  // The saved project's JSON, edited, written as `name`; returns its path.
  std::string edited(const std::string& name, const std::function<void(Json&)>& edit) {
    Json j = Json::parse(read_text(demo_project().path("demo.cagewrap")));
    edit(j);
    const std::string p = demo_project().path(name);
    write_text(p, j.dump(1));
    return p;
  }
};

TEST_F(BindingCacheTest, SaveLoadReproducesTheDeformationBitForBit) {
  DemoProject& d = demo_project();
  auto loaded = load_project(d.path("demo.cagewrap"));
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  const Document& back = loaded->document;
  ASSERT_TRUE(same_content(d.doc, back));
  auto rig = Rig::create(back);  // a fresh bind of what was loaded
  ASSERT_TRUE(rig.ok()) << rig.error().message;
  const size_t n = d.rig->num_skin_points();
  bool keypose_acted = false;
  for (const PoseCase& c : kPoses) {
    SCOPED_TRACE(c.name);
    PosedCage cage_before, cage_after;
    std::vector<glm::vec3> before(n), after(n);
    ASSERT_TRUE(d.rig->pose(d.doc, make_pose(*d.doc.character, c), cage_before, before).ok());
    ASSERT_TRUE(rig->pose(back, make_pose(*back.character, c), cage_after, after).ok());
    EXPECT_TRUE(same_bits(cage_before.positions, cage_after.positions));
    EXPECT_TRUE(same_bits(before, after));
    double bulge = 0;
    for (const glm::vec3& o : cage_after.keypose_offsets) bulge = std::max(bulge, double(glm::length(o)));
    if (c.elbow == 120) {
      EXPECT_NEAR(bulge, 0.02, 1e-6) << "the keypose acts fully at its key";
    }
    keypose_acted = keypose_acted || bulge > 0;
    // the pose moved the skin (the comparison is not between two rest poses)
    double moved = 0;
    for (size_t i = 0; i < n; ++i) moved = std::max(moved, double(glm::length(after[i] - rig->skin_rest()[i])));
    EXPECT_GT(moved, 0.01);
  }
  EXPECT_TRUE(keypose_acted);
}

TEST_F(BindingCacheTest, CachedOpenDeformsLikeAFreshBindWithoutBinding) {
  DemoProject& d = demo_project();
  const auto t0 = Clock::now();
  auto loaded = load_project(d.path("demo.cagewrap"));
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  const double load_seconds = seconds_since(t0);
  const Document& back = loaded->document;
  EXPECT_TRUE(back.cache_binding);
  EXPECT_EQ(back.binding_cache.file, d.path("demo.cagewrap.cwb"));
  EXPECT_EQ(Json::parse(read_text(d.path("demo.cagewrap")))["binding_cache"]["file"], "demo.cagewrap.cwb");
  const auto t1 = Clock::now();
  auto cached = load_binding_cache(back);
  ASSERT_TRUE(cached.ok()) << cached.error().message;
  auto cached_rig = Rig::create(back, std::move(cached).value());
  ASSERT_TRUE(cached_rig.ok()) << cached_rig.error().message;
  const double cached_seconds = seconds_since(t1);
  const auto t2 = Clock::now();
  auto fresh = Rig::create(back);
  ASSERT_TRUE(fresh.ok());
  const double fresh_seconds = seconds_since(t2);
  EXPECT_EQ(cached_rig->binding().ids, fresh->binding().ids);
  EXPECT_EQ(cached_rig->binding().weights, fresh->binding().weights);
  const size_t n = fresh->num_skin_points();
  for (const PoseCase& c : kPoses) {
    SCOPED_TRACE(c.name);
    PosedCage a, b;
    std::vector<glm::vec3> from_cache(n), from_bind(n);
    ASSERT_TRUE(cached_rig->pose(back, make_pose(*back.character, c), a, from_cache).ok());
    ASSERT_TRUE(fresh->pose(back, make_pose(*back.character, c), b, from_bind).ok());
    EXPECT_TRUE(same_bits(from_cache, from_bind));
  }
  RecordProperty("project_load_seconds", std::to_string(load_seconds));
  RecordProperty("cached_binding_seconds", std::to_string(cached_seconds));
  RecordProperty("fresh_bind_seconds", std::to_string(fresh_seconds));
  std::printf("demo project: load %.3f s; rig from the cache %.3f s; fresh bind %.3f s\n", load_seconds, cached_seconds,
              fresh_seconds);
  EXPECT_LT(cached_seconds, fresh_seconds) << "the cache is there to skip the bind";
}

TEST_F(BindingCacheTest, StaleCacheIsDetectedNamesTheChangeAndIsNotUsed) {
  struct Case {
    const char* name;
    std::function<void(Json&)> edit;
    const char* says;
  };
  const Case cases[] = {
      {"epsilon", [](Json& j) { j["binding"]["epsilon"] = 0.2; }, "out of date: the binding parameters changed"},
      {"separate", [](Json& j) { j["binding"]["separate"] = false; }, "the binding parameters and the attachment settings changed"},
      {"cage", [](Json& j) { j["cage"]["positions"][3][1] = j["cage"]["positions"][3][1].get<double>() + 0.001; }, "the cage changed"},
      {"set edits", [](Json& j) { j["set_edits"][0]["exclude"] = Json::array({0}); }, "the set edits changed"},
      {"attachment", [](Json& j) { j["attachment"]["smooth_width"] = 0.7; }, "the attachment settings changed"},
      {"cage and parameters", [](Json& j) {
         j["binding"]["local"] = 3;
         Json& face = j["cage"]["faces"][0];  // the same polygon starting at its next corner
         Json rotated = Json::array();
         for (size_t k = 1; k <= face.size(); ++k) rotated.push_back(face[k % face.size()]);
         face = rotated;
       }, "the cage and the binding parameters changed"},
      {"program", [](Json& j) { j["binding_cache"]["inputs"]["program"] = "cagewrap 0.0.1"; }, "the program (cagewrap 0.0.1 made it)"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string p = edited(std::string("stale-") + c.name + ".cagewrap", c.edit);
    auto loaded = load_project(p);
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    auto cached = load_binding_cache(loaded->document);
    EXPECT_TRUE(Fails(cached, ErrorCode::kInvalidArgument, {demo_project().path("demo.cagewrap.cwb"), c.says}));
  }
  // a cache that is still right loads from any copy of the project beside it
  auto same = load_project(edited("same.cagewrap", [](Json&) {}));
  ASSERT_TRUE(same.ok());
  EXPECT_TRUE(load_binding_cache(same->document).ok());
}

TEST_F(BindingCacheTest, ReplacedOrMissingCacheFileIsNotUsed) {
  DemoProject& d = demo_project();
  fs::create_directories(d.dir / "copy");
  fs::copy_file(d.path("demo.cagewrap"), d.path("copy/demo.cagewrap"));
  fs::copy_file(d.path("demo.glb"), d.path("copy/demo.glb"));
  // a cache file from another bind (other parameters) put in its place
  Document other = with_params(d.doc, [] { BindParams p; p.epsilon = 0.3; return p; }());
  auto other_rig = Rig::create(other);
  ASSERT_TRUE(other_rig.ok());
  ASSERT_TRUE(save_binding(d.path("copy/demo.cagewrap.cwb"), other_rig->binding()).ok());
  auto loaded = load_project(d.path("copy/demo.cagewrap"));
  ASSERT_TRUE(loaded.ok());
  EXPECT_TRUE(Fails(load_binding_cache(loaded->document), ErrorCode::kInvalidArgument,
                    {d.path("copy/demo.cagewrap.cwb"), "was changed or replaced since the project was saved"}));
  fs::remove(d.path("copy/demo.cagewrap.cwb"));
  EXPECT_TRUE(Fails(load_binding_cache(loaded->document), ErrorCode::kFileNotFound,
                    {d.path("copy/demo.cagewrap.cwb"), "gone"}));
  // a malformed record: the project still opens, with a warning, and nothing cached
  auto bad = load_project(edited("bad-record.cagewrap", [](Json& j) { j["binding_cache"]["file"] = 3; }));
  ASSERT_TRUE(bad.ok()) << bad.error().message;
  EXPECT_TRUE(bad->document.cache_binding);
  EXPECT_TRUE(bad->document.binding_cache.file.empty());
  ASSERT_EQ(bad->warnings.size(), 1u);
  EXPECT_NE(bad->warnings[0].find("binding_cache.file"), std::string::npos) << bad->warnings[0];
  EXPECT_NE(bad->warnings[0].find("not used"), std::string::npos) << bad->warnings[0];
}

class BindingCacheTinyTest : public test::TempDirTest {};

TEST_F(BindingCacheTinyTest, ChangedCharacterFileMakesTheCacheStale) {
  test::write_tiny_character(path("hero.gltf"));
  test::write_box_cage(path("cage.obj"));
  auto doc = document_from_files(path("hero.gltf"), path("cage.obj"));
  ASSERT_TRUE(doc.ok());
  Document d = with_cache_binding(*doc, true);
  auto rig = Rig::create(d);
  ASSERT_TRUE(rig.ok()) << rig.error().message;
  SaveOptions options;
  options.binding = &rig->binding();
  ASSERT_TRUE(save_project(path("p.cagewrap"), d, options).ok());
  ASSERT_TRUE(fs::exists(path("p.cagewrap.cwb")));
  test::write_tiny_character(path("hero.gltf"), 0.25f);  // re-exported: same structure, moved
  auto loaded = load_project(path("p.cagewrap"));
  ASSERT_TRUE(loaded.ok());
  EXPECT_TRUE(Fails(load_binding_cache(loaded->document), ErrorCode::kInvalidArgument, {"the character file changed"}));
}

TEST_F(BindingCacheTinyTest, SavingAgainKeepsAValidRecordAndDropsAStaleOne) {
  test::write_tiny_character(path("hero.gltf"));
  test::write_box_cage(path("cage.obj"));
  auto doc = document_from_files(path("hero.gltf"), path("cage.obj"));
  ASSERT_TRUE(doc.ok());
  Document d = with_cache_binding(*doc, true);
  // caching on, no binding given: the project says so, and records nothing
  ASSERT_TRUE(save_project(path("p.cagewrap"), d).ok());
  EXPECT_EQ(Json::parse(read_text(path("p.cagewrap")))["binding_cache"], Json::object());
  auto rig = Rig::create(d);
  ASSERT_TRUE(rig.ok());
  SaveOptions options;
  options.binding = &rig->binding();
  ASSERT_TRUE(save_project(path("p.cagewrap"), d, options).ok());
  auto loaded = load_project(path("p.cagewrap"));
  ASSERT_TRUE(loaded.ok());
  // saved again without a binding: nothing changed, so the record stays
  ASSERT_TRUE(save_project(path("p.cagewrap"), loaded->document).ok());
  auto again = load_project(path("p.cagewrap"));
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(again->document.binding_cache, loaded->document.binding_cache);
  EXPECT_TRUE(load_binding_cache(again->document).ok());
  // parameters edited, saved without a binding: the stale record is dropped
  BindParams p = loaded->document.params;
  p.local = 2;
  ASSERT_TRUE(save_project(path("p.cagewrap"), with_params(loaded->document, p)).ok());
  EXPECT_EQ(Json::parse(read_text(path("p.cagewrap")))["binding_cache"], Json::object());
  // a binding that is not this document's is refused, naming the cache file; nothing is written
  const std::string before = read_text(path("p.cagewrap"));
  options.binding = &rig->binding();
  EXPECT_TRUE(Fails(save_project(path("p.cagewrap"), with_params(loaded->document, p), options), ErrorCode::kInvalidArgument,
                    {path("p.cagewrap.cwb"), "other binding parameters"}));
  EXPECT_EQ(read_text(path("p.cagewrap")), before);
  // caching off: no record at all
  ASSERT_TRUE(save_project(path("q.cagewrap"), with_cache_binding(d, false)).ok());
  EXPECT_FALSE(Json::parse(read_text(path("q.cagewrap"))).contains("binding_cache"));
}

TEST(BindingInputs, EachInputIsNamedWhenItChanges) {
  Document d;
  d.character_hash = "fnv1a64:0000000000000001";
  d.cage = std::make_shared<const Cage>(fixtures::box_cage(1.0, 1));
  const BindingInputs a = binding_inputs(d);
  EXPECT_EQ(changed_inputs(a, a), "");
  // the program and its weight rule (a binding cached before the tie band is stale)
  EXPECT_EQ(a.program.rfind(std::string("cagewrap ") + CAGEWRAP_VERSION + " (weights: tie band", 0), 0u) << a.program;
  Document e = d;
  e.params.separate = false;  // without separation the attachment does not reach the bind
  const BindingInputs b = binding_inputs(e);
  AttachmentSettings smooth;
  smooth.mode = AttachmentMode::kSmooth;
  EXPECT_EQ(changed_inputs(b, binding_inputs(with_attachment(e, smooth))), "");
  EXPECT_EQ(changed_inputs(a, binding_inputs(with_attachment(d, smooth))), "the attachment settings");
  EXPECT_EQ(changed_inputs(a, binding_inputs(with_set_edits(d, {SetEdit{0, {1}, {}}}))), "the set edits");
  Document f = d;
  f.character_hash = "fnv1a64:0000000000000002";
  f.params.max_elements = 4;
  EXPECT_EQ(changed_inputs(a, binding_inputs(f)), "the character file and the binding parameters");
  f.set_edits = {SetEdit{0, {1}, {}}};
  EXPECT_EQ(changed_inputs(a, binding_inputs(f)), "the character file, the binding parameters and the set edits");
}

// The demo character written to `dir` (emptied first) with the demo cage, caching its bindings.
Document caching_demo_in(const fs::path& dir) {
  fs::remove_all(dir);
  fs::create_directories(dir);
  EXPECT_TRUE(write_glb((dir / "demo.glb").string(), make_demo_character()).ok());
  auto loaded = document_from_files((dir / "demo.glb").string(), std::string(CAGEWRAP_SOURCE_DIR) + "/assets/demo_cage.obj");
  if (!loaded) ADD_FAILURE() << loaded.error().message;
  return loaded ? with_cache_binding(*loaded, true) : Document{};
}

// A deformer stack caches each deformer's binding (issue 21): the demo with two layers (a sculpted copy of its
// cage under the head's mask, and a muted copy) saved with the rig's bindings writes P.cwb and P.1.cwb (the
// muted layer moves nothing: no file); opened again, both are used and the rig made from them poses the skin
// bit for bit like the one that bound; a change of the layer's parameters makes its cache alone stale (named),
// and saving again keeps deformer 0's record and drops the layer's.
TEST(BindingCacheStack, EachLayerIsCachedAndAStaleLayerAloneBindsAgain) {
  const fs::path dir = fs::temp_directory_path() / ("cagewrap-binding-cache-stack-" + std::to_string(::getpid()));
  Document doc = caching_demo_in(dir);
  ASSERT_TRUE(doc.cage);
  DeformerLayer face;
  face.name = "face";
  face.cage = doc.cage;
  face.params = doc.params;
  face.attachment = doc.attachment;
  face.cage_offsets.assign(face.cage->num_vertices(), glm::vec3(0.0f, 0.0f, 0.02f));
  const std::string head[] = {"head"};
  auto mask = joint_region_mask(*doc.character, head);
  ASSERT_TRUE(mask.ok());
  face.mask = std::make_shared<const std::vector<float>>(*mask);
  DeformerLayer muted = face;
  muted.name = "muted";
  muted.muted = true;
  doc = with_layers(doc, {face, muted});
  auto rig = Rig::create(doc);
  ASSERT_TRUE(rig.ok()) << rig.error().message;
  ASSERT_NE(rig->layer_binding(0), nullptr);
  EXPECT_EQ(rig->layer_binding(1), nullptr) << "a muted layer is not bound";
  const std::string P = (dir / "demo.cagewrap").string();
  SaveOptions options;
  options.binding = &rig->binding();
  options.layer_bindings = {rig->layer_binding(0), rig->layer_binding(1)};
  ASSERT_TRUE(save_project(P, doc, options).ok());
  EXPECT_TRUE(fs::exists(P + ".cwb"));
  EXPECT_TRUE(fs::exists(P + ".1.cwb"));
  EXPECT_FALSE(fs::exists(P + ".2.cwb"));
  const Json j = Json::parse(read_text(P));
  EXPECT_EQ(j["deformers"][0]["binding_cache"]["file"], "demo.cagewrap.1.cwb");
  EXPECT_EQ(j["deformers"][1]["binding_cache"], Json::object()) << "caching on, nothing cached for the muted layer";

  auto opened = load_project(P);
  ASSERT_TRUE(opened.ok()) << opened.error().message;
  Document again = opened->document;
  StackBindingCache cached = load_stack_binding_caches(again);
  EXPECT_EQ(cached.used, 2u);
  EXPECT_TRUE(cached.not_used.empty()) << cached.not_used.front();
  ASSERT_EQ(cached.bindings.size(), 3u);
  EXPECT_TRUE(cached.bindings[0] && cached.bindings[1]);
  EXPECT_FALSE(cached.bindings[2]);
  auto from_cache = Rig::create(again, std::move(cached.bindings));
  ASSERT_TRUE(from_cache.ok()) << from_cache.error().message;
  std::vector<glm::vec3> a(rig->num_skin_points()), b(from_cache->num_skin_points());
  PosedCage ca, cb;
  ASSERT_TRUE(rig->pose_clip(doc, 0, 0.4, {}, ca, a).ok());
  ASSERT_TRUE(from_cache->pose_clip(again, 0, 0.4, {}, cb, b).ok());
  EXPECT_TRUE(same_bits(a, b)) << "the stack from the caches poses like the one that bound";

  // the layer's parameters changed: its cache alone is stale, and says so
  std::vector<DeformerLayer> layers = again.layers;
  layers[0].params.epsilon *= 2.0;
  Document changed = with_layers(again, layers);
  StackBindingCache stale = load_stack_binding_caches(changed);
  EXPECT_EQ(stale.used, 1u);
  ASSERT_EQ(stale.not_used.size(), 1u);
  EXPECT_NE(stale.not_used[0].find("demo.cagewrap.1.cwb is out of date: the binding parameters changed"), std::string::npos)
      << stale.not_used[0];
  ASSERT_TRUE(save_project(P, changed).ok());
  auto reopened = load_project(P);
  ASSERT_TRUE(reopened.ok());
  EXPECT_FALSE(reopened->document.binding_cache.file.empty()) << "deformer 0's record is still valid: kept";
  EXPECT_TRUE(reopened->document.layers[0].binding_cache.file.empty()) << "the stale layer's record is dropped";
  fs::remove_all(dir);
}

// The parametric drivers' bindings are cached too (issue 21): the demo with two chest drivers (the second with
// its own epsilon and a set edit, both sculpted) saved with the rig's bindings writes P.D1.cwb and P.D2.cwb
// (sample bindings: .cwb version 3, keeping the sample count and the degenerate samples); opened again, both
// are used and the rig made from them poses bit for bit like the one that bound; the second driver's new
// parameters make its cache alone stale (named); a record whose binding is for another driver is refused by
// driver_binding_fits.
TEST(BindingCacheStack, EachDriverIsCachedAndAStaleDriverAloneBindsAgain) {
  const fs::path dir = fs::temp_directory_path() / ("cagewrap-binding-cache-drivers-" + std::to_string(::getpid()));
  Document doc = caching_demo_in(dir);
  ASSERT_TRUE(doc.cage);
  doc = with_patch_driver(doc, test::chest_driver(0.06));
  DriverDeformer second{test::chest_driver(-0.04), {}};
  second.place.name = "second";
  BindParams own = doc.params;
  own.epsilon *= 0.5;
  second.place.params = own;
  second.place.set_edits = {SetEdit{32831, {}, {0}, true}};
  doc = with_more_drivers(doc, {second});
  auto rig = Rig::create(doc);
  ASSERT_TRUE(rig.ok()) << rig.error().message;
  ASSERT_NE(rig->driver_binding(0), nullptr);
  ASSERT_NE(rig->driver_binding(1), nullptr);
  EXPECT_GT(rig->driver_binding(0)->num_samples, 0u);
  const std::string P = (dir / "demo.cagewrap").string();
  SaveOptions options;
  options.binding = &rig->binding();
  options.driver_bindings = {rig->driver_binding(0), rig->driver_binding(1)};
  ASSERT_TRUE(save_project(P, doc, options).ok());
  ASSERT_TRUE(fs::exists(P + ".D1.cwb"));
  ASSERT_TRUE(fs::exists(P + ".D2.cwb"));
  const Json j = Json::parse(read_text(P));
  EXPECT_EQ(j["patch_driver"]["binding_cache"]["file"], "demo.cagewrap.D1.cwb");
  EXPECT_EQ(j["more_drivers"][0]["binding_cache"]["file"], "demo.cagewrap.D2.cwb");
  // the file keeps what a sample binding is
  auto file = load_binding(P + ".D2.cwb");
  ASSERT_TRUE(file.ok()) << file.error().message;
  const Binding& bound = *rig->driver_binding(1);
  EXPECT_EQ(file->num_samples, bound.num_samples);
  EXPECT_EQ(file->invalid_elements, bound.invalid_elements);
  EXPECT_EQ(file->ids, bound.ids);
  EXPECT_EQ(file->weights, bound.weights);
  EXPECT_TRUE(file->params == bound.params);

  auto opened = load_project(P);
  ASSERT_TRUE(opened.ok()) << opened.error().message;
  Document again = opened->document;
  StackBindingCache cached = load_stack_binding_caches(again);
  EXPECT_EQ(cached.used, 1u);
  EXPECT_EQ(cached.drivers_used, 2u);
  EXPECT_TRUE(cached.not_used.empty()) << cached.not_used.front();
  auto from_cache = Rig::create(again, std::move(cached.bindings), {}, std::move(cached.drivers));
  ASSERT_TRUE(from_cache.ok()) << from_cache.error().message;
  std::vector<glm::vec3> a(rig->num_skin_points()), b(from_cache->num_skin_points());
  PosedCage ca, cb;
  ASSERT_TRUE(rig->pose_clip(doc, 0, 0.4, {}, ca, a).ok());
  ASSERT_TRUE(from_cache->pose_clip(again, 0, 0.4, {}, cb, b).ok());
  EXPECT_TRUE(same_bits(a, b)) << "the drivers from the caches pose like the ones that bound";
  std::vector<glm::vec3> plain(a.size());
  {
    const Document no_drivers = without_first_driver(without_first_driver(doc));
    auto cage_only = Rig::create(no_drivers);
    ASSERT_TRUE(cage_only.ok());
    ASSERT_TRUE(cage_only->pose_clip(no_drivers, 0, 0.4, {}, ca, plain).ok());
    double moved = 0;
    for (size_t i = 0; i < a.size(); ++i) moved = std::max(moved, double(glm::length(a[i] - plain[i])));
    EXPECT_GT(moved, 0.01) << "the drivers move the skin (the comparison above is not of two plain skins)";
  }

  // the second driver's parameters changed: its cache alone is stale, and says so
  DriverPlacement place = *driver_at(again, 1).place;
  place.params->epsilon *= 2.0;
  Document changed = with_driver_place(again, 1, place);
  StackBindingCache stale = load_stack_binding_caches(changed);
  EXPECT_EQ(stale.drivers_used, 1u);
  ASSERT_EQ(stale.not_used.size(), 1u);
  EXPECT_NE(stale.not_used[0].find("demo.cagewrap.D2.cwb is out of date: the binding parameters changed"), std::string::npos)
      << stale.not_used[0];
  // a binding of another driver (the cage's) does not fit a driver
  EXPECT_FALSE(driver_binding_fits(rig->binding(), again, 0).ok());
  EXPECT_FALSE(driver_binding_fits(*rig->driver_binding(1), again, 0).ok()) << "other parameters";
  ASSERT_TRUE(save_project(P, changed).ok());
  auto reopened = load_project(P);
  ASSERT_TRUE(reopened.ok());
  EXPECT_FALSE(driver_at(reopened->document, 0).place->binding_cache.file.empty()) << "the first driver's record is valid: kept";
  EXPECT_TRUE(driver_at(reopened->document, 1).place->binding_cache.file.empty()) << "the stale driver's record is dropped";
  fs::remove_all(dir);
}

}  // namespace
}  // namespace cagewrap
