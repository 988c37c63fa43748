// File > Export in the editor under Xvfb, driven by --script (`export FORMAT MODE FPS CLIPS PATH`
// opens the window, shows those settings and starts the workspace's export; the script waits for the
// background task): a script ending in an export waits for it and a failed one fails the run, and
// Browse... chooses the output the Export button writes. What the export writes, its refusals and
// Cancel are tested in-process (tests/workspace_export_test.cpp).
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
