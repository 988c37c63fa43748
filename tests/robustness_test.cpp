// Bad input that the per-module tests do not already cover (docs/robustness.md lists every case and
// the test for it): empty, truncated and wrongly tagged GLB files, huge declared counts, skins naming
// nodes that do not exist, a skin with no vertices, a project file cut short at every length, a cage
// far from the skin. In every case: no crash, no hang, an error naming the file and what is wrong.
// Also the kill test: a project being saved is killed (SIGKILL) at random moments, and the file on
// disk is always a complete, loadable project.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <thread>

#include "core/io/gltf_loader.h"
#include "core/geometry/mesh_io.h"
#include "app/workspace/autosave.h"
#include "core/document/project_io.h"
#include "core/deform/registration.h"
#include "tests/document_fixtures.h"
#include "tests/expect_error.h"
#include "tests/fuzz/seed_fixtures.h"

namespace cagewrap {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::GltfBuilder;
using test::read_text;
using test::write_text;

using fuzz::tet_builder;  // the tetrahedron of test::write_tiny_character, as a builder

// The load fails, and the message starts with (or at least names) the file.
template <class T>
::testing::AssertionResult FailsNamingFile(const Result<T>& r, const std::string& path) {
  if (r.ok()) return ::testing::AssertionFailure() << path << " loaded";
  if (r.error().message.find(path) == std::string::npos)
    return ::testing::AssertionFailure() << "message does not name " << path << ": " << r.error().message;
  return ::testing::AssertionSuccess();
}

class Robustness : public test::TempDirTest {};

TEST_F(Robustness, EmptyGltfAndGlbFilesAreNamed) {
  for (const char* name : {"empty.glb", "empty.gltf"}) {
    write_text(path(name), "");
    auto r = load_character(path(name));
    EXPECT_TRUE(FailsNamingFile(r, path(name)));
  }
}

TEST_F(Robustness, GlbCutAtEveryLengthFailsNamingTheFile) {
  tet_builder().write_glb(path("whole.glb"));
  const std::string whole = read_text(path("whole.glb"));
  ASSERT_TRUE(load_character(path("whole.glb")).ok());
  for (size_t n = 0; n < whole.size(); ++n) {
    write_text(path("cut.glb"), whole.substr(0, n));
    auto r = load_character(path("cut.glb"));
    EXPECT_TRUE(FailsNamingFile(r, path("cut.glb"))) << "cut at byte " << n << " of " << whole.size();
  }
}

TEST_F(Robustness, GlbWithAWrongMagicOrLengthIsNamed) {
  tet_builder().write_glb(path("whole.glb"));
  std::string bytes = read_text(path("whole.glb"));
  std::string magic = bytes;
  magic[0] = 'X';
  write_text(path("magic.glb"), magic);
  EXPECT_TRUE(FailsNamingFile(load_character(path("magic.glb")), path("magic.glb")));
  std::string length = bytes;
  length[8] = char(0xff), length[9] = char(0xff), length[10] = char(0xff), length[11] = char(0x7f);  // total 2 GB
  write_text(path("length.glb"), length);
  EXPECT_TRUE(FailsNamingFile(load_character(path("length.glb")), path("length.glb")));
  std::string chunk = bytes;
  chunk[12] = char(0xff), chunk[13] = char(0xff), chunk[14] = char(0xff), chunk[15] = char(0x7f);  // JSON chunk 2 GB
  write_text(path("chunk.glb"), chunk);
  EXPECT_TRUE(FailsNamingFile(load_character(path("chunk.glb")), path("chunk.glb")));
}

TEST_F(Robustness, HugeDeclaredCountsFailWithoutAllocating) {
  for (double count : {4294967295.0, 1e12, 2147483648.0}) {
    GltfBuilder b = tet_builder();
    b.doc["accessors"][0]["count"] = count;
    b.write_glb(path("huge.glb"));
    auto r = load_character(path("huge.glb"));
    EXPECT_TRUE(FailsNamingFile(r, path("huge.glb"))) << count;
  }
  {
    GltfBuilder b = tet_builder();
    b.doc["bufferViews"][0]["byteLength"] = 4294967295.0;
    b.write_glb(path("view.glb"));
    EXPECT_TRUE(FailsNamingFile(load_character(path("view.glb")), path("view.glb")));
  }
  // OFF and PLY headers promising a billion vertices
  write_text(path("huge.off"), "OFF\n1000000000 1000000000 0\n0 0 0\n");
  EXPECT_TRUE(FailsNamingFile(Result<Character>(Error{ErrorCode::kParse, load_mesh(path("huge.off")).ok()
                                                                            ? std::string("loaded")
                                                                            : load_mesh(path("huge.off")).error().message}),
                              path("huge.off")));
  write_text(path("huge.ply"),
             "ply\nformat ascii 1.0\nelement vertex 1000000000\nproperty float x\nproperty float y\nproperty float z\n"
             "end_header\n0 0 0\n");
  auto ply = load_mesh(path("huge.ply"));
  ASSERT_FALSE(ply.ok());
  EXPECT_NE(ply.error().message.find(path("huge.ply")), std::string::npos) << ply.error().message;
  write_text(path("huge.stl"), std::string(80, ' ') + std::string("\xff\xff\xff\x7f", 4));
  auto stl = load_mesh(path("huge.stl"));
  ASSERT_FALSE(stl.ok());
  EXPECT_NE(stl.error().message.find(path("huge.stl")), std::string::npos) << stl.error().message;
}

TEST_F(Robustness, SkinNamingMissingNodesIsNamed) {
  GltfBuilder b = tet_builder();
  b.doc["skins"] = json::array({{{"name", "rig"}, {"joints", {0, 42}}}});
  b.doc["nodes"][0]["skin"] = 0;
  b.write_embedded(path("skin.gltf"));
  auto r = load_character(path("skin.gltf"));
  ASSERT_TRUE(FailsNamingFile(r, path("skin.gltf")));
  EXPECT_NE(r.error().message.find("skin 0"), std::string::npos) << r.error().message;
  EXPECT_NE(r.error().message.find("42"), std::string::npos) << r.error().message;
  b.doc["skins"][0]["joints"] = json::array({0});
  b.doc["skins"][0]["skeleton"] = 17;
  b.write_embedded(path("root.gltf"));
  auto root = load_character(path("root.gltf"));
  if (!root.ok()) { EXPECT_NE(root.error().message.find(path("root.gltf")), std::string::npos) << root.error().message; }
}

TEST_F(Robustness, SkinWithNoVerticesIsNamed) {
  // a glTF whose only primitive has zero positions, and one with no meshes at all
  GltfBuilder b = tet_builder();
  b.doc["accessors"][0]["count"] = 0;
  b.doc["meshes"][0]["primitives"][0].erase("indices");
  b.write_embedded(path("novertex.gltf"));
  EXPECT_TRUE(FailsNamingFile(document_from_files(path("novertex.gltf"), ""), path("novertex.gltf")));
  GltfBuilder none;
  none.set_scene({none.add_node({{"name", "empty"}})});
  none.write_embedded(path("nomesh.gltf"));
  EXPECT_TRUE(FailsNamingFile(document_from_files(path("nomesh.gltf"), ""), path("nomesh.gltf")));
  // an OBJ skin with faces but no vertices
  write_text(path("noverts.obj"), "# nothing\nf 1 2 3\n");
  auto m = load_mesh(path("noverts.obj"));
  ASSERT_FALSE(m.ok());
  EXPECT_NE(m.error().message.find(path("noverts.obj")), std::string::npos) << m.error().message;
}

TEST_F(Robustness, ProjectCutShortAtEveryLengthFailsNamingTheFile) {
  test::write_tiny_character(path("hero.gltf"));
  test::write_box_cage(path("cage.obj"));
  auto doc = document_from_files(path("hero.gltf"), path("cage.obj"));
  ASSERT_TRUE(doc.ok()) << doc.error().message;
  ASSERT_TRUE(save_project(path("whole.cagewrap"), *doc).ok());
  const std::string whole = read_text(path("whole.cagewrap"));
  ASSERT_GT(whole.size(), 100u);
  size_t step = std::max<size_t>(1, whole.size() / 400);
  for (size_t n = 0; n + 1 < whole.size(); n += step) {
    // the final newline alone may go; anything more is a broken file
    if (whole.find_first_not_of(" \n\r\t", n) == std::string::npos) continue;
    write_text(path("cut.cagewrap"), whole.substr(0, n));
    auto r = load_project(path("cut.cagewrap"));
    ASSERT_FALSE(r.ok()) << "cut at byte " << n << " of " << whole.size() << " loaded";
    EXPECT_NE(r.error().message.find(path("cut.cagewrap")), std::string::npos) << r.error().message;
  }
}

TEST(RobustnessBind, CageFarFromTheSkinStillBindsEveryPoint) {
  // The skin lies 1000 units away from the cage: every point follows its nearest element; weights
  // are finite and sum to one. Not an error (the artist may be about to move the cage).
  Cage cage = fixtures::box_cage(1.0, 2);
  std::vector<glm::vec3> skin = {{1000, 0, 0}, {1000, 1, 0}, {1000, 0, 1}, {-2000, 5, 3}};
  auto b = bind_skin(skin, cage, cage.polygons.positions, BindParams{});
  ASSERT_TRUE(b.ok()) << b.error().message;
  ASSERT_EQ(b->num_points, skin.size());
  for (uint32_t p = 0; p < skin.size(); ++p) {
    double sum = 0;
    for (uint32_t k = b->offsets[p]; k < b->offsets[p + 1]; ++k) {
      ASSERT_TRUE(std::isfinite(b->weights[k]));
      sum += b->weights[k];
    }
    EXPECT_NEAR(sum, 1.0, 1e-6) << "point " << p;
  }
}

// ---------------------------------------------------------------------------------------- kill test

#ifdef CAGEWRAP_SAVE_LOOP
// Runs `cagewrap_save_loop DIR [mode]`, kills it with SIGKILL after `delay_us` microseconds and
// reaps it; true when the kill found it still running (not exited on its own).
bool run_save_loop_and_kill(const std::string& dir, const char* mode, int delay_us) {
  const std::string ready = dir + "/loop.ready";  // written by the loop after its first write
  std::filesystem::remove(ready);
  pid_t child = fork();
  EXPECT_GE(child, 0);
  if (child == 0) {
    execl(CAGEWRAP_SAVE_LOOP, CAGEWRAP_SAVE_LOOP, dir.c_str(), mode, static_cast<char*>(nullptr));
    _exit(127);
  }
  // the delay counts from the end of the first write (at most 60 s of waiting for it)
  for (int i = 0; i < 6000 && !std::filesystem::exists(ready); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  std::this_thread::sleep_for(std::chrono::microseconds(delay_us));
  kill(child, SIGKILL);
  int status = 0;
  EXPECT_EQ(waitpid(child, &status, 0), child);
  EXPECT_FALSE(WIFEXITED(status) && WEXITSTATUS(status) == 127) << "could not run " << CAGEWRAP_SAVE_LOOP;
  return WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL;
}

// `cagewrap_save_loop DIR` saves DIR/big.cagewrap over and over (two different cages in turn).
// Killed with SIGKILL after a random delay, 32 times: the file is always a complete project.
TEST_F(Robustness, KilledWhileSavingLeavesTheLastProjectIntact) {
  test::write_tiny_character(path("hero.gltf"));
  test::write_box_cage(path("cage_a.obj"), 2.0, 40);
  test::write_box_cage(path("cage_b.obj"), 3.0, 40);
  const std::string project = path("big.cagewrap");
  {
    auto doc = document_from_files(path("hero.gltf"), path("cage_a.obj"));
    ASSERT_TRUE(doc.ok()) << doc.error().message;
    ASSERT_TRUE(save_project(project, *doc).ok());
  }
  const auto first_size = fs::file_size(project);
  std::mt19937 rng(20261122);
  std::uniform_int_distribution<int> delay_us(0, 400000);
  int killed_mid_run = 0;
  for (int round = 0; round < 32; ++round) {
    killed_mid_run += run_save_loop_and_kill(dir_.string(), nullptr, delay_us(rng));
    auto r = load_project(project);
    ASSERT_TRUE(r.ok()) << "round " << round << ": " << r.error().message;
    ASSERT_TRUE(r->document.cage);
    EXPECT_EQ(r->document.cage->num_vertices(), fixtures::box_cage(2.0, 40).num_vertices()) << "round " << round;
  }
  EXPECT_GT(first_size, 100000u) << "the project should be big enough to take a while to write";
  EXPECT_GE(killed_mid_run, 30);
  // a temporary file left by a killed save does not stop the next one
  auto doc = document_from_files(path("hero.gltf"), path("cage_a.obj"));
  ASSERT_TRUE(doc.ok());
  EXPECT_TRUE(save_project(project, *doc).ok());
  EXPECT_TRUE(load_project(project).ok());
}

// The editor's autosave under the same treatment: `cagewrap_save_loop DIR --recovery` autosaves the
// recovery file DIR/config/recovery/loop.cagewrap over and over (two documents in turn), killed
// with SIGKILL after a random delay, 32 times: the recovery file the next start finds always loads
// (the previous complete autosave, or the new one), and the start-up scan offers it.
TEST_F(Robustness, KilledWhileAutosavingLeavesTheLastRecoveryFileIntact) {
  test::write_tiny_character(path("hero.gltf"));
  test::write_box_cage(path("cage_a.obj"), 2.0, 40);
  test::write_box_cage(path("cage_b.obj"), 3.0, 40);
  const std::string recovery = path("config/recovery/loop.cagewrap");
  const size_t vertices = fixtures::box_cage(2.0, 40).num_vertices();
  std::mt19937 rng(20261123);
  std::uniform_int_distribution<int> delay_us(0, 400000);
  int killed_mid_run = 0, killed_mid_write = 0, found = 0, rounds = 0;
  std::set<float> seen_sizes;  // which document each round left (cage a or b, told apart by size)
#if defined(CAGEWRAP_ASAN)
  constexpr int kWantMidWrite = 0;
#else
  constexpr int kWantMidWrite = 2;
#endif
  // 32 rounds, and more (up to 128) until at least two kills landed inside a write: how many do in
  // 32 depends on the machine's load (8 here when quiet, 1 in a loaded CI run), and the test is about
  // what such a kill leaves, so it keeps killing until it has seen it, instead of hoping to
  for (int round = 0; round < 128 && (round < 32 || killed_mid_write < kWantMidWrite); ++round) {
    ++rounds;
    killed_mid_run += run_save_loop_and_kill(dir_.string(), "--recovery", delay_us(rng));
    killed_mid_write += fs::exists(recovery + ".tmp");  // the kill interrupted a write
    if (!fs::exists(recovery)) continue;  // not expected: the kill comes after the first autosave
    ++found;
    RecoveryScan scan = list_recovery_files(path("config/recovery"), /*remove_stale=*/false);
    ASSERT_EQ(scan.offer.size(), 1u) << "round " << round;
    EXPECT_EQ(scan.offer[0].path, recovery);
    auto r = load_project(recovery);
    ASSERT_TRUE(r.ok()) << "round " << round << ": " << r.error().message;
    ASSERT_TRUE(r->recovery) << "round " << round;
    ASSERT_TRUE(r->document.cage);
    EXPECT_EQ(r->document.cage->num_vertices(), vertices) << "round " << round;
    seen_sizes.insert(r->document.cage->polygons.positions[0].x);
  }
  EXPECT_GE(found, rounds - 2);
  EXPECT_GE(killed_mid_run, rounds - 2);
  EXPECT_EQ(seen_sizes.size(), 2u) << "both documents were autosaved in turn";
  RecordProperty("rounds", rounds);
#if defined(CAGEWRAP_ASAN)
  // Under AddressSanitizer building the file in memory is several times slower and the write
  // itself is not, so few kills (none in 32, measured) land inside the write; the main build's run
  // of this test asserts that they do. Every round's file was checked above all the same.
#else
  EXPECT_GE(killed_mid_write, kWantMidWrite)
      << "some kills must land in the middle of a write (" << rounds << " rounds)";
#endif
  RecordProperty("killed_mid_write", killed_mid_write);
}
#endif

}  // namespace
}  // namespace cagewrap
