// File > Export in the editor under Xvfb, driven by --script (`export FORMAT MODE FPS CLIPS PATH`
// presses the window's Export button with those settings; the script waits for the background
// task): a baked-skin .glb of the demo's walk that loads again (core/io/gltf_loader.h), is skinned with
// one morph target per frame and passes the Khronos validator; the report in the log; a bad path
// shown as an error while the editor carries on with its document; the JSON rig; Cancel during a
// long bake; Browse... choosing the output. The screenshots show the window with its report, its progress bar
// and the error.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "core/io/gltf_loader.h"
#include "core/base/json_reader.h"
#include "tests/gltf_validator.h"
#include "tests/gui_harness.h"

namespace cagewrap {
namespace {

namespace fs = std::filesystem;
using test::read_file;

class EditorExportGui : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string why;
    if (!test::gui_available(why)) GTEST_SKIP() << why;
    dir_ = fs::temp_directory_path() / "cagewrap_export_gui_test" /
           ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  // Runs the editor on the demo character and its cage with `script`, saving a screenshot at the
  // end; returns stdout and stderr.
  // `screenshot`: end with --screenshot (else the script's end ends the run); `succeed`: the run is
  // expected to exit 0 (a script whose export failed exits non-zero).
  std::string run(const std::string& name, const std::string& script, bool succeed = true, bool screenshot = true) {
    const fs::path s = dir_ / (name + ".script"), log = dir_ / (name + ".log");
    std::ofstream(s) << script;
    const std::string cmd = test::editor_command(
        "--width 1280 --height 720 --script " + s.string() +
            (screenshot ? " --screenshot " + (dir_ / (name + ".png")).string() : std::string()),
        (dir_ / "config").string(), log.string());
    const int status = std::system(cmd.c_str());
    if (succeed) EXPECT_EQ(status, 0) << cmd << "\n" << read_file(log);
    else EXPECT_NE(status, 0) << cmd << "\n" << read_file(log);
    return read_file(log);
  }
  fs::path dir_;
};

TEST_F(EditorExportGui, BakedSkinFromTheEditorLoadsAndValidates) {
  const fs::path glb = dir_ / "demo walk.glb";  // a space in the name, as people write them
  const std::string log =
      run("baked_skin", "wait 2\nexport glb baked-skin 4 walk " + glb.string() + "\nwait 3\n");
  ASSERT_TRUE(fs::exists(glb)) << log;
  EXPECT_NE(log.find("exported baked-skin: 5 frames, 5 morph targets, wrote " + glb.string()),
            std::string::npos)
      << log;
  EXPECT_NE(log.find("error at frames, skeleton only:"), std::string::npos) << log;
  EXPECT_EQ(log.find("error: "), std::string::npos) << log;

  auto loaded = load_character(glb.string());
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  ASSERT_EQ(loaded->clips.size(), 1u);
  EXPECT_EQ(loaded->clips[0].name, "walk");
  ASSERT_FALSE(loaded->primitives.empty());
  for (const Primitive& p : loaded->primitives) {
    EXPECT_GE(p.skin, 0) << "fitted weights";
    EXPECT_EQ(p.morph_targets.size(), 5u) << "one corrective per frame (walk, 1 s at 4 fps)";
  }
  if (test::node_available()) {
    std::string report;
    const int rc = test::run_gltf_validator({glb.string()}, (dir_ / "validator.txt").string(), report);
    ASSERT_NE(rc, 2) << "gltf-validator is not installed: run scripts/setup.sh\n" << report;
    EXPECT_EQ(rc, 0) << report;
    EXPECT_NE(report.find(glb.string() + ": 0 errors"), std::string::npos) << report;
  }
  // the window with its report is on screen
  test::Image shot = test::load_png((dir_ / "baked_skin.png").string());
  ASSERT_FALSE(shot.rgb.empty());
}

TEST_F(EditorExportGui, ABadPathIsAnErrorAndTheEditorCarriesOn) {
  const fs::path bad = dir_ / "missing" / "x.glb", json = dir_ / "rig.json";
  const std::string log =
      run("bad_path", "wait 2\nexport glb cage 4 all " + bad.string() + "\nwait 1\nexport json - 30 all " +
                          json.string() + "\nwait 3\n",
          /*succeed=*/false);  // the refused export fails the scripted run
  EXPECT_NE(log.find("error: export: " + bad.string() + ": the folder " + bad.parent_path().string() +
                     " does not exist"),
            std::string::npos)
      << log;
  EXPECT_FALSE(fs::exists(bad.parent_path()));
  // the document is still there: its rig exports as JSON afterwards
  ASSERT_TRUE(fs::exists(json)) << log;
  EXPECT_NE(log.find("exported rig as JSON"), std::string::npos) << log;
  auto j = read_json_file(json.string());
  ASSERT_TRUE(j.ok()) << j.error().message;
  EXPECT_EQ((*j)["format"], "cagewrap-rig");
  EXPECT_GT((*j)["cage"]["positions"].size(), 100u);
  EXPECT_EQ((*j)["attachment"]["mode"], "fitted");  // the default a new document gets
}

// A script that ends in `export` waits for the export to finish before the editor exits (it used to
// exit 0 having written nothing), and a failed export makes the run exit non-zero.
TEST_F(EditorExportGui, AScriptEndingInExportWaitsForItAndAFailureFailsTheRun) {
  const fs::path glb = dir_ / "last.glb";
  const std::string log = run("last", "export glb baked-animation 10 walk " + glb.string() + "\n", true, false);
  ASSERT_TRUE(fs::exists(glb)) << log;
  EXPECT_NE(log.find("exported baked-animation"), std::string::npos) << log;
  const fs::path bad = dir_ / "nowhere" / "x.glb";
  const std::string failed = run("last_bad", "export glb baked-animation 10 walk " + bad.string() + "\n", false, false);
  EXPECT_NE(failed.find("does not exist"), std::string::npos) << failed;
}

// A long bake (both clips at 60 fps) shows its progress; Cancel stops it and leaves no file.
TEST_F(EditorExportGui, CancelStopsALongBakeAndLeavesNoFile) {
  const fs::path glb = dir_ / "long.glb";
  const std::string log =
      run("cancel", "wait 2\nexport_nowait glb baked-skin 60 all " + glb.string() + "\nwait 6\nscreenshot " +
                        (dir_ / "progress.png").string() + "\nwait 3\nexport_cancel\nwait 2\n");
  EXPECT_NE(log.find("export cancelled; nothing was written"), std::string::npos) << log;
  EXPECT_EQ(log.find("exported baked-skin"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(glb));
  EXPECT_FALSE(fs::exists(glb.string() + ".tmp"));
  EXPECT_FALSE(test::load_png((dir_ / "progress.png").string()).rgb.empty()) << log;
}

// Browse... opens the file browser for the format (.json here, added to a typed name); the choice
// becomes the output that the Export button writes.
TEST_F(EditorExportGui, BrowseChoosesTheOutputTheButtonWrites) {
  const fs::path first = dir_ / "first.json", chosen = dir_ / "chosen.json";
  const std::string log = run(
      "browse",
      "wait 2\nexport json - 30 all " + first.string() +
          "\nexport_browse\nwait 2\nbrowser_name chosen\nbrowser_confirm\nwait 2\nexport_press\nwait 2\n");
  ASSERT_TRUE(fs::exists(first)) << log;
  ASSERT_TRUE(fs::exists(chosen)) << log;
  EXPECT_NE(log.find("exported rig as JSON: 1002 cage vertices"), std::string::npos) << log;
  EXPECT_EQ(read_file(first), read_file(chosen)) << "the same document, the same settings";
}

}  // namespace
}  // namespace cagewrap
