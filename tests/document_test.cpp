// Tests for core/document/document.h and core/base/file_hash.h: loading a document from files (and every error
// naming the file), copy-on-write edits that share the big data, fresh revisions, content equality
// bit for bit, and the FNV-1a hash against its published test vectors.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "core/document/document.h"
#include "core/base/file_hash.h"
#include "tests/document_fixtures.h"

namespace cagewrap {
namespace {

using test::TempDirTest;

class DocumentTest : public TempDirTest {
 protected:
  Document load(const std::string& character, const std::string& cage) {
    auto doc = document_from_files(character, cage);
    EXPECT_TRUE(doc.ok()) << (doc.ok() ? "" : doc.error().message);
    return doc.ok() ? std::move(doc).value() : Document{};
  }
  Document tiny() {
    test::write_tiny_character(path("hero.gltf"));
    test::write_box_cage(path("cage.obj"));
    return load(path("hero.gltf"), path("cage.obj"));
  }
};

TEST(FileHash, PublishedFnv1a64Vectors) {
  EXPECT_EQ(fnv1a64(""), 0xcbf29ce484222325ull);
  EXPECT_EQ(fnv1a64("a"), 0xaf63dc4c8601ec8cull);
  EXPECT_EQ(fnv1a64("foobar"), 0x85944171f73967e8ull);
  EXPECT_EQ(format_hash(0xaf63dc4c8601ec8cull), "fnv1a64:af63dc4c8601ec8c");
  EXPECT_EQ(format_hash(0x1ull), "fnv1a64:0000000000000001");
  // continuing a hash over pieces equals hashing the whole
  EXPECT_EQ(fnv1a64("bar", fnv1a64("foo")), fnv1a64("foobar"));
}

TEST_F(DocumentTest, HashFileReadsEveryChunk) {
  std::string big(200000, 'x');  // more than one 64 KiB chunk
  big[150000] = 'y';
  test::write_text(path("big.bin"), big);
  auto h = hash_file(path("big.bin"));
  ASSERT_TRUE(h.ok());
  EXPECT_EQ(*h, format_hash(fnv1a64(big)));
  big[150000] = 'x';
  EXPECT_NE(*h, format_hash(fnv1a64(big)));
  auto missing = hash_file(path("nope.bin"));
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().code, ErrorCode::kFileNotFound);
  EXPECT_NE(missing.error().message.find("nope.bin"), std::string::npos);
}

TEST_F(DocumentTest, FromFilesLoadsCharacterCageAndHash) {
  Document doc = tiny();
  ASSERT_TRUE(doc.character);
  EXPECT_EQ(doc.character->num_vertices(), 4u);
  ASSERT_TRUE(doc.has_cage());
  EXPECT_EQ(doc.cage->num_vertices(), 26u);  // 2 x 2 quads per side of a cube
  EXPECT_EQ(doc.cage->polygons.num_faces(), 24u);
  EXPECT_EQ(doc.cage->num_elements(), 48u);
  EXPECT_EQ(doc.character_path, path("hero.gltf"));
  EXPECT_EQ(doc.character_hash, format_hash(fnv1a64(test::read_text(path("hero.gltf")))));
  EXPECT_EQ(doc.character_hash.size(), std::string("fnv1a64:").size() + 16);
  EXPECT_TRUE(same_params(doc.params, BindParams{}));
  EXPECT_TRUE(doc.set_edits.empty());
  EXPECT_TRUE(doc.project_path.empty());
  EXPECT_NE(doc.revision, 0u);
}

TEST_F(DocumentTest, FromFilesWithoutCage) {
  test::write_tiny_character(path("hero.gltf"));
  Document doc = load(path("hero.gltf"), "");
  EXPECT_FALSE(doc.has_cage());
  EXPECT_TRUE(doc.cage_positions().empty());
  EXPECT_EQ(doc.character->num_vertices(), 4u);
}

TEST_F(DocumentTest, FromFilesErrorsNameTheFile) {
  test::write_tiny_character(path("hero.gltf"));
  test::write_box_cage(path("cage.obj"));
  auto no_character = document_from_files(path("ghost.glb"), path("cage.obj"));
  ASSERT_FALSE(no_character.ok());
  EXPECT_EQ(no_character.error().code, ErrorCode::kFileNotFound);
  EXPECT_NE(no_character.error().message.find("ghost.glb"), std::string::npos) << no_character.error().message;

  auto no_cage = document_from_files(path("hero.gltf"), path("ghost.obj"));
  ASSERT_FALSE(no_cage.ok());
  EXPECT_EQ(no_cage.error().code, ErrorCode::kFileNotFound);
  EXPECT_NE(no_cage.error().message.find("ghost.obj"), std::string::npos) << no_cage.error().message;

  test::write_text(path("bad.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
  auto bad_cage = document_from_files(path("hero.gltf"), path("bad.obj"));
  ASSERT_FALSE(bad_cage.ok());
  EXPECT_NE(bad_cage.error().message.find("bad.obj"), std::string::npos) << bad_cage.error().message;

  test::write_text(path("broken.gltf"), "{ not json");
  auto bad_character = document_from_files(path("broken.gltf"), "");
  ASSERT_FALSE(bad_character.ok());
  EXPECT_NE(bad_character.error().message.find("broken.gltf"), std::string::npos) << bad_character.error().message;
}

TEST_F(DocumentTest, CopiesShareTheBigData) {
  Document a = tiny();
  Document b = a;
  EXPECT_EQ(a.character.get(), b.character.get());
  EXPECT_EQ(a.cage.get(), b.cage.get());
  EXPECT_EQ(a.character.use_count(), 2);
  EXPECT_EQ(a.revision, b.revision);
}

TEST_F(DocumentTest, WithCagePositionsIsCopyOnWrite) {
  Document a = tiny();
  std::vector<glm::vec3> rest(a.cage_positions().begin(), a.cage_positions().end());
  std::vector<glm::vec3> moved = rest;
  moved[7] += glm::vec3(0.25f, -0.5f, 1.0f);
  Document b = with_cage_positions(a, moved);

  // the original is untouched
  ASSERT_EQ(a.cage_positions().size(), rest.size());
  EXPECT_EQ(a.cage_positions()[7], rest[7]);
  // the new one has the new positions and the same topology in a new cage object
  EXPECT_EQ(b.cage_positions()[7], moved[7]);
  EXPECT_NE(a.cage.get(), b.cage.get());
  EXPECT_EQ(b.cage->polygons.face_vertices, a.cage->polygons.face_vertices);
  EXPECT_EQ(b.cage->elements, a.cage->elements);
  // everything else is shared or equal
  EXPECT_EQ(a.character.get(), b.character.get());
  EXPECT_EQ(a.character_hash, b.character_hash);
  EXPECT_NE(a.revision, b.revision);
  EXPECT_FALSE(same_content(a, b));
  EXPECT_TRUE(same_content(a, with_cage_positions(b, rest)));
}

TEST_F(DocumentTest, WithCagePositionsChecksTheCount) {
  Document a = tiny();
  std::vector<glm::vec3> too_few(3);
  EXPECT_DEATH((void)with_cage_positions(a, too_few), "one position per cage vertex");
}

TEST_F(DocumentTest, EveryEditGetsAFreshRevision) {
  Document a = tiny();
  BindParams p;
  p.epsilon = 0.2;
  std::vector<Document> docs = {a};
  docs.push_back(with_params(docs.back(), p));
  docs.push_back(with_set_edits(docs.back(), {SetEdit{1, {2}, {}}}));
  docs.push_back(with_cage(docs.back(), nullptr));
  docs.push_back(with_cage(docs.back(), a.cage));
  docs.push_back(with_character(docs.back(), a.character, "elsewhere.gltf", a.character_hash));
  docs.push_back(with_params(docs.back(), p));  // same values still count as an edit
  std::set<uint64_t> revisions;
  for (const Document& d : docs) revisions.insert(d.revision);
  EXPECT_EQ(revisions.size(), docs.size());
  EXPECT_EQ(docs[1].params.epsilon, 0.2);
  EXPECT_EQ(a.params.epsilon, BindParams{}.epsilon);
  EXPECT_EQ(docs[2].set_edits.size(), 1u);
  EXPECT_TRUE(a.set_edits.empty());
  EXPECT_FALSE(docs[3].has_cage());
  EXPECT_EQ(docs[4].cage.get(), a.cage.get());
  EXPECT_EQ(docs[5].character_path, "elsewhere.gltf");
}

TEST_F(DocumentTest, SameContentIsBitExact) {
  Document a = tiny();
  EXPECT_TRUE(same_content(a, a));
  std::vector<glm::vec3> p(a.cage_positions().begin(), a.cage_positions().end());
  p[0].x = std::nextafter(p[0].x, 10.0f);  // one ulp
  EXPECT_FALSE(same_content(a, with_cage_positions(a, p)));
  // +0 and -0 compare equal as floats but are different bits
  p = {a.cage_positions().begin(), a.cage_positions().end()};
  p[1] = glm::vec3(0.0f, p[1].y, p[1].z);
  Document plus = with_cage_positions(a, p);
  p[1].x = -0.0f;
  EXPECT_FALSE(same_content(plus, with_cage_positions(a, p)));

  BindParams q;
  q.variant = Variant::kClamped;
  EXPECT_FALSE(same_content(a, with_params(a, q)));
  EXPECT_FALSE(same_content(a, with_set_edits(a, {SetEdit{0, {}, {}}})));
  EXPECT_FALSE(same_set_edits(std::vector<SetEdit>{{0, {1}, {}}}, std::vector<SetEdit>{{0, {}, {1}}}));
  Document moved_character = with_character(a, a.character, "other/path.gltf", a.character_hash);
  EXPECT_TRUE(same_content(a, moved_character));  // paths are not content
  Document other_character = with_character(a, a.character, a.character_path, "fnv1a64:0000000000000000");
  EXPECT_FALSE(same_content(a, other_character));
}

TEST_F(DocumentTest, ByteEstimatesCoverTheArrays) {
  Document a = tiny();
  const Cage& cage = *a.cage;
  size_t arrays = cage.polygons.positions.size() * 12 + cage.polygons.face_vertices.size() * 4 +
                  cage.polygons.face_start.size() * 4 + cage.elements.size() * 12 + cage.element_face.size() * 4;
  EXPECT_GE(estimated_bytes(cage), arrays);
  EXPECT_LT(estimated_bytes(cage), 2 * arrays + 1024);
  EXPECT_GE(estimated_bytes(*a.character), a.character->num_vertices() * 12 + a.character->num_triangles() * 12);
  size_t plain = estimated_own_bytes(a);
  std::vector<SetEdit> edits(100, SetEdit{0, std::vector<uint32_t>(50, 1), {}});
  EXPECT_GE(estimated_own_bytes(with_set_edits(a, edits)), plain + 100 * 50 * 4);
}

TEST_F(DocumentTest, AttachmentAndKeyposesAreUndoableContent) {
  Document a = tiny();
  AttachmentSettings smooth;
  smooth.mode = AttachmentMode::kSmooth;
  Document b = with_attachment(a, smooth);
  EXPECT_NE(b.revision, a.revision);
  EXPECT_EQ(a.attachment, AttachmentSettings{});  // copy on write
  EXPECT_FALSE(same_content(a, b));
  EXPECT_TRUE(same_content(b, with_attachment(a, smooth)));
  EXPECT_FALSE(same_content(a, with_attachment(a, assign_vertices({}, std::vector<uint32_t>{3}, 0u))));
  KeyposeSet set;
  set.name = "bulge";
  set.drivers = {JointDriver{0, DriverKind::kRotation, {1, 0, 0}}};
  set_key(set, KeyposeKey{{120}, {2}, {{0, 1, 0}}});
  Document k = with_keyposes(a, {set});
  EXPECT_NE(k.revision, a.revision);
  EXPECT_TRUE(a.keyposes.empty());
  EXPECT_FALSE(same_content(a, k));
  KeyposeSet muted = set;
  muted.mute = true;
  EXPECT_FALSE(same_content(k, with_keyposes(a, {muted})));
  EXPECT_TRUE(same_content(k, with_keyposes(a, {set})));
  // the cage offsets are content too (they were not compared before)
  std::vector<glm::vec3> offsets(a.cage->num_vertices(), glm::vec3(0.0f));
  offsets[1].y = 0.5f;
  EXPECT_FALSE(same_content(a, with_cage_offsets(a, offsets)));
  EXPECT_TRUE(same_content(with_cage_offsets(a, offsets), with_cage_offsets(a, offsets)));
}

TEST_F(DocumentTest, ANewVertexCountDropsPerVertexData) {
  Document a = tiny();
  KeyposeSet set;
  set.name = "bulge";
  set.drivers = {JointDriver{0, DriverKind::kRotation, {1, 0, 0}}};
  set_key(set, KeyposeKey{{120}, {2}, {{0, 1, 0}}});
  a = with_keyposes(with_attachment(a, assign_vertices({}, std::vector<uint32_t>{3}, 0u)), {set});
  SimSettings sim;
  sim.enabled = true;
  sim.vertices.assign(a.cage->num_vertices(), SimVertex{false, 2.0f, 0.5f});
  a = with_sim(a, sim);
  EXPECT_FALSE(same_content(a, with_sim(a, SimSettings{})));  // the simulation is content
  // same topology (new positions): everything stays
  std::vector<glm::vec3> p(a.cage_positions().begin(), a.cage_positions().end());
  p[0].x += 0.1f;
  Document moved = with_cage_positions(a, p);
  EXPECT_EQ(moved.attachment, a.attachment);
  EXPECT_EQ(moved.keyposes, a.keyposes);
  EXPECT_EQ(moved.sim, a.sim);
  // another vertex count: the overrides, the keyed vertices and the simulation weights go, the
  // drivers, keys and simulation parameters stay
  Document other = with_cage(a, std::make_shared<const Cage>(fixtures::box_cage(2.0, 3)));
  EXPECT_TRUE(other.attachment.overrides.empty());
  ASSERT_EQ(other.keyposes.size(), 1u);
  EXPECT_EQ(other.keyposes[0].keys[0].values, std::vector<double>{120});
  EXPECT_TRUE(other.keyposes[0].keys[0].vertices.empty());
  EXPECT_TRUE(other.sim.vertices.empty());
  EXPECT_TRUE(other.sim.enabled);
}

TEST_F(DocumentTest, ByteEstimatesCountKeyposes) {
  Document a = tiny();
  size_t plain = estimated_own_bytes(a);
  KeyposeSet set;
  set.drivers = {JointDriver{0, DriverKind::kRotation, {1, 0, 0}}};
  std::vector<glm::vec3> dense(1000, glm::vec3(1.0f));
  set_key(set, make_key({10}, dense));
  set_key(set, make_key({20}, dense));
  EXPECT_GE(estimated_own_bytes(with_keyposes(a, {set})), plain + 2 * 1000 * (12 + 4));
  AttachmentSettings many = assign_vertices({}, std::vector<uint32_t>(500, 0), 0u);
  std::vector<uint32_t> all(500);
  for (uint32_t i = 0; i < 500; ++i) all[i] = i;
  many = assign_vertices({}, all, 0u);
  EXPECT_GE(estimated_own_bytes(with_attachment(a, many)), plain + 500 * 8);
}

}  // namespace
}  // namespace cagewrap
