// File > Export driven in-process on the demo character (app/workspace/workspace_export.cpp, issue 20):
// the export runs in the background with its own bind, writes a baked-skin .glb that loads again with
// one corrective per frame, reports to the log, refuses a bad path by name while the document carries
// on, stops on Cancel leaving no file, and names what it cannot read in an export line. The Export
// window only draws this (tests/editor_export_gui_test.cpp keeps the window's Browse and a script's end).
#include <chrono>
#include <fstream>
#include <iterator>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "tests/workspace_fixtures.h"
#include "core/base/json_reader.h"
#include "core/io/gltf_loader.h"
#include "tests/gltf_validator.h"

namespace cagewrap::app {
namespace {

namespace fs = std::filesystem;

class WorkspaceExportTest : public DemoWorkspaceTest {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / "cagewrap_workspace_export_test" / ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    DemoWorkspaceTest::SetUp();
  }
  void finish_export() { poll_while([this] { return ws.exporting(); }); }
  std::string log_text() const {
    std::string out;
    for (const auto& l : ws.log_lines()) out += l.text + "\n";
    return out;
  }
  fs::path dir_;
};

TEST_F(WorkspaceExportTest, BakedSkinLoadsAgainWithCompressedCorrectives) {
  const fs::path glb = dir_ / "demo walk.glb";  // a space in the name, as people write them
  ASSERT_TRUE(ws.run("export glb baked-skin 4 walk " + glb.string()));
  EXPECT_TRUE(ws.exporting());
  EXPECT_EQ(ws.scene()->history().undo_steps(), 0u) << "an export never changes the document";
  finish_export();
  ASSERT_TRUE(errors.empty()) << errors.front();
  ASSERT_TRUE(fs::exists(glb)) << log_text();
  const std::string log = log_text();
  // compressed correctives (the default): the walk's first and last frames are the same pose, so its 5 frames'
  // residuals have 4 components, all kept
  EXPECT_NE(log.find("exported baked-skin: 5 frames, 4 morph targets, wrote " + glb.string()), std::string::npos) << log;
  EXPECT_NE(log.find("correctives: 4 of the residuals' 4 components (at most 16)"), std::string::npos) << log;
  EXPECT_NE(log.find("error at frames, skeleton only:"), std::string::npos) << log;
  ASSERT_TRUE(ws.export_state().report.has_value());
  EXPECT_EQ(ws.export_state().failures, 0);

  auto loaded = load_character(glb.string());
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  ASSERT_EQ(loaded->clips.size(), 1u);
  EXPECT_EQ(loaded->clips[0].name, "walk");
  ASSERT_FALSE(loaded->primitives.empty());
  for (const Primitive& p : loaded->primitives) {
    EXPECT_GE(p.skin, 0) << "fitted weights";
    EXPECT_EQ(p.morph_targets.size(), 4u) << "the residuals' components (walk, 1 s at 4 fps)";
  }
  ASSERT_GT(loaded->clips[0].samplers.size(), 0u);
  if (test::node_available()) {
    std::string report;
    const int rc = test::run_gltf_validator({glb.string()}, (dir_ / "validator.txt").string(), report);
    ASSERT_NE(rc, 2) << "gltf-validator is not installed: run scripts/setup.sh\n" << report;
    EXPECT_EQ(rc, 0) << report;
  }
  // one target per frame, asked for by export_correctives (the Export window has the same field); a bad
  // request is refused by name and changes nothing
  ASSERT_TRUE(ws.run("export_correctives frames"));
  const fs::path per_frame = dir_ / "per frame.glb";
  ASSERT_TRUE(ws.run("export glb baked-skin 4 walk " + per_frame.string()));
  finish_export();
  EXPECT_NE(log_text().find("exported baked-skin: 5 frames, 5 morph targets, wrote " + per_frame.string()), std::string::npos);
  EXPECT_NE(log_text().find("correctives: one per frame (exact at the frames)"), std::string::npos);
  ws.run("export_correctives 5000");
  ws.run("export_correctives frames 0.001");
  EXPECT_NE(log_text().find("export_correctives N|frames|default [MAX_ERROR] (N from 1 to 4096"), std::string::npos) << log_text();
  EXPECT_EQ(ws.export_correctives.max_targets, 0) << "refused requests change nothing";
  EXPECT_EQ(ws.export_correctives.max_error, 0.0);
  ASSERT_TRUE(ws.run("export_correctives 8 0.002"));
  EXPECT_EQ(ws.export_correctives.max_targets, 8);
  EXPECT_EQ(ws.export_correctives.max_error, 0.002);
}

// The options the Export window's check boxes set, from a script: quantized (KHR_mesh_quantization),
// reordered for the GPU, pose-driven correctives holding a clip out; the file says so, loads again and its
// report says so.
TEST_F(WorkspaceExportTest, QuantizedReorderedAndPoseDrivenExportFromAScript) {
  ws.run("export_pose_driven off walk");
  EXPECT_NE(log_text().find("export_pose_driven on|off [CLIP]"), std::string::npos) << log_text();
  ASSERT_TRUE(ws.run("export_pose_driven on arm_raise"));
  ws.run("export_quantize maybe");
  EXPECT_NE(log_text().find("export_quantize on|off"), std::string::npos) << log_text();
  EXPECT_FALSE(ws.export_correctives.quantize);
  ASSERT_TRUE(ws.run("export_quantize on"));
  ASSERT_TRUE(ws.run("export_optimize on"));
  const fs::path glb = dir_ / "q.glb";
  ASSERT_TRUE(ws.run("export glb baked-skin 4 walk,arm_raise " + glb.string()));
  finish_export();
  ASSERT_TRUE(fs::exists(glb)) << log_text();
  EXPECT_NE(log_text().find("quantized (KHR_mesh_quantization): positions in steps of"), std::string::npos) << log_text();
  EXPECT_NE(log_text().find("clip 'arm_raise' (9 frames, held out of the fit) at frames"), std::string::npos) << log_text();
  EXPECT_NE(log_text().find("pose-driven targets"), std::string::npos) << log_text();
  EXPECT_NE(log_text().find("GPU order: vertex cache misses per triangle"), std::string::npos) << log_text();
  auto loaded = load_character(glb.string());
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  ASSERT_FALSE(loaded->primitives.empty());
  EXPECT_GT(loaded->primitives[0].morph_targets.size(), 0u);
  std::ifstream in(glb, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(bytes.find(R"("extensionsRequired":["KHR_mesh_quantization"])"), std::string::npos);
  EXPECT_NE(bytes.find("_CAGEWRAP_SOURCE_INDEX"), std::string::npos);
  EXPECT_NE(bytes.find(R"("cagewrap_pose_correctives":)"), std::string::npos);
}

TEST_F(WorkspaceExportTest, ABadPathIsRefusedByNameAndTheNextExportRuns) {
  const fs::path bad = dir_ / "missing" / "x.glb", json = dir_ / "rig.json";
  EXPECT_TRUE(ws.run("export glb cage 4 all " + bad.string()));
  EXPECT_FALSE(ws.exporting());
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_NE(errors[0].find("export: " + bad.string() + ": the folder " + bad.parent_path().string() + " does not exist"), std::string::npos)
      << errors[0];
  EXPECT_EQ(ws.export_state().failures, 1);
  EXPECT_FALSE(fs::exists(bad.parent_path()));
  // the document is still there: its rig exports as JSON afterwards
  ASSERT_TRUE(ws.run("export json - 30 all " + json.string()));
  finish_export();
  ASSERT_TRUE(fs::exists(json)) << log_text();
  EXPECT_NE(log_text().find("exported rig as JSON"), std::string::npos) << log_text();
  auto j = read_json_file(json.string());
  ASSERT_TRUE(j.ok()) << j.error().message;
  EXPECT_EQ((*j)["format"], "cagewrap-rig");
  EXPECT_GT((*j)["cage"]["positions"].size(), 100u);
  EXPECT_EQ((*j)["attachment"]["mode"], "fitted");  // the default a new document gets
  EXPECT_EQ(ws.export_state().failures, 1);
}

// A long bake (both clips at 60 fps): a second export is refused while it runs; Cancel stops it and
// leaves no file.
TEST_F(WorkspaceExportTest, CancelStopsALongBakeAndLeavesNoFile) {
  const fs::path glb = dir_ / "long.glb", other = dir_ / "other.json";
  ASSERT_TRUE(ws.run("export_nowait glb baked-skin 60 all " + glb.string()));
  ASSERT_TRUE(ws.exporting());
  ws.run("export json - 30 all " + other.string());
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_NE(errors[0].find("an export is running already"), std::string::npos) << errors[0];
  // let it get going, then cancel
  for (int i = 0; i < 500 && ws.exporting() && ws.export_state().job->progress() <= 0.0; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ASSERT_TRUE(ws.exporting()) << "the long bake ended before it could be cancelled";
  ws.run("export_cancel");
  finish_export();
  EXPECT_EQ(ws.export_state().outcome, "cancelled; nothing was written");
  EXPECT_NE(log_text().find("export cancelled; nothing was written"), std::string::npos) << log_text();
  EXPECT_EQ(log_text().find("exported baked-skin"), std::string::npos) << log_text();
  EXPECT_FALSE(fs::exists(glb));
  EXPECT_FALSE(fs::exists(glb.string() + ".tmp"));
  EXPECT_FALSE(fs::exists(other));
}

TEST_F(WorkspaceExportTest, ExportLinesItCannotReadAreNamedAndCounted) {
  ws.run("export gltf baked-skin 4 walk " + (dir_ / "a.glb").string());
  ws.run("export glb baked-skin 4 jog " + (dir_ / "b.glb").string());
  ws.run("export glb sideways 4 walk " + (dir_ / "c.glb").string());
  ws.run("export glb baked-skin");
  const std::string log = log_text();
  EXPECT_NE(log.find("format 'gltf' is not glb, obj or json"), std::string::npos) << log;
  EXPECT_NE(log.find("no clip 'jog'"), std::string::npos) << log;
  EXPECT_NE(log.find("unknown mode 'sideways'"), std::string::npos) << log;
  EXPECT_NE(log.find("export FORMAT MODE|- FPS all|CLIP[,CLIP] PATH"), std::string::npos) << log;
  EXPECT_EQ(ws.export_state().failures, 4);
  EXPECT_FALSE(ws.exporting());
  EXPECT_TRUE(fs::is_empty(dir_));
}

}  // namespace
}  // namespace cagewrap::app
