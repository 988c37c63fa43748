// Issue 23: an FBX and a DirectX character opened in the editor as an artist would: through File > Open's file
// browser, which lists them, with its "Keep the file's units and up axis" choice (saved in the project), and
// directly (as a drop on the window does); a broken FBX is refused naming the file and the document stays.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "tests/gui_harness.h"

namespace {

namespace fs = std::filesystem;
using namespace cagewrap;

fs::path assimp_models() {
  const char* env = std::getenv("CAGEWRAP_ASSIMP_MODELS");
  return env && *env ? fs::path(env) : fs::path("/usr/share/assimp/models");
}

TEST(EditorAssimpGui, FbxAndDirectXCharactersOpenThroughTheBrowserAndKeepTheirUnitsOnRequest) {
  std::string why;
  if (!test::gui_available(why)) GTEST_SKIP() << why;
  const fs::path models = assimp_models();
  if (!fs::exists(models / "FBX/huesitos.fbx") || !fs::exists(models / "X/Testwuson.X"))
    GTEST_SKIP() << models << " lacks FBX/huesitos.fbx or X/Testwuson.X: install assimp-testmodels (scripts/setup.sh)";
  const fs::path dir = test::gui_test_dir() / "assimp";
  fs::remove_all(dir);
  fs::create_directories(dir / "files");
  fs::copy_file(models / "FBX/huesitos.fbx", dir / "files/bones.fbx");
  { std::ofstream(dir / "files/broken.fbx") << "Kaydara FBX Binary  \n not really"; }
  const std::string files = (dir / "files").string();
  const std::string script =
      "wait 2\n"
      "browse open " + files + "\nwait 1\nbrowser_select broken.fbx\nbrowser_confirm\nwait 2\n"
      "screenshot " + (dir / "broken.png").string() + "\nerror_ok\nwait 1\n"
      "keep_units on\nbrowse open " + files + "\nwait 1\n"
      "screenshot " + (dir / "browser.png").string() + "\nbrowser_select bones.fbx\nbrowser_confirm\nwait 3\n"
      "save " + (dir / "bones.cagewrap").string() + "\nwait 1\n"
      "keep_units off\nopen " + (models / "X/Testwuson.X").string() + "\nwait 2\n"
      "clip Wuson_Walk\ntime 1.0\nwait 3\n"
      "screenshot " + (dir / "wuson.png").string() + "\n";
  const auto run = test::run_editor_script(dir, "assimp", script, "--width 1280 --height 720", dir / "config");
  EXPECT_EQ(run.status, 0) << run.log;
  // the broken file is named, and not opened
  EXPECT_NE(run.log.find("error: " + files + "/broken.fbx: "), std::string::npos) << run.log;
  EXPECT_EQ(run.log.find("opened " + files + "/broken.fbx"), std::string::npos) << run.log;
  // the FBX opened in its own units: no conversion note, and the project saved says so
  EXPECT_NE(run.log.find("opened " + files + "/bones.fbx"), std::string::npos) << run.log;
  const std::string project = test::read_file(dir / "bones.cagewrap");
  EXPECT_NE(project.find("\"keep_units\": true"), std::string::npos) << project;
  // the DirectX character, converted as usual, is drawn
  EXPECT_NE(run.log.find("opened " + (models / "X/Testwuson.X").string()), std::string::npos) << run.log;
  const test::Image wuson = test::load_png((dir / "wuson.png").string());
  ASSERT_EQ(wuson.w, 1280) << run.log;
  EXPECT_GT(test::skin_share(wuson), 0.02) << "the Wuson should be drawn";
}

}  // namespace
