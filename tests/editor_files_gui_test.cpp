// The editor's files under Xvfb, driven by --script through the file browser's own code: saving
// through the browser writes the project, the recent files, the last folder, the display toggles
// and the window size to preferences.json in the config folder (CAGEWRAP_CONFIG_DIR, a temporary
// folder here), and the next run reads them back; the overwrite question; a corrupt preferences
// file is named and replaced; screenshots and cage imports through the browser.
#include <gtest/gtest.h>
#include <stb_image.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/gui_harness.h"

namespace {

namespace fs = std::filesystem;
using cagewrap::test::read_file;
using cagewrap::test::gui_available;



class EditorFilesGui : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string why;
    if (!gui_available(why)) GTEST_SKIP() << why;
    dir_ = fs::temp_directory_path() / "cagewrap_files_gui_test" /
           ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "projects");
  }
  // Runs the editor (demo character) with `script`; returns its log. `args` adds options.
  std::string run(const std::string& name, const std::string& script, const std::string& args = "") {
    auto r = cagewrap::test::run_editor_script(dir_, name, script, args, config());
    EXPECT_EQ(r.status, 0) << name << "\n" << r.log;
    return r.log;
  }
  nlohmann::json prefs() const { return nlohmann::json::parse(read_file(config() / "preferences.json")); }
  fs::path config() const { return dir_ / "config"; }
  fs::path project(const std::string& name) const { return dir_ / "projects" / (name + ".cagewrap"); }
  fs::path dir_;
};

TEST_F(EditorFilesGui, SavedThroughTheBrowserAndRememberedNextTime) {
  const std::string folder = (dir_ / "projects").string();
  // first run: a wireframe toggle, then Save as through the browser
  std::string log = run("first",
                        "wait 2\ntoggle wireframe\nbrowse save " + folder +
                            "\nwait 1\nbrowser_name first\nbrowser_confirm\nwait 2\n",
                        "--width 1000 --height 600");
  ASSERT_TRUE(fs::exists(project("first"))) << log;
  auto p = prefs();
  ASSERT_EQ(p["recent_files"].size(), 1u) << p.dump(2);
  EXPECT_EQ(p["recent_files"][0], project("first").string());
  EXPECT_EQ(p["last_directory"], folder);
  EXPECT_EQ(p["display"]["wireframe"], true);
  EXPECT_EQ(p["window"]["width"], 1000);
  EXPECT_EQ(p["window"]["height"], 600);

  // second run, no folder and no size given: the browser opens in the last folder; saving over
  // "first" asks first (confirmed), then "second" is saved beside it; the window has the size left
  const auto first_written = fs::last_write_time(project("first"));
  const fs::path png = dir_ / "second.png";
  log = run(
      "second",
      "wait 2\nbrowse save\nwait 1\nbrowser_name first\nbrowser_confirm\nwait 1\nbrowser_confirm\nwait 2\n"
      "browse save\nwait 1\nbrowser_name second\nbrowser_confirm\nwait 2\n",
      "--screenshot " + png.string());
  EXPECT_NE(log.find("saved " + project("first").string()), std::string::npos) << log;
  EXPECT_GE(fs::last_write_time(project("first")), first_written);
  ASSERT_TRUE(fs::exists(project("second"))) << log;
  p = prefs();
  ASSERT_EQ(p["recent_files"].size(), 2u) << p.dump(2);
  EXPECT_EQ(p["recent_files"][0], project("second").string());
  EXPECT_EQ(p["recent_files"][1], project("first").string());
  EXPECT_EQ(p["display"]["wireframe"], true) << "read back and kept";
  int w = 0, h = 0, n = 0;
  ASSERT_TRUE(stbi_info(png.string().c_str(), &w, &h, &n)) << png;
  EXPECT_EQ(w, 1000);
  EXPECT_EQ(h, 600);
}

TEST_F(EditorFilesGui, OverwriteCanBeDeclined) {
  std::ofstream(project("keep")) << "precious";
  const std::string log = run("decline", "wait 2\nbrowse save " + (dir_ / "projects").string() +
                                             "\nwait 1\nbrowser_name keep\nbrowser_confirm\nwait "
                                             "1\nbrowser_cancel\nwait 1\nbrowser_cancel\nwait 1\n");
  EXPECT_EQ(read_file(project("keep")), "precious") << log;
  EXPECT_EQ(log.find("saved"), std::string::npos) << log;
}

TEST_F(EditorFilesGui, CorruptPreferencesAreNamedAndReplaced) {
  fs::create_directories(config());
  std::ofstream(config() / "preferences.json") << "{ \"recent_files\": [ oops";
  const std::string log = run("corrupt", "wait 2\n");
  EXPECT_NE(log.find((config() / "preferences.json").string()), std::string::npos) << log;
  EXPECT_NE(log.find("using the defaults"), std::string::npos) << log;
  EXPECT_NO_THROW(prefs()) << "replaced by a valid file on exit";
}

TEST_F(EditorFilesGui, ScreenshotAndCageImportThroughTheBrowser) {
  // the demo's own cage, imported again through the browser: one undo step, bound again
  const std::string assets = std::string(CAGEWRAP_SOURCE_DIR) + "/assets";
  const std::string log =
      run("shot", "wait 2\nbrowse import_cage " + assets +
                      "\nwait 1\nbrowser_select demo_cage.obj\nbrowser_confirm\nwait 2\n"
                      "undo\nwait 1\nredo\nwait 1\n"
                      "browse screenshot " +
                      dir_.string() + "\nwait 1\nbrowser_name shot\nbrowser_confirm\nwait 4\n");
  EXPECT_NE(log.find("imported cage " + assets + "/demo_cage.obj: 1002 vertices"), std::string::npos) << log;
  EXPECT_NE(log.find("Import cage demo_cage.obj"), std::string::npos) << "undo names the step\n" << log;
  EXPECT_NE(log.find("saved screenshot " + (dir_ / "shot.png").string()), std::string::npos) << log;
  int w = 0, h = 0, n = 0;
  ASSERT_TRUE(stbi_info((dir_ / "shot.png").string().c_str(), &w, &h, &n));
  EXPECT_EQ(w, 1600) << "no size given and none remembered: the default window";
  EXPECT_EQ(h, 900);
}

}  // namespace
