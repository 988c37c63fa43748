// The editor's side of files: the preferences it remembers between runs (app/workspace/preferences.h), the
// File > Open Recent menu and the file browser (app/file_browser.h), so that app/editor.cpp only
// asks for a file and acts on the answer.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "app/file_browser.h"
#include "app/workspace/preferences.h"
#include "render/viewport_renderer.h"

namespace cagewrap::app {

class EditorFiles {
 public:
  // Reads preferences.json from the config folder ($CAGEWRAP_CONFIG_DIR, $XDG_CONFIG_HOME/cagewrap
  // or ~/.config/cagewrap); returns the warnings to log (a corrupt file: the defaults are used).
  std::vector<std::string> load();
  // Writes it (atomically); returns an error message naming the file, or "".
  std::string save();
  const Preferences& prefs() const { return prefs_; }
  const std::string& path() const { return path_; }

  // The display toggles and window size remembered, into and out of the editor.
  void apply(render::ViewportStyle& style) const;
  void remember(const render::ViewportStyle& style, int window_width, int window_height);
  void remember_panels(float left, float right, float bottom);  // the splitters (app/workspace/panel_layout.h)

  // Opens the browser: in the folder of `near_path` when given, else the last folder browsed, else
  // the current folder; `file_name` prefills the name field when saving.
  void browse(FilePurpose purpose, const std::string& near_path = {}, const std::string& file_name = {});
  FileBrowser& browser() { return browser_; }
  bool browsing() const { return browser_.is_open(); }

  struct Choice {
    FilePurpose purpose;
    std::string path;
  };
  // Draws the browser while open; returns the file chosen this frame. Remembers the folder browsed.
  std::optional<Choice> draw_browser();

  // Remembers the autosave interval (0 = off) and saves the preferences; returns an error or "".
  std::string set_autosave_seconds(double seconds);

  // Puts `path` first in the recent files and saves the preferences; returns an error or "".
  std::string add_recent(const std::string& path);
  // Drops `path` from the recent files (it could not be opened); returns the message to log.
  std::string forget_recent(const std::string& path);
  // The items of File > Open Recent (between BeginMenu and EndMenu): missing files shown disabled,
  // "Remove missing files", "Clear list". Returns the file to open; `message` gets what to log.
  std::optional<std::string> draw_recent_menu(std::string& message);

 private:
  std::string path_;
  Preferences prefs_;
  FileBrowser browser_;
};

}  // namespace cagewrap::app
