// Tests for core/document/project_io.h and core/base/atomic_write.h: save -> load gives the same document (cage
// positions bit for bit), the character path is stored relative to the project and survives moving
// both, every load error names the file and the JSON path, the hash mismatch is a warning, unknown
// fields are kept, and saving is atomic (the old file is replaced only by a complete new one).
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>

#include <bit>
#include <cmath>
#include <filesystem>
#include <limits>
#include <random>

#include <nlohmann/json.hpp>

#include "core/base/atomic_write.h"
#include "core/base/file_hash.h"
#include "core/document/project_io.h"
#include "tests/document_fixtures.h"
#include "tests/patch_fixtures.h"
#include "tests/expect_error.h"

namespace cagewrap {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;
using test::read_text;
using test::write_text;

::testing::AssertionResult Contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "message \"" << text << "\" does not contain \"" << part << "\"";
}
#define EXPECT_CONTAINS(text, part) EXPECT_TRUE(Contains((text), (part)))

class ProjectIoTest : public test::TempDirTest {
 protected:
  // hero.gltf + cage.obj in the test folder, non-default parameters and two set edits.
  Document make_doc() {
    test::write_tiny_character(path("hero.gltf"));
    test::write_box_cage(path("cage.obj"));
    auto doc = document_from_files(path("hero.gltf"), path("cage.obj"));
    EXPECT_TRUE(doc.ok()) << (doc.ok() ? "" : doc.error().message);
    BindParams p;
    p.variant = Variant::kClamped;
    p.local = 3.5;
    p.epsilon = 0.0123456789012345;
    p.max_elements = 5;
    p.scale = 0.75;
    p.max_distance = 12.5;
    p.close_distance = 0.3;
    Document d = with_params(*doc, p);
    return with_set_edits(d, {SetEdit{2, {0, 7}, {}}, SetEdit{3, {}, {47}}});
  }
  ProjectLoad load_ok(const std::string& project, const std::string& override_path = {}) {
    auto r = load_project(project, override_path);
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    return r.ok() ? std::move(r).value() : ProjectLoad{};
  }
  // Saves a project, lets `edit` change its JSON, and returns the load error.
  template <class F>
  Error error_after(F edit, std::string* missing = nullptr) {
    std::string project = path("p.cagewrap");
    EXPECT_TRUE(save_project(project, make_doc()).ok());
    Json j = Json::parse(read_text(project));
    edit(j);
    write_text(project, j.dump(2));
    auto r = load_project(project, {}, missing);
    EXPECT_FALSE(r.ok());
    return r.ok() ? Error{ErrorCode::kCancelled, "loaded"} : r.error();
  }
};

TEST_F(ProjectIoTest, SaveThenLoadGivesTheSameDocument) {
  Document doc = make_doc();
  std::string project = path("hero.cagewrap");
  ASSERT_TRUE(save_project(project, doc).ok());
  EXPECT_FALSE(fs::exists(project + ".tmp"));
  ProjectLoad loaded = load_ok(project);
  const Document& back = loaded.document;
  EXPECT_TRUE(loaded.warnings.empty());
  EXPECT_FALSE(loaded.character_relocated);
  EXPECT_TRUE(same_content(doc, back));
  EXPECT_TRUE(same_params(doc.params, back.params));
  EXPECT_TRUE(same_set_edits(doc.set_edits, back.set_edits));
  EXPECT_TRUE(fs::equivalent(back.character_path, doc.character_path));
  EXPECT_EQ(back.character_hash, doc.character_hash);
  EXPECT_EQ(back.project_path, project);
  EXPECT_EQ(back.character->num_vertices(), 4u);
  EXPECT_EQ(back.cage->elements, doc.cage->elements);
  EXPECT_NE(back.revision, doc.revision);
  // saving what was loaded writes the same bytes
  ASSERT_TRUE(save_project(path("again.cagewrap"), back).ok());
  EXPECT_EQ(read_text(path("again.cagewrap")), read_text(project));
}

TEST_F(ProjectIoTest, SimulationRoundTripsAndBadSettingsAreNamed) {
  Document doc = make_doc();
  ASSERT_TRUE(save_project(path("plain.cagewrap"), doc).ok());
  EXPECT_EQ(read_text(path("plain.cagewrap")).find("\"simulation\""), std::string::npos);  // files without it stay as they were
  SimSettings s;
  s.enabled = true;
  s.params.damping = 1.25;
  s.params.gravity = {0.5, -9.0, 0.25};
  s.params.preroll = 0.5;
  s.params.iterations = 3;
  s.params.skeleton_colliders = true;
  s.vertices.assign(doc.cage->num_vertices(), SimVertex{});
  s.vertices[3] = {false, 2.5f, 0.125f};
  s.vertices[5] = {false, 0.1f, 0.0f};
  s.colliders.push_back({"table", ColliderKind::kCapsule, {0.1, 0.2, 0.3}, {1, 2, 3}, 0.05, -1});
  s.colliders.push_back({"", ColliderKind::kPlane, {0, 0, 0}, {0, 1, 0}, 0.1, -1});
  doc = with_sim(doc, s);
  const std::string project = path("sim.cagewrap");
  ASSERT_TRUE(save_project(project, doc).ok());
  ProjectLoad loaded = load_ok(project);
  EXPECT_TRUE(loaded.warnings.empty());
  EXPECT_EQ(loaded.document.sim, s);
  EXPECT_TRUE(same_content(doc, loaded.document));
  ASSERT_TRUE(save_project(path("again.cagewrap"), loaded.document).ok());
  EXPECT_EQ(read_text(path("again.cagewrap")), read_text(project));

  Error e = error_after([](Json& j) { j["simulation"] = {{"pinned", {1}}, {"mass", {1}}, {"stiffness", {0.5}}}; });
  EXPECT_EQ(e.code, ErrorCode::kTopologyMismatch);
  EXPECT_CONTAINS(e.message, "simulation.pinned has 1 entries");
  e = error_after([](Json& j) { j["simulation"] = {{"colliders", {{{"kind", "cone"}, {"a", {0, 0, 0}}}}}}; });
  EXPECT_CONTAINS(e.message, "simulation.colliders[0].kind is 'cone'");
  e = error_after([&](Json& j) {
    Json sim = Json::parse(read_text(project))["simulation"];
    sim["mass"][2] = -1;
    j["simulation"] = sim;
  });
  EXPECT_EQ(e.code, ErrorCode::kInvalidArgument);
  EXPECT_CONTAINS(e.message, "cage vertex 2 has mass -1");
  // and a document with bad settings is not saved
  s.vertices[4].stiffness = 2.0f;
  EXPECT_TRUE(Fails(save_project(path("bad.cagewrap"), with_sim(doc, s)), ErrorCode::kInvalidArgument,
                    {"not saved", "cage vertex 4"}));
  EXPECT_FALSE(fs::exists(path("bad.cagewrap")));
}

TEST_F(ProjectIoTest, ParametricDriverRoundTripsAndBadValuesAreNamed) {
  Document doc = make_doc();
  ASSERT_TRUE(save_project(path("plain.cagewrap"), doc).ok());
  EXPECT_EQ(read_text(path("plain.cagewrap")).find("\"patch_driver\""), std::string::npos);  // files without it stay as they were
  EXPECT_EQ(load_ok(path("plain.cagewrap")).document.patch_driver, nullptr);
  PatchDriver d;
  d.rest = PatchSurface{{test::wavy_grid(4, 5), test::wavy_grid(7, 4, PatchBasis::kBezier)}};
  d.posed = d.rest;
  std::vector<glm::dvec3> moved = d.posed.control_points();
  moved[3] += glm::dvec3(0.1234567890123, -1.0 / 3.0, 2e-9);  // doubles, not floats
  moved[27] -= glm::dvec3(0.5, 0.25, 1.0);
  d.posed.set_control_points(moved);
  d.density = 5;
  d.drive_skin = false;
  doc = with_patch_driver(doc, std::make_shared<const PatchDriver>(d));
  EXPECT_FALSE(same_content(doc, make_doc()));
  const std::string project = path("patch.cagewrap");
  ASSERT_TRUE(save_project(project, doc).ok());
  ProjectLoad loaded = load_ok(project);
  EXPECT_TRUE(loaded.warnings.empty());
  ASSERT_NE(loaded.document.patch_driver, nullptr);
  EXPECT_EQ(*loaded.document.patch_driver, d);  // bit for bit
  EXPECT_TRUE(same_content(doc, loaded.document));
  ASSERT_TRUE(save_project(path("again.cagewrap"), loaded.document).ok());
  EXPECT_EQ(read_text(path("again.cagewrap")), read_text(project));

  const Json saved = Json::parse(read_text(project))["patch_driver"];
  auto with = [&](auto change) {
    return error_after([&](Json& j) {
      j["patch_driver"] = saved;
      change(j["patch_driver"]);
    });
  };
  Error e = with([](Json& p) { p["posed"].erase(0); });
  EXPECT_EQ(e.code, ErrorCode::kTopologyMismatch);
  EXPECT_CONTAINS(e.message, "patch_driver.posed has 47 control points, but patch_driver.rest has 48");
  e = with([](Json& p) { p["posed"][7][1] = "x"; });
  EXPECT_CONTAINS(e.message, "patch_driver.posed[7][1] should be a number");
  e = with([](Json& p) { p["posed"][9][2] = nullptr; });
  EXPECT_EQ(e.code, ErrorCode::kNonFinite);
  EXPECT_CONTAINS(e.message, "patch_driver.posed[9][2]");
  e = with([](Json& p) { p["density"] = 0; });
  EXPECT_CONTAINS(e.message, "patch_driver.density is 0; it must be 1 to 1024");
  e = with([](Json& p) { p["rest"]["grids"][1]["rows"] = 6; });
  EXPECT_EQ(e.code, ErrorCode::kTopologyMismatch);
  EXPECT_CONTAINS(e.message, "patch_driver.rest.grids[1].points has 7 rows");
  e = with([](Json& p) { p.erase("rest"); });
  EXPECT_CONTAINS(e.message, "patch_driver");
  EXPECT_CONTAINS(e.message, "rest");
  e = with([](Json& p) { p["drive_skin"] = 1; });
  EXPECT_CONTAINS(e.message, "patch_driver.drive_skin should be true or false");
  // a driver whose posed grids do not match its rest grids is not saved
  PatchDriver bad = d;
  bad.posed.grids.pop_back();
  EXPECT_TRUE(Fails(save_project(path("bad.cagewrap"), with_patch_driver(doc, std::make_shared<const PatchDriver>(bad))),
                    ErrorCode::kTopologyMismatch, {"not saved", "20 posed control points for 48"}));
  EXPECT_FALSE(fs::exists(path("bad.cagewrap")));
}

TEST_F(ProjectIoTest, CagePositionsRoundTripBitForBit) {
  Document doc = make_doc();
  std::mt19937 rng(11);
  std::vector<glm::vec3> p(doc.cage_positions().begin(), doc.cage_positions().end());
  const float specials[] = {0.1f, -0.0f, 0.0f, 1e-40f /* subnormal */, std::numeric_limits<float>::min(),
                            std::numeric_limits<float>::max(), -3.4028e38f, 1.0f / 3.0f, 16777217.0f, 1e-7f};
  size_t k = 0;
  for (auto& v : p)
    for (int c = 0; c < 3; ++c) {
      if (k < std::size(specials)) {
        v[c] = specials[k++];
        continue;
      }
      float x;
      do x = std::bit_cast<float>(static_cast<uint32_t>(rng()));  // any finite bit pattern
      while (!std::isfinite(x));
      v[c] = x;
    }
  doc = with_cage_positions(doc, p);
  ASSERT_TRUE(save_project(path("bits.cagewrap"), doc).ok());
  Document back = load_ok(path("bits.cagewrap")).document;
  ASSERT_EQ(back.cage_positions().size(), p.size());
  for (size_t v = 0; v < p.size(); ++v)
    for (int c = 0; c < 3; ++c)
      EXPECT_EQ(std::bit_cast<uint32_t>(back.cage_positions()[v][c]), std::bit_cast<uint32_t>(p[v][c]))
          << "vertex " << v << " coordinate " << c << " = " << p[v][c];
  EXPECT_TRUE(same_content(doc, back));
}

// The driver's place in the stack, mask and keyposes (Document::driver_place) are saved inside "patch_driver"
// only when set; a file without them (every project before them) opens with the driver after every layer.
TEST_F(ProjectIoTest, ParametricDriverPlaceMaskAndKeyposesRoundTrip) {
  Document doc = make_doc();
  PatchDriver d;
  d.rest = PatchSurface{{test::wavy_grid(4, 5)}};
  d.posed = d.rest;
  doc = with_patch_driver(doc, std::make_shared<const PatchDriver>(d));
  ASSERT_TRUE(save_project(path("unplaced.cagewrap"), doc).ok());
  EXPECT_EQ(read_text(path("unplaced.cagewrap")).find("\"after\""), std::string::npos);
  EXPECT_EQ(load_ok(path("unplaced.cagewrap")).document.driver_place, DriverPlacement{});
  EXPECT_EQ(DriverPlacement{}.after, -1);

  DriverPlacement place;
  place.after = 0;
  auto mask = std::make_shared<std::vector<float>>(doc.character->num_vertices(), 0.25f);
  (*mask)[0] = 1.0f;
  place.mask = mask;
  place.mask_source = "joints spine";
  KeyposeSet set;
  set.name = "bend";
  set.drivers.push_back(JointDriver{});
  set.keys.push_back(make_key({30.0}, std::vector<glm::vec3>{glm::vec3(0.0f), glm::vec3(0.0f, 0.125f, -0.5f)}));
  place.keyposes.push_back(set);
  BindParams own;
  own.local = 6.5;
  own.epsilon = 0.0625;
  own.max_elements = 5;
  place.params = own;
  doc = with_driver_place(doc, place);
  const std::string project = path("placed.cagewrap");
  ASSERT_TRUE(save_project(project, doc).ok());
  ProjectLoad loaded = load_ok(project);
  EXPECT_TRUE(loaded.warnings.empty());
  EXPECT_EQ(loaded.document.driver_place, place);
  EXPECT_TRUE(same_content(doc, loaded.document));
  EXPECT_FALSE(same_content(doc, with_driver_place(doc, DriverPlacement{})));
  ASSERT_TRUE(save_project(path("placed_again.cagewrap"), loaded.document).ok());
  EXPECT_EQ(read_text(path("placed_again.cagewrap")), read_text(project));

  const Json saved = Json::parse(read_text(project))["patch_driver"];
  auto with = [&](auto change) {
    return error_after([&](Json& j) {
      j["patch_driver"] = saved;
      change(j["patch_driver"]);
    });
  };
  Error e = with([](Json& p) { p["mask"].erase(0); });
  EXPECT_EQ(e.code, ErrorCode::kTopologyMismatch);
  EXPECT_CONTAINS(e.message, "patch_driver.mask has");
  e = with([](Json& p) { p["mask"][3] = 1.5; });
  EXPECT_CONTAINS(e.message, "patch_driver.mask[3] should be in [0, 1]");
  e = with([](Json& p) { p["keyposes"][0]["keys"][0]["vertices"][0] = 20; });  // the driver has 20 control points: 0..19
  EXPECT_CONTAINS(e.message, "20");
  e = with([](Json& p) { p["after"] = -2; });
  EXPECT_CONTAINS(e.message, "patch_driver.after");
  e = with([](Json& p) { p["binding"]["epsilon"] = 3.0; });
  EXPECT_CONTAINS(e.message, "patch_driver: binding");
}

TEST_F(ProjectIoTest, DriverOffsetsRoundTripAndMustMatchTheCage) {
  Document doc = make_doc();
  std::vector<glm::vec3> offsets(doc.cage->num_vertices(), glm::vec3(0.f));
  offsets[1] = {0.125f, -0.5f, 3e-7f};
  doc = with_cage_offsets(doc, offsets);
  ASSERT_TRUE(save_project(path("offsets.cagewrap"), doc).ok());
  auto back = load_project(path("offsets.cagewrap"));
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(back->document.cage_offsets, offsets);
  // a file whose offsets do not match the cage is refused, naming both counts
  std::string text;
  {
    std::ifstream in(path("offsets.cagewrap"));
    text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  size_t at = text.find("\"offsets\": [") + 13;
  text.insert(at, "\n      [0, 0, 0],");
  { std::ofstream(path("bad_offsets.cagewrap")) << text; }
  auto bad = load_project(path("bad_offsets.cagewrap"));
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find(std::to_string(offsets.size() + 1) + " entries"), std::string::npos) << bad.error().message;
  // replacing the cage with one of another vertex count drops the offsets
  PolyMesh smaller = doc.cage->polygons;
  smaller.positions.push_back(glm::vec3(9.f));
  EXPECT_TRUE(with_cage(doc, std::make_shared<const Cage>(std::move(make_cage(smaller, "c")).value())).cage_offsets.empty());
}

TEST_F(ProjectIoTest, FloatsAreWrittenShort) {
  Document doc = make_doc();
  std::vector<glm::vec3> p(doc.cage_positions().begin(), doc.cage_positions().end());
  p[0] = {0.1f, 0.3f, -2.5f};
  ASSERT_TRUE(save_project(path("short.cagewrap"), with_cage_positions(doc, p)).ok());
  std::string text = read_text(path("short.cagewrap"));
  EXPECT_CONTAINS(text, "[0.1, 0.3, -2.5]");
  EXPECT_EQ(text.find("0.10000000149"), std::string::npos);
}

TEST_F(ProjectIoTest, FileLayoutMatchesTheFormatDocument) {
  ASSERT_TRUE(save_project(path("p.cagewrap"), make_doc()).ok());
  Json j = Json::parse(read_text(path("p.cagewrap")));
  EXPECT_EQ(j["format"], "cagewrap-project");
  EXPECT_EQ(j["version"], 2);
  EXPECT_EQ(j["character"]["path"], "hero.gltf");
  EXPECT_EQ(j["character"]["hash"], format_hash(fnv1a64(read_text(path("hero.gltf")))));
  EXPECT_EQ(j["cage"]["positions"].size(), 26u);
  EXPECT_EQ(j["cage"]["faces"].size(), 24u);
  EXPECT_EQ(j["cage"]["faces"][0].size(), 4u);
  EXPECT_EQ(j["binding"]["variant"], "clamped");
  EXPECT_EQ(j["binding"]["max_elements"], 5);
  EXPECT_EQ(j["binding"]["epsilon"], 0.0123456789012345);
  EXPECT_EQ(j["set_edits"][0]["point"], 2);
  EXPECT_EQ(j["set_edits"][0]["exclude"], Json::array({0, 7}));
  EXPECT_EQ(j["set_edits"][1]["include"], Json::array({47}));
  EXPECT_TRUE(j["extensions"].is_object());
  EXPECT_EQ(j["attachment"], Json::parse(R"({"mode": "fitted", "smooth_width": 0.5, "overrides": []})"));
  EXPECT_EQ(j["keyposes"], Json::array());
  std::vector<std::string> keys;
  for (const auto& [key, value] : j.items()) keys.push_back(key);
  EXPECT_EQ(keys, (std::vector<std::string>{"format", "version", "character", "cage", "binding", "set_edits",
                                            "attachment", "keyposes", "extensions"}));
}

TEST_F(ProjectIoTest, ProjectWithoutCage) {
  Document doc = with_cage(make_doc(), nullptr);
  doc = with_set_edits(doc, {});
  ASSERT_TRUE(save_project(path("nocage.cagewrap"), doc).ok());
  Document back = load_ok(path("nocage.cagewrap")).document;
  EXPECT_FALSE(back.has_cage());
  EXPECT_TRUE(same_content(doc, back));
}

TEST_F(ProjectIoTest, CharacterPathIsRelativeToTheProject) {
  Document doc = make_doc();
  fs::create_directories(dir_ / "projects" / "v1");
  ASSERT_TRUE(save_project(path("projects/v1/p.cagewrap"), doc).ok());
  EXPECT_EQ(Json::parse(read_text(path("projects/v1/p.cagewrap")))["character"]["path"], "../../hero.gltf");
  fs::create_directories(dir_ / "chars");
  fs::copy_file(path("hero.gltf"), path("chars/hero.gltf"));
  doc.character_path = path("chars/hero.gltf");
  ASSERT_TRUE(save_project(path("q.cagewrap"), doc).ok());
  EXPECT_EQ(Json::parse(read_text(path("q.cagewrap")))["character"]["path"], "chars/hero.gltf");
}

TEST_F(ProjectIoTest, MovingProjectAndCharacterTogetherKeepsItWorking) {
  fs::create_directories(dir_ / "a" / "chars");
  test::write_tiny_character(path("a/chars/hero.gltf"));
  test::write_box_cage(path("a/cage.obj"));
  auto doc = document_from_files(path("a/chars/hero.gltf"), path("a/cage.obj"));
  ASSERT_TRUE(doc.ok());
  ASSERT_TRUE(save_project(path("a/p.cagewrap"), *doc).ok());
  fs::rename(dir_ / "a", dir_ / "b");  // the old paths no longer exist
  ProjectLoad loaded = load_ok(path("b/p.cagewrap"));
  EXPECT_TRUE(loaded.warnings.empty());
  EXPECT_TRUE(fs::equivalent(loaded.document.character_path, path("b/chars/hero.gltf")));
  EXPECT_TRUE(same_content(*doc, loaded.document));
  // a project path given relative to the working directory resolves the same way
  fs::path cwd = fs::current_path();
  fs::current_path(dir_);
  auto relative = load_project("b/p.cagewrap");
  fs::current_path(cwd);
  ASSERT_TRUE(relative.ok()) << relative.error().message;
  EXPECT_TRUE(fs::path(relative->document.character_path).is_absolute());
  EXPECT_TRUE(fs::equivalent(relative->document.character_path, path("b/chars/hero.gltf")));
}

TEST_F(ProjectIoTest, MissingProjectFile) {
  std::string missing = "unchanged";
  auto r = load_project(path("nope.cagewrap"), {}, &missing);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ErrorCode::kFileNotFound);
  EXPECT_CONTAINS(r.error().message, "nope.cagewrap");
  EXPECT_TRUE(missing.empty());  // it is the project that is missing, not the character
}

TEST_F(ProjectIoTest, NotJsonNamesTheFileAndThePosition) {
  write_text(path("p.cagewrap"), "{\n  \"format\": \"cagewrap-project\",\n  oops\n}\n");
  auto r = load_project(path("p.cagewrap"));
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ErrorCode::kParse);
  EXPECT_CONTAINS(r.error().message, path("p.cagewrap") + ": not a JSON file");
  EXPECT_CONTAINS(r.error().message, "line 3, column 3");
  write_text(path("empty.cagewrap"), "");
  auto e = load_project(path("empty.cagewrap"));
  ASSERT_FALSE(e.ok());
  EXPECT_EQ(e.error().code, ErrorCode::kParse);
  EXPECT_CONTAINS(e.error().message, "line 1, column 1");
}

TEST_F(ProjectIoTest, WrongFormat) {
  write_text(path("a.cagewrap"), R"({"format": "gltf", "version": 1})");
  auto a = load_project(path("a.cagewrap"));
  ASSERT_FALSE(a.ok());
  EXPECT_EQ(a.error().code, ErrorCode::kUnsupportedFormat);
  EXPECT_CONTAINS(a.error().message, "not a cagewrap project (\"format\" is \"gltf\"");
  write_text(path("b.cagewrap"), R"({"asset": {"version": "2.0"}})");
  auto b = load_project(path("b.cagewrap"));
  ASSERT_FALSE(b.ok());
  EXPECT_EQ(b.error().code, ErrorCode::kUnsupportedFormat);
  write_text(path("c.cagewrap"), "[1, 2]");
  EXPECT_EQ(load_project(path("c.cagewrap")).error().code, ErrorCode::kUnsupportedFormat);
}

TEST_F(ProjectIoTest, NewerVersion) {
  Error e = error_after([](Json& j) { j["version"] = 5; });
  EXPECT_EQ(e.code, ErrorCode::kVersion);
  EXPECT_CONTAINS(e.message, "made by a newer cagewrap: version 5, this build reads up to 4");
  Error bad = error_after([](Json& j) { j["version"] = "1"; });
  EXPECT_EQ(bad.code, ErrorCode::kParse);
  EXPECT_CONTAINS(bad.message, "version should be a whole number >= 1");
  EXPECT_EQ(error_after([](Json& j) { j["version"] = 0; }).code, ErrorCode::kParse);
  EXPECT_CONTAINS(error_after([](Json& j) { j.erase("version"); }).message, "version is missing");
}

TEST_F(ProjectIoTest, MissingAndInvalidFieldsNameTheJsonPath) {
  Error e = error_after([](Json& j) { j["binding"].erase("epsilon"); });
  EXPECT_EQ(e.code, ErrorCode::kParse);
  EXPECT_CONTAINS(e.message, path("p.cagewrap") + ": binding.epsilon is missing");
  EXPECT_CONTAINS(error_after([](Json& j) { j.erase("cage"); }).message, "cage is missing");
  EXPECT_CONTAINS(error_after([](Json& j) { j["cage"] = 3; }).message, "cage should be an object");
  EXPECT_CONTAINS(error_after([](Json& j) { j["character"].erase("path"); }).message, "character.path is missing");
  EXPECT_CONTAINS(error_after([](Json& j) { j["character"]["hash"] = 5; }).message, "character.hash should be a string");
  EXPECT_CONTAINS(error_after([](Json& j) { j["cage"]["faces"][12][3] = "x"; }).message,
                  "cage.faces[12][3] should be an index (a whole number >= 0), not \"x\"");
  EXPECT_CONTAINS(error_after([](Json& j) { j["cage"]["faces"][4][1] = -1; }).message, "cage.faces[4][1] should be an index");
  EXPECT_CONTAINS(error_after([](Json& j) { j["cage"]["faces"][2] = Json::array({0, 1}); }).message,
                  "cage.faces[2] has 2 corners; a face needs at least 3");
  EXPECT_CONTAINS(error_after([](Json& j) { j["cage"]["positions"][5] = Json::array({1, 2}); }).message,
                  "cage.positions[5] should be [x, y, z]");
  EXPECT_CONTAINS(error_after([](Json& j) { j["cage"]["positions"][5][2] = "1.0"; }).message,
                  "cage.positions[5][2] should be a number");
  EXPECT_CONTAINS(error_after([](Json& j) { j["cage"]["faces"] = Json::array(); }).message,
                  "cage.faces is empty; a cage needs at least one face");
  EXPECT_CONTAINS(error_after([](Json& j) { j["binding"]["max_elements"] = 2.5; }).message, "binding.max_elements");
  Error variant = error_after([](Json& j) { j["binding"]["variant"] = "fancy"; });
  EXPECT_CONTAINS(variant.message, "binding.variant is 'fancy'; expected basic, clamped or extended");
  Error range = error_after([](Json& j) { j["binding"]["epsilon"] = 2.0; });
  EXPECT_EQ(range.code, ErrorCode::kInvalidArgument);
  EXPECT_CONTAINS(range.message, "binding: epsilon must be in (0, 1]");
  EXPECT_CONTAINS(error_after([](Json& j) { j["set_edits"][1].erase("point"); }).message, "set_edits[1].point is missing");
  EXPECT_CONTAINS(error_after([](Json& j) { j["set_edits"] = Json::object(); }).message, "set_edits should be an array");
  EXPECT_CONTAINS(error_after([](Json& j) { j["extensions"] = 1; }).message, "extensions should be an object");
}

TEST_F(ProjectIoTest, IndicesOutOfRange) {
  Error face = error_after([](Json& j) { j["cage"]["faces"][12][3] = 26; });
  EXPECT_EQ(face.code, ErrorCode::kIndexOutOfRange);
  EXPECT_CONTAINS(face.message, "cage.faces[12][3] is vertex 26, but the cage has 26 vertices");
  Error element = error_after([](Json& j) { j["set_edits"][0]["exclude"][1] = 48; });
  EXPECT_EQ(element.code, ErrorCode::kIndexOutOfRange);
  EXPECT_CONTAINS(element.message, "set_edits[0].exclude[1] is element 48, but the cage has 48 elements");
  Error point = error_after([](Json& j) { j["set_edits"][1]["point"] = 4; });
  EXPECT_EQ(point.code, ErrorCode::kIndexOutOfRange);
  EXPECT_CONTAINS(point.message, "set_edits[1].point is skin vertex 4, but the character has 4 vertices");
}

TEST_F(ProjectIoTest, NonFinitePositions) {
  // nlohmann writes NaN and infinity as null
  Error null = error_after([](Json& j) { j["cage"]["positions"][3][1] = nullptr; });
  EXPECT_EQ(null.code, ErrorCode::kNonFinite);
  EXPECT_CONTAINS(null.message, "cage.positions[3][1] is null");
  Error huge = error_after([](Json& j) { j["cage"]["positions"][3][0] = 1e39; });
  EXPECT_EQ(huge.code, ErrorCode::kNonFinite);
  EXPECT_CONTAINS(huge.message, "cage.positions[3][0] = 1e+39 is too large for a float coordinate");
  // a literal too large for a double
  std::string project = path("p.cagewrap");
  ASSERT_TRUE(save_project(project, make_doc()).ok());
  std::string text = read_text(project);
  size_t at = text.find("\n      [", text.find("\"positions\"")) + 8;  // the first x
  text.replace(at, text.find(',', at) - at, "1e999");
  write_text(project, text);
  auto r = load_project(project);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ErrorCode::kParse);
  EXPECT_CONTAINS(r.error().message, "p.cagewrap: not a JSON file (number overflow parsing '1e999')");
  // just past the largest float: rounds to infinity; just below: rounds to FLT_MAX and loads
  EXPECT_EQ(error_after([](Json& j) { j["cage"]["positions"][0][0] = 0x1.ffffffp127; }).code, ErrorCode::kNonFinite);
  ASSERT_TRUE(save_project(project, make_doc()).ok());
  Json j = Json::parse(read_text(project));
  j["cage"]["positions"][0][0] = 0x1.fffffefffffffp127;
  write_text(project, j.dump());
  auto near_max = load_project(project);
  ASSERT_TRUE(near_max.ok()) << near_max.error().message;
  EXPECT_EQ(near_max->document.cage_positions()[0].x, std::numeric_limits<float>::max());
}

TEST_F(ProjectIoTest, MissingCharacterCanBeLocated) {
  Document doc = make_doc();
  std::string project = path("p.cagewrap");
  ASSERT_TRUE(save_project(project, doc).ok());
  fs::create_directories(dir_ / "moved");
  fs::rename(path("hero.gltf"), path("moved/hero.gltf"));
  std::string missing;
  auto r = load_project(project, {}, &missing);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ErrorCode::kFileNotFound);
  EXPECT_CONTAINS(r.error().message, "character file " + path("hero.gltf") + " not found; locate it");
  EXPECT_EQ(missing, path("hero.gltf"));

  // the editor asks where it went and opens again with the answer
  ProjectLoad located = load_ok(project, path("moved/hero.gltf"));
  EXPECT_TRUE(located.character_relocated);
  EXPECT_TRUE(located.warnings.empty());  // same bytes: no hash warning
  EXPECT_EQ(located.document.character_path, path("moved/hero.gltf"));
  EXPECT_TRUE(same_content(doc, located.document));
  // saving records the new place
  ASSERT_TRUE(save_project(project, located.document).ok());
  EXPECT_EQ(Json::parse(read_text(project))["character"]["path"], "moved/hero.gltf");
  EXPECT_FALSE(load_ok(project).character_relocated);

  // an override that does not exist either is reported the same way
  auto again = load_project(project, path("elsewhere.glb"), &missing);
  ASSERT_FALSE(again.ok());
  EXPECT_EQ(missing, path("elsewhere.glb"));
}

TEST_F(ProjectIoTest, ChangedCharacterIsAWarning) {
  Document doc = make_doc();
  std::string project = path("p.cagewrap");
  ASSERT_TRUE(save_project(project, doc).ok());
  test::write_tiny_character(path("hero.gltf"), 0.5f);  // same structure, different bytes
  ProjectLoad loaded = load_ok(project);
  ASSERT_EQ(loaded.warnings.size(), 1u);
  EXPECT_CONTAINS(loaded.warnings[0], "changed since the project was saved");
  EXPECT_CONTAINS(loaded.warnings[0], doc.character_hash);
  EXPECT_NE(loaded.document.character_hash, doc.character_hash);
  EXPECT_EQ(loaded.document.character->primitives[0].positions[0].x, 0.5f);
}

TEST_F(ProjectIoTest, UnknownFieldsAreKeptAndReported) {
  std::string project = path("p.cagewrap");
  ASSERT_TRUE(save_project(project, make_doc()).ok());
  Json j = Json::parse(read_text(project));
  j["muscles"] = Json::array({1, 2, {{"a", 3}}});
  j["extensions"] = {{"vendor", {{"x", 1.5}}}};
  j["attachments"] = "later";
  j["binding"]["future_knob"] = 7;
  write_text(project, j.dump(2));
  ProjectLoad loaded = load_ok(project);
  ASSERT_EQ(loaded.warnings.size(), 3u);
  EXPECT_CONTAINS(loaded.warnings[0], "binding.future_knob is not known to this build and was ignored");
  EXPECT_CONTAINS(loaded.warnings[1], "field 'muscles' is not known to this build");
  EXPECT_CONTAINS(loaded.warnings[1], "kept and written back on save");
  EXPECT_CONTAINS(loaded.warnings[2], "'attachments'");
  ASSERT_TRUE(save_project(path("resaved.cagewrap"), loaded.document).ok());
  Json back = Json::parse(read_text(path("resaved.cagewrap")));
  EXPECT_EQ(back["muscles"], j["muscles"]);
  EXPECT_EQ(back["extensions"], j["extensions"]);
  EXPECT_EQ(back["attachments"], "later");
  EXPECT_FALSE(back["binding"].contains("future_knob"));
  std::vector<std::string> keys;
  for (const auto& [key, value] : back.items()) keys.push_back(key);
  EXPECT_EQ(keys.back(), "attachments");  // unknown fields follow the known ones, in file order
  EXPECT_EQ(keys[keys.size() - 2], "muscles");
}

TEST_F(ProjectIoTest, SaveIntoAMissingFolderFailsCleanly) {
  std::string target = path("no/such/folder/p.cagewrap");
  Status s = save_project(target, make_doc());
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, ErrorCode::kWrite);
  EXPECT_CONTAINS(s.error().message, target + ": could not save");
  EXPECT_FALSE(fs::exists(path("no")));
}

TEST_F(ProjectIoTest, SaveIntoAReadOnlyFolderFailsCleanly) {
  Document doc = make_doc();
  fs::create_directories(dir_ / "locked");
  std::string project = path("locked/p.cagewrap");
  ASSERT_TRUE(save_project(project, doc).ok());
  const std::string old = read_text(project);
  chmod(path("locked").c_str(), 0555);
  Status s = save_project(project, with_params(doc, BindParams{}));
  chmod(path("locked").c_str(), 0755);
  if (geteuid() == 0) GTEST_SKIP() << "running as root: a read-only folder does not stop root";
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, ErrorCode::kWrite);
  EXPECT_CONTAINS(s.error().message, "Permission denied");
  EXPECT_EQ(read_text(project), old);
}

TEST_F(ProjectIoTest, FailedSaveLeavesTheOldFileUntouched) {
  Document doc = make_doc();
  std::string project = path("p.cagewrap");
  ASSERT_TRUE(save_project(project, doc).ok());
  const std::string old = read_text(project);
  std::vector<glm::vec3> p(doc.cage_positions().begin(), doc.cage_positions().end());
  p[0].x += 1;
  Document edited = with_cage_positions(doc, p);

  // the temporary file cannot be created (a folder is in the way)
  fs::create_directory(project + ".tmp");
  Status blocked = save_project(project, edited);
  ASSERT_FALSE(blocked.ok());
  EXPECT_EQ(blocked.error().code, ErrorCode::kWrite);
  EXPECT_EQ(read_text(project), old);
  fs::remove(project + ".tmp");

  // the disk fills up half way through the write (the file size limit stands in for a full disk)
  std::vector<glm::vec3> many(5000, glm::vec3(0.123456f, -7.654321f, 1e-3f));
  PolyMesh big;
  big.positions = many;
  for (uint32_t i = 0; i + 2 < 5000; i += 3) big.add_face({i, i + 1, i + 2});
  auto cage = make_cage(big, "big");
  ASSERT_TRUE(cage.ok());
  Document large = with_cage(doc, std::make_shared<const Cage>(std::move(cage).value()));
  struct rlimit saved;
  ASSERT_EQ(getrlimit(RLIMIT_FSIZE, &saved), 0);
  auto old_handler = signal(SIGXFSZ, SIG_IGN);
  struct rlimit small = saved;
  small.rlim_cur = 16384;
  ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &small), 0);
  Status full = save_project(project, large);
  setrlimit(RLIMIT_FSIZE, &saved);
  signal(SIGXFSZ, old_handler);
  ASSERT_FALSE(full.ok());
  EXPECT_EQ(full.error().code, ErrorCode::kWrite);
  EXPECT_CONTAINS(full.error().message, "writing");
  EXPECT_EQ(read_text(project), old);
  EXPECT_FALSE(fs::exists(project + ".tmp"));

  // once there is room the same save goes through
  ASSERT_TRUE(save_project(project, large).ok());
  EXPECT_EQ(load_ok(project).document.cage->num_vertices(), 5000u);

  // non-finite positions are refused before anything is written
  const std::string complete = read_text(project);
  p[3].y = std::numeric_limits<float>::quiet_NaN();
  Status nan = save_project(project, with_cage_positions(doc, p));
  ASSERT_FALSE(nan.ok());
  EXPECT_EQ(nan.error().code, ErrorCode::kNonFinite);
  EXPECT_CONTAINS(nan.error().message, "cage vertex 3 has a non-finite coordinate");
  EXPECT_EQ(read_text(project), complete);
  // so are parameters that could not be read back
  BindParams bad;
  bad.local = std::numeric_limits<double>::infinity();
  Status params = save_project(project, with_params(doc, bad));
  ASSERT_FALSE(params.ok());
  EXPECT_CONTAINS(params.error().message, "not saved: local must be a finite number");
  // and a character path that JSON cannot hold
  Document odd = doc;
  odd.character_path = path("hero\xff.gltf");
  EXPECT_FALSE(save_project(project, odd).ok());
  EXPECT_EQ(read_text(project), complete);
}

TEST_F(ProjectIoTest, SaveReplacesTheFileInsteadOfRewritingIt) {
  Document doc = make_doc();
  std::string project = path("p.cagewrap");
  ASSERT_TRUE(save_project(project, doc).ok());
  const std::string old = read_text(project);
  chmod(project.c_str(), 0600);
  std::ifstream reader(project, std::ios::binary);  // someone is reading the old file
  ASSERT_TRUE(save_project(project, with_params(doc, BindParams{})).ok());
  std::stringstream seen;
  seen << reader.rdbuf();
  EXPECT_EQ(seen.str(), old);  // an open reader still sees the complete old file
  EXPECT_NE(read_text(project), old);
  EXPECT_TRUE(load_ok(project).warnings.empty());
  struct stat st;
  ASSERT_EQ(stat(project.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600u);  // permissions survive the replacement
}

TEST_F(ProjectIoTest, NeverWritesOverTheCharacterFile) {
  Document doc = make_doc();
  const std::string character = read_text(path("hero.gltf"));
  Status s = save_project(path("hero.gltf"), doc);
  ASSERT_FALSE(s.ok());
  EXPECT_CONTAINS(s.error().message, "that is the character file");
  fs::path cwd = fs::current_path();
  fs::current_path(dir_);
  Status relative = save_project("./hero.gltf", doc);
  fs::current_path(cwd);
  EXPECT_FALSE(relative.ok());
  EXPECT_EQ(read_text(path("hero.gltf")), character);
}

TEST_F(ProjectIoTest, AtomicWriteCreatesAndReplaces) {
  ASSERT_TRUE(write_file_atomic(path("f.txt"), "one").ok());
  EXPECT_EQ(read_text(path("f.txt")), "one");
  ASSERT_TRUE(write_file_atomic(path("f.txt"), "two, longer").ok());
  EXPECT_EQ(read_text(path("f.txt")), "two, longer");
  ASSERT_TRUE(write_file_atomic(path("f.txt"), "").ok());
  EXPECT_EQ(read_text(path("f.txt")), "");
  EXPECT_FALSE(fs::exists(path("f.txt.tmp")));
}

TEST(ProjectIoDemo, DemoCharacterRoundTrip) {
  std::string demo = std::string(CAGEWRAP_SOURCE_DIR) + "/assets/demo_character.glb";
  if (!fs::exists(demo)) GTEST_SKIP() << demo << " not found";
  std::string dir = test::temp_dir("project_demo");
  test::write_box_cage(dir + "/cage.obj", 1.5, 3);
  auto doc = document_from_files(demo, dir + "/cage.obj");
  ASSERT_TRUE(doc.ok()) << doc.error().message;
  ASSERT_TRUE(save_project(dir + "/demo.cagewrap", *doc).ok());
  auto back = load_project(dir + "/demo.cagewrap");
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_TRUE(same_content(*doc, back->document));
  EXPECT_EQ(back->document.character->num_vertices(), doc->character->num_vertices());
  EXPECT_TRUE(back->warnings.empty());
  fs::remove_all(dir);
}

}  // namespace
}  // namespace cagewrap

// ------------------------------------------------------------------ version 2: attachment, keyposes
namespace cagewrap {
namespace {

class ProjectIoRigTest : public ProjectIoTest {
 protected:
  // make_doc() with a smooth attachment, two overrides and two keypose sets (one and two drivers).
  Document make_rig_doc() {
    Document doc = make_doc();
    AttachmentSettings a;
    a.mode = AttachmentMode::kSmooth;
    a.smooth_width = 0.7;
    a = assign_vertices(a, std::vector<uint32_t>{5, 3}, 0u);
    doc = with_attachment(doc, a);
    KeyposeSet bulge;
    bulge.name = "bulge";
    bulge.drivers = {JointDriver{0, DriverKind::kTwist, {0.0f, 0.0f, 1.0f}}};
    bulge.interpolation = KeyInterpolation::kSmooth;
    std::vector<glm::vec3> dense(doc.cage->num_vertices(), glm::vec3(0.0f));
    dense[1] = {0.1f, -0.25f, 1e-7f};
    dense[4] = {0.3f, 0.0f, -2.0f};
    set_key(bulge, make_key({120.0}, dense));
    dense[7] = {0.5f, 0.5f, 0.5f};
    set_key(bulge, make_key({-45.5}, dense));
    KeyposeSet shoulder;
    shoulder.name = "shoulder space";
    shoulder.drivers = {JointDriver{0, DriverKind::kRotation, {1.0f, 0.0f, 0.0f}},
                        JointDriver{0, DriverKind::kSwing, {0.0f, 1.0f, 0.0f}}};
    shoulder.kernel = RbfKernel::kThinPlate;
    shoulder.rbf_width = 33.25;
    shoulder.rest_key = false;
    shoulder.mute = true;
    set_key(shoulder, make_key({10.0, 20.0}, dense));
    return with_keyposes(doc, {bulge, shoulder});
  }
};

TEST_F(ProjectIoRigTest, AttachmentAndKeyposesRoundTrip) {
  Document doc = make_rig_doc();
  ASSERT_TRUE(save_project(path("rig.cagewrap"), doc).ok());
  ProjectLoad loaded = load_ok(path("rig.cagewrap"));
  EXPECT_TRUE(loaded.warnings.empty());
  EXPECT_TRUE(same_content(doc, loaded.document));
  EXPECT_EQ(loaded.document.attachment, doc.attachment);
  EXPECT_EQ(loaded.document.keyposes, doc.keyposes);
  // what the file says: nodes by name, angles in degrees, sparse offsets
  Json j = Json::parse(read_text(path("rig.cagewrap")));
  EXPECT_EQ(j["attachment"]["mode"], "smooth");
  EXPECT_EQ(j["attachment"]["smooth_width"], 0.7);
  EXPECT_EQ(j["attachment"]["overrides"][0], Json::parse(R"({"vertex": 3, "node": "tet_node"})"));
  EXPECT_EQ(j["keyposes"][0]["drivers"][0],
            Json::parse(R"({"node": "tet_node", "kind": "twist", "axis": [0, 0, 1]})"));
  EXPECT_EQ(j["keyposes"][0]["interpolation"], "smooth");
  EXPECT_EQ(j["keyposes"][0]["keys"][0]["values"], Json::array({-45.5}));  // sorted by value
  EXPECT_EQ(j["keyposes"][0]["keys"][1]["vertices"], Json::array({1, 4}));
  EXPECT_EQ(j["keyposes"][0]["keys"][1]["offsets"][0], Json::parse("[0.1, -0.25, 1e-07]"));
  EXPECT_EQ(j["keyposes"][1]["kernel"], "thin_plate");
  EXPECT_EQ(j["keyposes"][1]["rest_key"], false);
  EXPECT_EQ(j["keyposes"][1]["mute"], true);
  // saving the loaded document again gives the same bytes
  ASSERT_TRUE(save_project(path("again.cagewrap"), loaded.document).ok());
  EXPECT_EQ(read_text(path("again.cagewrap")), read_text(path("rig.cagewrap")));
}

TEST_F(ProjectIoRigTest, NodesMayBeGivenByIndex) {
  ASSERT_TRUE(save_project(path("p.cagewrap"), make_rig_doc()).ok());
  Json j = Json::parse(read_text(path("p.cagewrap")));
  j["keyposes"][0]["drivers"][0]["node"] = 0;
  j["attachment"]["overrides"][1]["node"] = 0;
  write_text(path("p.cagewrap"), j.dump(2));
  ProjectLoad loaded = load_ok(path("p.cagewrap"));
  EXPECT_EQ(loaded.document.keyposes, make_rig_doc().keyposes);
}

TEST_F(ProjectIoRigTest, Version1FilesStillLoad) {
  Document doc = make_doc();
  doc.attachment.mode = AttachmentMode::kRigid;  // the only mode version 1 had
  ASSERT_TRUE(save_project(path("v1.cagewrap"), doc).ok());
  Json j = Json::parse(read_text(path("v1.cagewrap")));
  j["version"] = 1;
  j.erase("attachment");
  j.erase("keyposes");
  write_text(path("v1.cagewrap"), j.dump(2));
  ProjectLoad loaded = load_ok(path("v1.cagewrap"));
  EXPECT_TRUE(loaded.warnings.empty());
  EXPECT_TRUE(same_content(doc, loaded.document));
  EXPECT_EQ(loaded.document.attachment, doc.attachment);
  EXPECT_TRUE(loaded.document.keyposes.empty());
  // and are written back as version 2
  ASSERT_TRUE(save_project(path("v2.cagewrap"), loaded.document).ok());
  EXPECT_EQ(Json::parse(read_text(path("v2.cagewrap")))["version"], 2);
}

TEST_F(ProjectIoRigTest, UnknownFieldsInsideAreDroppedWithAWarning) {
  ASSERT_TRUE(save_project(path("p.cagewrap"), make_rig_doc()).ok());
  Json j = Json::parse(read_text(path("p.cagewrap")));
  j["attachment"]["stiffness"] = 2;
  j["keyposes"][1]["keys"][0]["tangent"] = 1;
  write_text(path("p.cagewrap"), j.dump(2));
  ProjectLoad loaded = load_ok(path("p.cagewrap"));
  ASSERT_EQ(loaded.warnings.size(), 2u);
  EXPECT_CONTAINS(loaded.warnings[0], "attachment.stiffness is not known to this build and was ignored");
  EXPECT_CONTAINS(loaded.warnings[1], "keyposes[1].keys[0].tangent is not known");
}

TEST_F(ProjectIoRigTest, ErrorsNameTheJsonPath) {
  auto error_in = [&](auto edit) {
    EXPECT_TRUE(save_project(path("p.cagewrap"), make_rig_doc()).ok());
    Json j = Json::parse(read_text(path("p.cagewrap")));
    edit(j);
    write_text(path("p.cagewrap"), j.dump(2));
    auto r = load_project(path("p.cagewrap"));
    EXPECT_FALSE(r.ok());
    return r.ok() ? Error{ErrorCode::kCancelled, "loaded"} : r.error();
  };
  Error e = error_in([](Json& j) { j["keyposes"][0]["drivers"][0]["node"] = "elbow"; });
  EXPECT_CONTAINS(
      e.message,
      path("p.cagewrap") +
          ": keyposes[0].drivers[0].node is node 'elbow', but the character has no node of that name");
  e = error_in([](Json& j) { j["keyposes"][0]["drivers"][0]["node"] = 7; });
  EXPECT_EQ(e.code, ErrorCode::kIndexOutOfRange);
  EXPECT_CONTAINS(e.message, "keyposes[0].drivers[0].node is node 7, but the character has 1 nodes");
  e = error_in([](Json& j) { j["keyposes"][0]["drivers"][0]["kind"] = "bend"; });
  EXPECT_CONTAINS(e.message, "keyposes[0].drivers[0].kind is 'bend'; expected rotation, twist or swing");
  e = error_in([](Json& j) { j["keyposes"][0]["drivers"][0]["axis"] = Json::array({0, 0, 0}); });
  EXPECT_CONTAINS(e.message, "keyposes[0].drivers[0].axis is [0, 0, 0]");
  e = error_in([](Json& j) { j["keyposes"][0]["keys"][1]["vertices"][1] = 26; });
  EXPECT_EQ(e.code, ErrorCode::kIndexOutOfRange);
  EXPECT_CONTAINS(e.message,
                  "keyposes[0].keys[1].vertices[1] is cage vertex 26, but the cage has 26 vertices");
  e = error_in([](Json& j) { j["keyposes"][0]["keys"][1]["vertices"][1] = 1; });
  EXPECT_CONTAINS(e.message, "keyposes[0].keys[1].vertices lists cage vertex 1 twice");
  e = error_in([](Json& j) { j["keyposes"][0]["keys"][1]["offsets"][0][2] = nullptr; });
  EXPECT_EQ(e.code, ErrorCode::kNonFinite);
  EXPECT_CONTAINS(e.message, "keyposes[0].keys[1].offsets[0][2] is null");
  e = error_in([](Json& j) { j["keyposes"][0]["keys"][1]["offsets"].erase(0); });
  EXPECT_CONTAINS(e.message, "keyposes[0].keys[1].offsets has 1 entries for 2 vertices");
  e = error_in([](Json& j) { j["keyposes"][1]["keys"][0]["values"] = Json::array({1}); });
  EXPECT_CONTAINS(e.message, "keyposes[1].keys[0].values has 1 entries; the set has 2 drivers");
  e = error_in([](Json& j) { j["keyposes"][0]["keys"][1]["values"] = Json::array({-45.5}); });
  EXPECT_CONTAINS(e.message,
                  "keyposes[0]: keypose set 'bulge': key 1 sits at the same driver values as key 0");
  e = error_in([](Json& j) { j["keyposes"][0]["drivers"] = Json::array(); });
  EXPECT_CONTAINS(e.message, "keyposes[0].drivers is empty");
  e = error_in([](Json& j) { j["keyposes"][0]["rest_key"] = 1; });
  EXPECT_CONTAINS(e.message, "keyposes[0].rest_key should be true or false");
  e = error_in([](Json& j) { j["attachment"]["mode"] = "soft"; });
  EXPECT_CONTAINS(e.message, "attachment.mode is 'soft'; expected rigid, smooth, skin_weights or fitted");
  e = error_in([](Json& j) { j["attachment"]["smooth_width"] = 0; });
  EXPECT_CONTAINS(e.message, "attachment.smooth_width must be > 0");
  e = error_in([](Json& j) { j["attachment"]["overrides"][0]["vertex"] = 99; });
  EXPECT_CONTAINS(e.message, "attachment.overrides[0].vertex is 99, but the cage has 26 vertices");
  e = error_in([](Json& j) { j["attachment"]["overrides"][0]["vertex"] = 5; });
  EXPECT_CONTAINS(e.message, "attachment.overrides[1] assigns cage vertex 5 a second time");
  e = error_in([](Json& j) { j["attachment"]["overrides"][0].erase("node"); });
  EXPECT_CONTAINS(e.message, "attachment.overrides[0].node is missing");
}

TEST_F(ProjectIoRigTest, InvalidKeyposesAreNotSaved) {
  Document doc = make_rig_doc();
  std::vector<KeyposeSet> sets = doc.keyposes;
  sets[0].keys[0].offsets[0].x = std::numeric_limits<float>::quiet_NaN();
  Status s = save_project(path("bad.cagewrap"), with_keyposes(doc, sets));
  ASSERT_FALSE(s.ok());
  EXPECT_CONTAINS(s.error().message,
                  "not saved: keypose set 'bulge': key 0 has a non-finite offset for cage vertex 1");
  EXPECT_FALSE(fs::exists(path("bad.cagewrap")));
}

}  // namespace
}  // namespace cagewrap
