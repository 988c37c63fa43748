#if CAGEWRAP_GUI  // the editor's; nothing here without it
#include "app/editor_files.h"

#include <imgui/imgui.h>

#include <cstdlib>
#include <filesystem>

#include "app/workspace/file_listing.h"

namespace cagewrap::app {

namespace fs = std::filesystem;

namespace {

// A folder for a menu: "~" for the home folder, the middle elided past `max` characters.
std::string short_folder(const std::string& dir, size_t max = 48) {
  std::string s = dir;
  const char* home = std::getenv("HOME");
  if (home && *home) {
    const std::string h = absolute_path(home);
    if (h != "/" && s.compare(0, h.size(), h) == 0 && (s.size() == h.size() || s[h.size()] == '/'))
      s.replace(0, h.size(), "~");
  }
  if (s.size() > max) s.replace(max / 3, s.size() - (max - 3), "...");  // keeps max / 3 + the rest
  return s;
}

// The View menu's toggles as remembered in the preferences.
struct DisplayToggle {
  bool Preferences::*pref;
  bool render::ViewportStyle::*view;
};
constexpr DisplayToggle kDisplayToggles[] = {
    {&Preferences::show_skin, &render::ViewportStyle::show_skin},
    {&Preferences::show_cage, &render::ViewportStyle::show_cage},
    {&Preferences::show_skeleton, &render::ViewportStyle::show_skeleton},
    {&Preferences::show_grid, &render::ViewportStyle::show_grid},
    {&Preferences::wireframe, &render::ViewportStyle::wireframe},
    {&Preferences::xray, &render::ViewportStyle::xray},
};

}  // namespace

std::vector<std::string> EditorFiles::load() {
  path_ = preferences_path();
  auto loaded = load_preferences(path_);
  prefs_ = std::move(loaded.prefs);
  if (path_.empty())
    loaded.warnings.push_back("no config folder (HOME is not set): preferences will not be remembered");
  return loaded.warnings;
}

std::string EditorFiles::save() {
  if (path_.empty()) return {};
  auto st = save_preferences(path_, prefs_);
  return st.ok() ? std::string() : st.error().message;
}

void EditorFiles::apply(render::ViewportStyle& style) const {
  for (const auto& [pref, view] : kDisplayToggles) style.*view = prefs_.*pref;
}

void EditorFiles::remember(const render::ViewportStyle& style, int window_width, int window_height) {
  for (const auto& [pref, view] : kDisplayToggles) prefs_.*pref = style.*view;
  if (window_width > 0 && window_height > 0) {
    prefs_.window_width = window_width;
    prefs_.window_height = window_height;
  }
}

void EditorFiles::remember_panels(float left, float right, float bottom) {
  prefs_.panel_left = static_cast<int>(left + 0.5f);
  prefs_.panel_right = static_cast<int>(right + 0.5f);
  prefs_.panel_bottom = static_cast<int>(bottom + 0.5f);
}

void EditorFiles::browse(FilePurpose purpose, const std::string& near_path, const std::string& file_name) {
  std::string dir = prefs_.last_directory;
  if (!near_path.empty()) dir = parent_directory(absolute_path(near_path));
  browser_.open(purpose, dir.empty() ? absolute_path(".") : dir, file_name);
}

std::optional<EditorFiles::Choice> EditorFiles::draw_browser() {
  if (!browser_.is_open()) return std::nullopt;
  auto chosen = browser_.draw();
  if (!browser_.directory().empty()) prefs_.last_directory = browser_.directory();
  if (!chosen) return std::nullopt;
  return Choice{browser_.purpose(), *chosen};
}

std::string EditorFiles::set_autosave_seconds(double seconds) {
  prefs_.autosave_seconds = seconds;
  return save();
}

std::string EditorFiles::add_recent(const std::string& path) {
  add_recent_file(prefs_, path);
  return save();
}

std::string EditorFiles::forget_recent(const std::string& path) {
  if (!remove_recent_file(prefs_, path)) return {};
  if (auto error = save(); !error.empty()) return "warning: " + error;
  return "removed " + path + " from the recent files: it no longer exists";
}

std::optional<std::string> EditorFiles::draw_recent_menu(std::string& message) {
  std::optional<std::string> open;
  if (prefs_.recent_files.empty()) {
    ImGui::MenuItem("(no recent files)", nullptr, false, false);
    return open;
  }
  std::vector<std::string> missing;
  for (size_t i = 0; i < prefs_.recent_files.size(); ++i) {
    const std::string& p = prefs_.recent_files[i];
    const fs::path fp(p);
    std::error_code ec;
    const bool exists = fs::is_regular_file(fp, ec);
    if (!exists) missing.push_back(p);
    const std::string label = fp.filename().string() + (exists ? "" : " (missing)");
    ImGui::PushID(static_cast<int>(i));
    // the folder goes in the shortcut column: dimmed, and it tells apart files of the same name
    if (ImGui::MenuItem(label.c_str(), short_folder(fp.parent_path().string()).c_str(), false, exists))
      open = p;
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
      ImGui::SetTooltip("%s%s", p.c_str(),
                        exists ? "" : "\nno longer exists (File > Open Recent > Remove missing files)");
    ImGui::PopID();
  }
  ImGui::Separator();
  if (ImGui::MenuItem("Remove missing files", nullptr, false, !missing.empty())) {
    for (const auto& m : missing) remove_recent_file(prefs_, m);
    message = "removed " + std::to_string(missing.size()) + " missing file" +
              (missing.size() == 1 ? "" : "s") + " from the recent files";
    if (auto error = save(); !error.empty()) message = "warning: " + error;
  }
  if (ImGui::MenuItem("Clear list")) {
    prefs_.recent_files.clear();
    message = "cleared the recent files";
    if (auto error = save(); !error.empty()) message = "warning: " + error;
  }
  return open;
}

}  // namespace cagewrap::app

#endif  // CAGEWRAP_GUI
