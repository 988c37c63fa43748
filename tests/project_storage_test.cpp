// Tests for how a project stores its character: core/base/base64.h (RFC 4648 vectors, every length,
// strict decoding), load_character_bytes (core/io/gltf_loader.h), and core/document/character_embedding.h with
// the project file (core/document/project_io.h): an embedded project opens with no other file, is written as
// version 3 (a project that embeds nothing stays version 2 for older builds), a damaged embedding
// is named, a character that refers to other files cannot be embedded, and taking it out again
// writes the same bytes.
#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include <nlohmann/json.hpp>

#include "core/base/base64.h"
#include "core/document/character_embedding.h"
#include "core/base/file_hash.h"
#include "core/io/gltf_loader.h"
#include "core/document/project_io.h"
#include "tests/document_fixtures.h"
#include "tests/expect_error.h"

namespace cagewrap {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;
using test::read_text;
using test::write_text;

TEST(Base64, Rfc4648Vectors) {
  const std::pair<const char*, const char*> vectors[] = {{"", ""},         {"f", "Zg=="},         {"fo", "Zm8="},
                                                         {"foo", "Zm9v"},  {"foob", "Zm9vYg=="},  {"fooba", "Zm9vYmE="},
                                                         {"foobar", "Zm9vYmFy"}};
  for (const auto& [plain, encoded] : vectors) {
    EXPECT_EQ(base64_encode(plain), encoded);
    auto back = base64_decode(encoded, "v");
    ASSERT_TRUE(back.ok()) << encoded << ": " << back.error().message;
    EXPECT_EQ(*back, plain);
  }
}

TEST(Base64, EveryByteAndLengthRoundTrips) {
  std::mt19937 rng(7);
  for (size_t n = 0; n < 300; ++n) {
    std::string bytes(n, '\0');
    for (auto& c : bytes) c = static_cast<char>(rng() & 255);
    if (n == 256)
      for (size_t i = 0; i < n; ++i) bytes[i] = static_cast<char>(i);  // every byte value once
    const std::string text = base64_encode(bytes);
    EXPECT_EQ(text.size(), (n + 2) / 3 * 4);
    auto back = base64_decode(text, "x");
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(*back, bytes) << "length " << n;
  }
}

TEST(Base64, MalformedTextIsNamed) {
  EXPECT_TRUE(Fails(base64_decode("Zm9", "the data"), ErrorCode::kParse, {"the data", "not a multiple of 4"}));
  EXPECT_TRUE(Fails(base64_decode("Zm9v!m8=", "d"), ErrorCode::kParse, {"character 4 is '!'"}));
  EXPECT_TRUE(Fails(base64_decode("Zg==Zm8=", "d"), ErrorCode::kParse, {"character 2 is '='"}));
  EXPECT_TRUE(Fails(base64_decode("Z===", "d"), ErrorCode::kParse, {"character 1 is '='"}));
  EXPECT_TRUE(Fails(base64_decode("Zm 9", "d"), ErrorCode::kParse, {"character 2 is ' '"}));
}

class ProjectStorageTest : public test::TempDirTest {
 protected:
  Document tiny_doc(const std::string& character = "hero.gltf") {
    if (!fs::exists(path(character))) test::write_tiny_character(path(character));
    test::write_box_cage(path("cage.obj"));
    auto doc = document_from_files(path(character), path("cage.obj"));
    EXPECT_TRUE(doc.ok()) << (doc.ok() ? "" : doc.error().message);
    return with_set_edits(*doc, {SetEdit{2, {0, 7}, {}}});
  }
};

TEST_F(ProjectStorageTest, CharacterBytesLoadLikeTheFile) {
  test::write_tiny_character(path("hero.gltf"));  // data: URI buffers
  auto from_file = load_character(path("hero.gltf"));
  auto from_bytes = load_character_bytes(read_text(path("hero.gltf")), "embedded hero");
  ASSERT_TRUE(from_file.ok() && from_bytes.ok()) << (from_bytes.ok() ? "" : from_bytes.error().message);
  ASSERT_EQ(from_bytes->primitives.size(), from_file->primitives.size());
  EXPECT_EQ(from_bytes->primitives[0].positions, from_file->primitives[0].positions);
  EXPECT_EQ(from_bytes->source, "embedded hero");
  EXPECT_TRUE(Fails(load_character_bytes("", "empty thing"), ErrorCode::kEmpty, {"empty thing"}));
  EXPECT_TRUE(Fails(load_character_bytes("{not json", "junk"), ErrorCode::kParse, {"junk", "not a usable glTF"}));
}

TEST_F(ProjectStorageTest, EmbeddedProjectOpensWithNoOtherFile) {
  Document doc = tiny_doc();
  auto embedded = embed_character(doc);
  ASSERT_TRUE(embedded.ok()) << embedded.error().message;
  EXPECT_EQ(*embedded->embedded_character, read_text(path("hero.gltf")));
  EXPECT_FALSE(same_content(doc, *embedded)) << "embedding is a change to save";
  ASSERT_TRUE(save_project(path("p.cagewrap"), *embedded).ok());
  Json j = Json::parse(read_text(path("p.cagewrap")));
  EXPECT_EQ(j["version"], 3) << "older builds must refuse a file they would open without its character";
  EXPECT_EQ(j["character"]["path"], "hero.gltf") << "where it came from";
  EXPECT_EQ(j["character"]["embedded"], base64_encode(read_text(path("hero.gltf"))));

  // the project alone, in another folder, with the character file gone
  fs::create_directories(dir_ / "elsewhere");
  fs::rename(path("p.cagewrap"), path("elsewhere/p.cagewrap"));
  fs::remove(path("hero.gltf"));
  auto back = load_project(path("elsewhere/p.cagewrap"));
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_TRUE(back->warnings.empty()) << back->warnings[0];
  const Document& d = back->document;
  ASSERT_TRUE(d.embedded_character);
  EXPECT_TRUE(same_content(*embedded, d));
  EXPECT_EQ(d.character->primitives[0].positions, doc.character->primitives[0].positions);
  EXPECT_EQ(d.character->source, "hero.gltf (embedded)");
  EXPECT_EQ(d.character_hash, doc.character_hash);

  // saved again: the same bytes
  const std::string first = read_text(path("elsewhere/p.cagewrap"));
  ASSERT_TRUE(save_project(path("elsewhere/p.cagewrap"), d).ok());
  EXPECT_EQ(read_text(path("elsewhere/p.cagewrap")), first);
}

TEST_F(ProjectStorageTest, GlbEmbedsToo) {
  test::GltfBuilder b;
  int pos = b.add_floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", true);
  b.doc["meshes"].push_back({{"primitives", {{{"attributes", {{"POSITION", pos}}}}}}});
  b.set_scene({b.add_node({{"mesh", 0}})});
  b.write_glb(path("tri.glb"));
  Document doc = tiny_doc("tri.glb");
  auto embedded = embed_character(doc);
  ASSERT_TRUE(embedded.ok()) << embedded.error().message;
  ASSERT_TRUE(save_project(path("p.cagewrap"), *embedded).ok());
  fs::remove(path("tri.glb"));
  auto back = load_project(path("p.cagewrap"));
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(back->document.character->num_vertices(), 3u);
}

TEST_F(ProjectStorageTest, ProjectsThatEmbedNothingStayVersion2) {
  ASSERT_TRUE(save_project(path("p.cagewrap"), tiny_doc()).ok());
  EXPECT_EQ(Json::parse(read_text(path("p.cagewrap")))["version"], 2);
  EXPECT_FALSE(Json::parse(read_text(path("p.cagewrap")))["character"].contains("embedded"));
}

TEST_F(ProjectStorageTest, DamagedEmbeddingIsNamed) {
  auto embedded = embed_character(tiny_doc());
  ASSERT_TRUE(embedded.ok());
  ASSERT_TRUE(save_project(path("p.cagewrap"), *embedded).ok());
  const Json good = Json::parse(read_text(path("p.cagewrap")));
  auto load_with = [&](auto edit) {
    Json j = good;
    edit(j);
    write_text(path("bad.cagewrap"), j.dump(1));
    return load_project(path("bad.cagewrap"));
  };
  // one character changed: still base64, other bytes
  auto changed = load_with([](Json& j) {
    std::string e = j["character"]["embedded"];
    e[40] = e[40] == 'A' ? 'B' : 'A';
    j["character"]["embedded"] = e;
  });
  EXPECT_TRUE(Fails(changed, ErrorCode::kParse,
                    {path("bad.cagewrap"), "character.embedded does not match character.hash", "damaged"}));
  auto cut = load_with([](Json& j) { j["character"]["embedded"] = j["character"]["embedded"].get<std::string>().substr(0, 101); });
  EXPECT_TRUE(Fails(cut, ErrorCode::kParse, {path("bad.cagewrap"), "character.embedded is not base64", "multiple of 4"}));
  auto number = load_with([](Json& j) { j["character"]["embedded"] = 12; });
  EXPECT_TRUE(Fails(number, ErrorCode::kParse, {"character.embedded"}));
  // not a glTF at all, with a matching hash: the loader's message, naming the project
  auto junk = load_with([](Json& j) {
    j["character"]["embedded"] = base64_encode("junk!");
    j["character"]["hash"] = format_hash(fnv1a64("junk!"));
  });
  EXPECT_TRUE(Fails(junk, ErrorCode::kParse, {path("bad.cagewrap"), "the embedded character hero.gltf", "not a usable glTF"}));
}

TEST_F(ProjectStorageTest, CharacterReferringToOtherFilesCannotBeEmbedded) {
  test::GltfBuilder b;
  int pos = b.add_floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", true);
  b.doc["meshes"].push_back({{"primitives", {{{"attributes", {{"POSITION", pos}}}}}}});
  b.set_scene({b.add_node({{"mesh", 0}})});
  b.write_external(path("split.gltf"), "split.bin");
  Document doc = tiny_doc("split.gltf");
  auto e = embed_character(doc);
  EXPECT_TRUE(Fails(e, ErrorCode::kFileUnreadable,
                    {"cannot embed the character", path("split.gltf"), "buffer 0", "'split.bin'", "must hold all its buffers"}));
}

TEST_F(ProjectStorageTest, ACharacterChangedSinceLoadingIsNotEmbedded) {
  Document doc = tiny_doc();
  test::write_tiny_character(path("hero.gltf"), 0.5f);  // re-exported under the editor
  EXPECT_TRUE(Fails(embed_character(doc), ErrorCode::kInvalidArgument,
                    {path("hero.gltf"), "changed since it was loaded"}));
  fs::remove(path("hero.gltf"));
  EXPECT_TRUE(Fails(embed_character(doc), ErrorCode::kFileNotFound, {path("hero.gltf")}));
}

TEST_F(ProjectStorageTest, TakingTheCharacterOutWritesTheSameBytes) {
  const std::string original = (test::write_tiny_character(path("hero.gltf")), read_text(path("hero.gltf")));
  auto embedded = embed_character(tiny_doc());
  ASSERT_TRUE(embedded.ok());
  Document doc = *embedded;
  doc.project_path = path("p.cagewrap");
  EXPECT_TRUE(Fails(unembed_character(doc, path("p.cagewrap"), true), ErrorCode::kInvalidArgument, {"is the project file"}));
  write_text(path("taken.glb"), "something else");
  EXPECT_TRUE(Fails(unembed_character(doc, path("taken.glb"), false), ErrorCode::kInvalidArgument,
                    {path("taken.glb"), "already exists"}));
  EXPECT_EQ(read_text(path("taken.glb")), "something else");
  auto out = unembed_character(doc, path("out/hero2.gltf"), false);
  EXPECT_FALSE(out.ok()) << "a missing folder is an error naming the file";
  auto out2 = unembed_character(doc, path("hero2.gltf"), false);
  ASSERT_TRUE(out2.ok()) << out2.error().message;
  EXPECT_EQ(read_text(path("hero2.gltf")), original);
  EXPECT_FALSE(out2->embedded_character);
  EXPECT_EQ(out2->character_path, path("hero2.gltf"));
  // the same bytes already there: fine without `replace`; replacing another file needs it
  EXPECT_TRUE(unembed_character(doc, path("hero.gltf"), false).ok());
  ASSERT_TRUE(unembed_character(doc, path("taken.glb"), true).ok());
  EXPECT_EQ(read_text(path("taken.glb")), original);
  ASSERT_TRUE(save_project(path("p.cagewrap"), *out2).ok());
  auto back = load_project(path("p.cagewrap"));
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_FALSE(back->document.embedded_character);
  EXPECT_EQ(Json::parse(read_text(path("p.cagewrap")))["character"]["path"], "hero2.gltf");
  EXPECT_TRUE(Fails(unembed_character(*out2, path("x.gltf"), false), ErrorCode::kInvalidArgument, {"not embedded"}));
}

}  // namespace
}  // namespace cagewrap
