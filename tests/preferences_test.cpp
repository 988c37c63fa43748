// Tests for app/workspace/preferences.h: save -> load gives the same preferences; a missing file gives the
// defaults quietly; a corrupt file or a bad field gives the defaults and a warning naming it, never
// a crash; fields of a newer version survive; the recent list stays short and without repeats; the
// config folder follows CAGEWRAP_CONFIG_DIR, then XDG_CONFIG_HOME, then HOME.
#include "app/workspace/preferences.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "tests/document_fixtures.h"

namespace cagewrap {
namespace {

namespace fs = std::filesystem;
using test::read_text;
using test::write_text;

class PreferencesTest : public test::TempDirTest {};

Preferences sample() {
  Preferences p;
  p.recent_files = {"/models/hero.cagewrap", "/models/hero.glb"};
  p.window_width = 1280;
  p.window_height = 720;
  p.last_directory = "/models";
  p.wireframe = true;
  p.show_grid = false;
  p.xray = true;
  return p;
}

bool mentions(const std::vector<std::string>& warnings, const std::string& part) {
  for (const auto& w : warnings)
    if (w.find(part) != std::string::npos) return true;
  return false;
}

TEST_F(PreferencesTest, SaveThenLoadGivesTheSame) {
  const std::string file = path("sub/dir/preferences.json");  // the folder is created
  ASSERT_TRUE(save_preferences(file, sample()).ok());
  auto loaded = load_preferences(file);
  EXPECT_TRUE(loaded.warnings.empty()) << loaded.warnings[0];
  EXPECT_TRUE(loaded.prefs == sample());
  EXPECT_FALSE(fs::exists(file + ".tmp"));
  auto j = nlohmann::json::parse(read_text(file));
  EXPECT_EQ(j["format"], "cagewrap-preferences");
  EXPECT_EQ(j["version"], kPreferencesVersion);
  EXPECT_EQ(j["window"]["width"], 1280);
  EXPECT_EQ(j["display"]["wireframe"], true);
}

TEST_F(PreferencesTest, PanelSizesAreRememberedAndCheckedByName) {
  Preferences p;
  p.panel_left = 310;
  p.panel_right = 420;
  p.panel_bottom = 230;
  ASSERT_TRUE(save_preferences(path("p.json"), p).ok());
  auto loaded = load_preferences(path("p.json"));
  EXPECT_TRUE(loaded.warnings.empty());
  EXPECT_EQ(loaded.prefs.panel_left, 310);
  EXPECT_EQ(loaded.prefs.panel_right, 420);
  EXPECT_EQ(loaded.prefs.panel_bottom, 230);
  write_text(path("q.json"), R"({"panels": {"left": 5, "right": "wide", "bottom": 200}})");
  loaded = load_preferences(path("q.json"));
  EXPECT_EQ(loaded.prefs.panel_left, Preferences{}.panel_left);
  EXPECT_EQ(loaded.prefs.panel_right, Preferences{}.panel_right);
  EXPECT_EQ(loaded.prefs.panel_bottom, 200);
  EXPECT_EQ(loaded.warnings.size(), 2u);
  EXPECT_TRUE(mentions(loaded.warnings, "panels.left"));
  EXPECT_TRUE(mentions(loaded.warnings, "panels.right"));
}

TEST_F(PreferencesTest, MissingFileGivesDefaultsQuietly) {
  auto loaded = load_preferences(path("nothing.json"));
  EXPECT_TRUE(loaded.warnings.empty());
  EXPECT_TRUE(loaded.prefs == Preferences{});
  EXPECT_TRUE(load_preferences("").warnings.empty());
}

TEST_F(PreferencesTest, CorruptFileGivesDefaultsAndNamesIt) {
  for (const char* text :
       {"{ \"recent_files\": [", "", "[1, 2]", "\x89PNG\r\n", "null", "{\"format\": \"something-else\"}"}) {
    write_text(path("preferences.json"), text);
    auto loaded = load_preferences(path("preferences.json"));
    EXPECT_TRUE(loaded.prefs == Preferences{}) << text;
    ASSERT_EQ(loaded.warnings.size(), 1u) << text;
    EXPECT_NE(loaded.warnings[0].find(path("preferences.json")), std::string::npos) << loaded.warnings[0];
    EXPECT_NE(loaded.warnings[0].find("using the defaults"), std::string::npos) << loaded.warnings[0];
  }
}

TEST_F(PreferencesTest, FolderInPlaceOfTheFileIsAWarning) {
  fs::create_directories(dir_ / "preferences.json");
  auto loaded = load_preferences(path("preferences.json"));
  EXPECT_TRUE(loaded.prefs == Preferences{});
  ASSERT_EQ(loaded.warnings.size(), 1u);
  EXPECT_NE(loaded.warnings[0].find(path("preferences.json")), std::string::npos);
  auto st = save_preferences(path("preferences.json"), sample());
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().message.find(path("preferences.json")), std::string::npos) << st.error().message;
}

TEST_F(PreferencesTest, BadFieldsKeepTheirDefaultAndAreNamed) {
  write_text(path("p.json"),
             R"({"window": {"width": "wide", "height": 50}, "display": {"wireframe": 1, "xray": true},
                                  "last_directory": 7, "recent_files": ["/a.glb", 3, "", "/a.glb", "/b.glb"]})");
  auto loaded = load_preferences(path("p.json"));
  EXPECT_EQ(loaded.prefs.window_width, 1600);
  EXPECT_EQ(loaded.prefs.window_height, 900);
  EXPECT_FALSE(loaded.prefs.wireframe);
  EXPECT_TRUE(loaded.prefs.xray) << "good fields beside bad ones are read";
  EXPECT_EQ(loaded.prefs.last_directory, "");
  EXPECT_EQ(loaded.prefs.recent_files, (std::vector<std::string>{"/a.glb", "/b.glb"}));
  EXPECT_EQ(loaded.warnings.size(), 4u);
  EXPECT_TRUE(mentions(loaded.warnings, "window.width"));
  EXPECT_TRUE(mentions(loaded.warnings, "window.height"));
  EXPECT_TRUE(mentions(loaded.warnings, "display.wireframe"));
  EXPECT_TRUE(mentions(loaded.warnings, "last_directory"));
  for (const auto& w : loaded.warnings) EXPECT_NE(w.find(path("p.json")), std::string::npos) << w;
  write_text(path("q.json"), R"({"window": [1], "display": false, "recent_files": "x"})");
  loaded = load_preferences(path("q.json"));
  EXPECT_TRUE(loaded.prefs == Preferences{});
  EXPECT_EQ(loaded.warnings.size(), 3u);
}

TEST_F(PreferencesTest, FieldsOfANewerVersionSurvive) {
  write_text(path("p.json"), R"({"format": "cagewrap-preferences", "version": 3, "theme": "light",
                                  "display": {"wireframe": true, "shadows": "soft"}, "window": {"width": 800, "maximised": true}})");
  auto loaded = load_preferences(path("p.json"));
  EXPECT_TRUE(loaded.warnings.empty());
  EXPECT_TRUE(loaded.prefs.wireframe);
  EXPECT_EQ(loaded.prefs.window_width, 800);
  loaded.prefs.wireframe = false;
  ASSERT_TRUE(save_preferences(path("p.json"), loaded.prefs).ok());
  auto j = nlohmann::json::parse(read_text(path("p.json")));
  EXPECT_EQ(j["theme"], "light");
  EXPECT_EQ(j["display"]["shadows"], "soft");
  EXPECT_EQ(j["display"]["wireframe"], false) << "the known value wins";
  EXPECT_EQ(j["window"]["maximised"], true);
  EXPECT_EQ(j["window"]["width"], 800);
  EXPECT_EQ(j["version"], kPreferencesVersion);
}

TEST_F(PreferencesTest, PathsJsonCannotHoldAreNotRemembered) {
  Preferences p;
  p.recent_files = {"/ok.glb", std::string("/bad\xff.glb")};
  p.last_directory = std::string("/bad\xfe");
  ASSERT_TRUE(save_preferences(path("p.json"), p).ok());
  auto loaded = load_preferences(path("p.json"));
  EXPECT_TRUE(loaded.warnings.empty());
  EXPECT_EQ(loaded.prefs.recent_files, (std::vector<std::string>{"/ok.glb"}));
  EXPECT_EQ(loaded.prefs.last_directory, "");
}

TEST(Preferences, RecentFilesMostRecentFirstWithoutRepeats) {
  Preferences p;
  add_recent_file(p, "/m/a.glb");
  add_recent_file(p, "/m/b.cagewrap");
  add_recent_file(p, "/m/x/../a.glb");  // the same file: moves to the front
  EXPECT_EQ(p.recent_files, (std::vector<std::string>{"/m/a.glb", "/m/b.cagewrap"}));
  for (int i = 0; i < 20; ++i) add_recent_file(p, "/m/f" + std::to_string(i) + ".glb");
  ASSERT_EQ(p.recent_files.size(), kMaxRecentFiles);
  EXPECT_EQ(p.recent_files.front(), "/m/f19.glb");
  EXPECT_EQ(p.recent_files.back(), "/m/f10.glb");
  EXPECT_TRUE(remove_recent_file(p, "/m/f15.glb"));
  EXPECT_FALSE(remove_recent_file(p, "/m/f15.glb"));
  EXPECT_EQ(p.recent_files.size(), kMaxRecentFiles - 1);
  add_recent_file(p, "relative.glb");
  EXPECT_EQ(p.recent_files.front(), (fs::current_path() / "relative.glb").string());
}

TEST(Preferences, ConfigFolderFollowsTheEnvironment) {
  EXPECT_EQ(preferences_directory("/tmp/cfg", "/xdg", "/home/u"), "/tmp/cfg");
  EXPECT_EQ(preferences_directory("", "/xdg", "/home/u"), "/xdg/cagewrap");
  EXPECT_EQ(preferences_directory(nullptr, nullptr, "/home/u"), "/home/u/.config/cagewrap");
  EXPECT_EQ(preferences_directory(nullptr, "relative/xdg", "/home/u"), "/home/u/.config/cagewrap");
  EXPECT_EQ(preferences_directory(nullptr, nullptr, nullptr), "");
  EXPECT_EQ(preferences_directory(nullptr, "", ""), "");
}

}  // namespace
}  // namespace cagewrap
