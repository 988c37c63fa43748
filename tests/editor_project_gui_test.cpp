// The editor keeping and finding projects, under Xvfb: the autosave survives a SIGKILL and the
// next start offers it back (Recover / Discard / Later; a recovered document is unsaved and saves
// with the edit; a clean quit or a save removes it); a moved character is located through the dialog and the file browser, and the
// project remembers the new place when saved; a project of a newer version is refused naming both
// versions; unknown fields are logged and written back; a cached binding opens without a bind
// and a stale one says why; the character is embedded from the File menu and the project then
// opens with no other file. Screenshots of each dialog are kept in the test folder.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "app/workspace/autosave.h"
#include "core/document/binding_cache.h"
#include "core/document/project_io.h"
#include "tests/gui_harness.h"

namespace cagewrap {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;
using test::read_file;

::testing::AssertionResult Logged(const std::string& log, const std::string& part) {
  if (log.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "the log does not say \"" << part << "\":\n" << log;
}

class EditorProjectGui : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string why;
    if (!test::gui_available(why)) GTEST_SKIP() << why;
    dir_ = test::gui_test_dir() / "project" / ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  std::string p(const std::string& name) const { return (dir_ / name).string(); }
  fs::path config() const { return dir_ / "config"; }
  static std::string asset(const std::string& name) { return std::string(CAGEWRAP_SOURCE_DIR) + "/assets/" + name; }
  // `cagewrap new` on the demo character (copied to `character`) and its cage, with `options`.
  void make_project(const std::string& project, const std::string& character, const std::string& options = "") {
    fs::create_directories(fs::path(p(character)).parent_path());
    fs::copy_file(asset("demo_character.glb"), p(character), fs::copy_options::overwrite_existing);
    const std::string cmd = std::string(CAGEWRAP_BINARY) + " new --character " + p(character) + " --cage " +
                            asset("demo_cage.obj") + " " + options + " --out " + p(project) + " > " + p(project + ".new.log") + " 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << read_file(p(project + ".new.log"));
  }
  test::EditorRun run(const std::string& name, const std::string& script, const std::string& args = "") {
    auto r = test::run_editor_script(dir_, name, script, args, config());
    EXPECT_EQ(r.status, 0) << name << "\n" << r.log;
    return r;
  }
  void expect_picture(const std::string& png) {
    test::Image img = test::load_png(png);
    EXPECT_EQ(img.w, 1280) << png;
    EXPECT_EQ(img.h, 720) << png;
  }
  fs::path dir_;
};

std::vector<fs::path> recovery_files(const fs::path& dir) {
  std::vector<fs::path> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.path().extension() == ".cagewrap") out.push_back(e.path());
  return out;
}

TEST_F(EditorProjectGui, AutosaveSurvivesSigkillAndTheNextStartRecoversIt) {
  make_project("hero.cagewrap", "hero.glb");
  const std::string project_bytes = read_file(p("hero.cagewrap"));
  const fs::path recovery_dir = recovery_directory(config().string());
  // first run: an edit, then the editor stays up until the test kills it
  std::ofstream(p("edit.script")) << "wait 2\nselect_cage_vertex 5\nmove 0 0.05 0\nwait 100000\n";
  const std::string cmd = test::editor_command_with_pid(
      "--width 1280 --height 720 " + p("hero.cagewrap") + " --autosave-seconds 1 --script " + p("edit.script"),
      config().string(), p("edit.log"), p("editor.pid"));
  std::thread editor([cmd] { (void)std::system(cmd.c_str()); });
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  // the log line comes after the file is in place: once it is there, the kill finds a written file
  while (read_file(p("edit.log")).find("autosaved the unsaved work to") == std::string::npos &&
         std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  const std::string pid_text = read_file(p("editor.pid"));
  const pid_t pid = static_cast<pid_t>(std::atoi(pid_text.c_str()));
  ASSERT_GT(pid, 0) << "no editor pid";
  kill(pid, SIGKILL);
  editor.join();
  const std::string log1 = read_file(p("edit.log"));
  auto files = recovery_files(recovery_dir);
  ASSERT_EQ(files.size(), 1u) << log1;
  EXPECT_TRUE(Logged(log1, "autosaved the unsaved work to " + files[0].string()));
  EXPECT_EQ(read_file(p("hero.cagewrap")), project_bytes) << "the project itself is untouched";
  auto autosaved = load_project(files[0].string());
  ASSERT_TRUE(autosaved.ok()) << autosaved.error().message;
  ASSERT_TRUE(autosaved->recovery);
  EXPECT_EQ(autosaved->recovery->project, p("hero.cagewrap"));
  EXPECT_EQ(autosaved->recovery->pid, pid);
  ASSERT_GT(autosaved->document.cage_offsets.size(), 5u);
  EXPECT_GT(glm::length(autosaved->document.cage_offsets[5]), 0.01f) << "the edit is in the recovery file";
  fs::copy_file(files[0], p("kept.cagewrap"));  // for the Later / Discard runs below

  // second start: the prompt is up (screenshot), Recover, then save the recovered work elsewhere
  auto r = run("recover", "wait 2\nscreenshot " + p("recover_prompt.png") + "\nanswer_recovery recover\nwait 3\nsave " +
                              p("recovered.cagewrap") + "\nwait 1\n",
               "--width 1280 --height 720 --autosave-seconds 1");
  EXPECT_TRUE(Logged(r.log, "1 recovery file(s) of unsaved work found"));
  EXPECT_TRUE(Logged(r.log, "recovered the unsaved work of " + p("hero.cagewrap") + " from "));
  EXPECT_TRUE(Logged(r.log, "saved " + p("recovered.cagewrap")));
  expect_picture(p("recover_prompt.png"));
  auto recovered = load_project(p("recovered.cagewrap"));
  ASSERT_TRUE(recovered.ok()) << recovered.error().message;
  EXPECT_FALSE(recovered->recovery) << "a saved project is not a recovery file";
  EXPECT_TRUE(same_content(recovered->document, autosaved->document)) << "the edit survived the kill";
  EXPECT_TRUE(recovery_files(recovery_dir).empty()) << "saved: no recovery file is left";

  // Later keeps the file for the next start; Discard deletes it
  fs::copy_file(p("kept.cagewrap"), recovery_dir / "recovery-1-1.cagewrap");
  r = run("later", "wait 2\nanswer_recovery later\nwait 2\n", "--autosave-seconds 1");
  EXPECT_EQ(recovery_files(recovery_dir).size(), 1u) << r.log;
  r = run("discard", "wait 2\nanswer_recovery discard\nwait 2\n", "--autosave-seconds 1");
  EXPECT_TRUE(Logged(r.log, "discarded the recovery file"));
  EXPECT_TRUE(recovery_files(recovery_dir).empty()) << r.log;
  // a clean quit removes the recovery file even with unsaved work (the artist was asked on quit)
  r = run("quit", "wait 2\nselect_cage_vertex 5\nmove 0 0.05 0\nwait 5\n", p("hero.cagewrap") + " --autosave-seconds 0.01");
  EXPECT_TRUE(Logged(r.log, "autosaved the unsaved work to "));
  EXPECT_TRUE(recovery_files(recovery_dir).empty()) << r.log;
  // the project saved after its autosave: not offered, removed
  fs::copy_file(p("kept.cagewrap"), recovery_dir / "recovery-1-1.cagewrap");
  fs::last_write_time(p("hero.cagewrap"), fs::file_time_type::clock::now());
  r = run("stale", "wait 2\n", "--autosave-seconds 1");
  EXPECT_TRUE(Logged(r.log, "older than its project"));
  EXPECT_TRUE(recovery_files(recovery_dir).empty()) << r.log;
}

TEST_F(EditorProjectGui, MovedCharacterIsLocatedAndTheProjectRemembersIt) {
  make_project("p.cagewrap", "chars/hero.glb");
  fs::create_directories(dir_ / "chars/moved");
  fs::rename(p("chars/hero.glb"), p("chars/moved/hero.glb"));
  // Cancel: nothing opens, the error is in the log
  auto r = run("cancel", "wait 2\nanswer_missing cancel\nwait 2\n", p("p.cagewrap"));
  EXPECT_TRUE(Logged(r.log, "character file " + p("chars/hero.glb") + " not found"));
  EXPECT_EQ(r.log.find("located the character"), std::string::npos) << r.log;
  // Locate...: the browser opens in the folder it was in; pick the file; save
  r = run("locate",
          "wait 2\nscreenshot " + p("missing.png") + "\nanswer_missing locate\nwait 2\nbrowser_select moved\nbrowser_confirm\nwait 1\n"
          "browser_select hero.glb\nwait 1\nscreenshot " + p("locate.png") + "\nbrowser_confirm\nwait 3\nsave " + p("p.cagewrap") + "\nwait 1\n",
          "--width 1280 --height 720 " + p("p.cagewrap"));
  expect_picture(p("missing.png"));
  expect_picture(p("locate.png"));
  EXPECT_TRUE(Logged(r.log, "located the character at " + p("chars/moved/hero.glb") + "; save the project to remember"));
  EXPECT_TRUE(Logged(r.log, "saved " + p("p.cagewrap")));
  EXPECT_EQ(Json::parse(read_file(p("p.cagewrap")))["character"]["path"], "chars/moved/hero.glb");
  auto loaded = load_project(p("p.cagewrap"));
  EXPECT_TRUE(loaded.ok()) << (loaded.ok() ? "" : loaded.error().message);
}

TEST_F(EditorProjectGui, NewerVersionIsRefusedNamingBothVersions) {
  make_project("p.cagewrap", "hero.glb");
  Json j = Json::parse(read_file(p("p.cagewrap")));
  j["version"] = 99;
  std::ofstream(p("newer.cagewrap")) << j.dump(1);
  auto r = run("newer", "wait 2\nscreenshot " + p("newer.png") + "\n", "--width 1280 --height 720 " + p("newer.cagewrap"));
  EXPECT_TRUE(Logged(r.log, p("newer.cagewrap") + ": made by a newer cagewrap: version 99, this build reads up to " +
                                std::to_string(kProjectVersion) + "; update cagewrap to open it"));
  expect_picture(p("newer.png"));
}

TEST_F(EditorProjectGui, UnknownFieldsAreLoggedAndWrittenBack) {
  make_project("p.cagewrap", "hero.glb");
  Json j = Json::parse(read_file(p("p.cagewrap")));
  j["muscles"] = {{"biceps", 1.5}};
  j["binding"]["stiffness"] = 2;
  std::ofstream(p("unknown.cagewrap")) << j.dump(1);
  auto r = run("unknown", "wait 2\nscreenshot " + p("unknown.png") + "\nsave " + p("resaved.cagewrap") + "\nwait 1\n",
               "--width 1280 --height 720 " + p("unknown.cagewrap"));
  EXPECT_TRUE(Logged(r.log, "warning: " + p("unknown.cagewrap") + ": field 'muscles' is not known to this build"));
  EXPECT_TRUE(Logged(r.log, "binding.stiffness is not known to this build and was ignored"));
  EXPECT_TRUE(Logged(r.log, "opened " + p("unknown.cagewrap")));
  expect_picture(p("unknown.png"));
  EXPECT_EQ(Json::parse(read_file(p("resaved.cagewrap")))["muscles"]["biceps"], 1.5) << "kept";
}

TEST_F(EditorProjectGui, CachedBindingOpensWithoutABindAndAStaleOneSaysWhy) {
  make_project("p.cagewrap", "hero.glb", "--cache-binding");
  ASSERT_TRUE(fs::exists(p("p.cagewrap.cwb")));
  auto r = run("cached", "wait 2\n", p("p.cagewrap"));
  EXPECT_TRUE(Logged(r.log, "using the cached binding " + p("p.cagewrap.cwb") + " (no bind)"));
  EXPECT_EQ(r.log.find("bound "), std::string::npos) << "no bind ran:\n" << r.log;
  // the parameters edited in the file: the cache is stale, the editor binds and says why
  Json j = Json::parse(read_file(p("p.cagewrap")));
  j["binding"]["epsilon"] = 0.2;
  std::ofstream(p("p.cagewrap")) << j.dump(1);
  r = run("stale", "wait 2\nsave " + p("p.cagewrap") + "\nwait 1\n", p("p.cagewrap"));
  EXPECT_TRUE(Logged(r.log, "binding cache not used: " + p("p.cagewrap.cwb") + " is out of date: the binding parameters changed"));
  EXPECT_TRUE(Logged(r.log, "bound "));
  // saved after the bind: the cache is written again and is valid for the new parameters
  EXPECT_TRUE(Logged(r.log, "(and its binding, " + p("p.cagewrap.cwb") + ")"));
  auto loaded = load_project(p("p.cagewrap"));
  ASSERT_TRUE(loaded.ok());
  EXPECT_TRUE(load_binding_cache(loaded->document).ok());
}

TEST_F(EditorProjectGui, EmbeddedFromTheFileMenuOpensWithNoOtherFile) {
  make_project("p.cagewrap", "hero.glb");
  auto r = run("embed", "wait 2\nembed on\nwait 1\nsave " + p("embedded.cagewrap") + "\nwait 1\n", p("p.cagewrap"));
  EXPECT_TRUE(Logged(r.log, "embedded the character " + p("hero.glb")));
  Json j = Json::parse(read_file(p("embedded.cagewrap")));
  EXPECT_EQ(j["version"], 3);
  EXPECT_TRUE(j["character"].contains("embedded"));
  fs::remove(p("hero.glb"));
  const test::Image img = test::screenshot(p("embedded.cagewrap"), "embedded_open");
  EXPECT_GT(test::skin_share(img), 0.02) << "the embedded character is drawn";
  // taken out again from the menu: written where the browser says, named by the project
  r = run("unembed", "wait 2\nembed off\nwait 1\nbrowser_name back\nbrowser_confirm\nwait 1\nsave " + p("out.cagewrap") + "\nwait 1\n",
          p("embedded.cagewrap"));
  EXPECT_TRUE(Logged(r.log, "names the character file " + p("back.glb")));
  EXPECT_EQ(read_file(p("back.glb")), read_file(asset("demo_character.glb")));
  EXPECT_EQ(Json::parse(read_file(p("out.cagewrap")))["character"]["path"], "back.glb");
}

}  // namespace
}  // namespace cagewrap
