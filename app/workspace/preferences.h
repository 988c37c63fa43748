// What the editor remembers between runs: recent files, window size, the last folder browsed, the
// display toggles and the autosave interval, in preferences.json in the user's config folder ($CAGEWRAP_CONFIG_DIR, else
// $XDG_CONFIG_HOME/cagewrap, else ~/.config/cagewrap). Loading never fails: a missing file gives
// the defaults, a corrupt one the defaults and a warning naming it, a bad field its default and a
// warning naming the field. Saving is atomic (core/base/atomic_write.h).
#pragma once

#include <string>
#include <vector>

#include "core/base/result.h"

namespace cagewrap {

inline constexpr int kPreferencesVersion = 1;
inline constexpr size_t kMaxRecentFiles = 10;

struct Preferences {
  std::vector<std::string> recent_files;  // absolute paths, most recent first, at most kMaxRecentFiles
  int window_width = 1600, window_height = 900;
  // the editor's panel sizes in pixels (app/workspace/panel_layout.h: the defaults, and how a small
  // window shrinks them)
  int panel_left = 260, panel_right = 340, panel_bottom = 170;
  std::string last_directory;  // the folder the file browser showed last; "" = the current folder
  // display toggles (View menu)
  bool show_skin = true, show_cage = true, show_skeleton = true, show_grid = true;
  bool wireframe = false, xray = false;
  // How often the editor writes a recovery file of unsaved work (app/workspace/autosave.h); 0 = never.
  double autosave_seconds = 180.0;
  // A JSON object (text) of the fields this build does not know, written back unchanged so that a
  // newer version's settings survive a run of this one. "" = none.
  std::string preserved_fields;
};

bool operator==(const Preferences& a, const Preferences& b);

// Puts `path` (made absolute) first in the recent list, removing an earlier copy and the oldest
// entries beyond kMaxRecentFiles.
void add_recent_file(Preferences& prefs, const std::string& path);
// Removes `path` from the recent list; returns whether it was there.
bool remove_recent_file(Preferences& prefs, const std::string& path);

// The folder preferences.json lives in, from the values of $CAGEWRAP_CONFIG_DIR, $XDG_CONFIG_HOME
// and $HOME (null or empty = unset; a relative XDG_CONFIG_HOME is ignored, as the XDG spec says).
// "" when none is set.
std::string preferences_directory(const char* override_dir, const char* xdg_config_home, const char* home);
// The same from this process's environment.
std::string preferences_directory();
// preferences_directory() + "/preferences.json", or "" when there is no config folder.
std::string preferences_path();

struct PreferencesLoad {
  Preferences prefs;
  std::vector<std::string> warnings;  // each names the file (and the field)
};

PreferencesLoad load_preferences(const std::string& path);
std::string preferences_to_json(const Preferences& prefs);
// Creates the folder when needed; errors name the file.
Status save_preferences(const std::string& path, const Preferences& prefs);

}  // namespace cagewrap
