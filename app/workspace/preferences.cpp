#include "app/workspace/preferences.h"

#include <algorithm>
#include <filesystem>
#include <initializer_list>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/base/atomic_write.h"
#include "app/workspace/file_listing.h"

namespace cagewrap {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

namespace {

constexpr const char* kFormat = "cagewrap-preferences";
constexpr int kMinWindow = 200, kMaxWindow = 16384;
constexpr int kMinPanel = 100;  // pixels: a panel narrower than this shows nothing useful
constexpr double kMaxAutosaveSeconds = 24 * 3600;

struct Flag {
  const char* key;
  bool Preferences::*member;
};
constexpr Flag kDisplayFlags[] = {
    {"show_skin", &Preferences::show_skin},         {"show_cage", &Preferences::show_cage},
    {"show_skeleton", &Preferences::show_skeleton}, {"show_grid", &Preferences::show_grid},
    {"wireframe", &Preferences::wireframe},         {"xray", &Preferences::xray},
};

// A path JSON can hold (valid UTF-8); other paths are not remembered.
bool json_can_hold(const std::string& s) {
  try {
    (void)Json(s).dump();
    return true;
  } catch (const Json::exception&) {
    return false;
  }
}

// Reads the fields this build knows from `j` into `p`, erasing them from `j` (what is left is kept
// for the next save). Bad fields keep their default and add a warning naming them.
void read_known_fields(Json& j, Preferences& p, const std::string& path, std::vector<std::string>& warnings) {
  auto bad = [&](const std::string& field, const std::string& why) {
    warnings.push_back(path + ": " + field + " " + why + "; using the default");
  };
  j.erase("format");
  j.erase("version");
  if (auto it = j.find("recent_files"); it != j.end()) {
    if (!it->is_array()) {
      bad("recent_files", "is not a list");
    } else {
      for (const auto& r : *it) {
        if (!r.is_string() || r.get<std::string>().empty()) continue;  // skipped quietly: a list stays usable
        if (p.recent_files.size() < kMaxRecentFiles &&
            std::find(p.recent_files.begin(), p.recent_files.end(), r.get<std::string>()) ==
                p.recent_files.end())
          p.recent_files.push_back(r.get<std::string>());
      }
    }
    j.erase(it);
  }
  if (auto it = j.find("last_directory"); it != j.end()) {
    if (it->is_string())
      p.last_directory = it->get<std::string>();
    else
      bad("last_directory", "is not a string");
    j.erase(it);
  }
  // an object of whole numbers of pixels: {"width": 1600, "height": 900}
  auto read_pixels = [&](const char* group, std::initializer_list<std::pair<const char*, int Preferences::*>> fields, int lo) {
    auto it = j.find(group);
    if (it == j.end()) return;
    if (!it->is_object()) {
      bad(group, "is not an object");
      j.erase(it);
      return;
    }
    for (auto [key, member] : fields) {
      auto f = it->find(key);
      if (f == it->end()) continue;
      if (f->is_number_integer() && f->get<int64_t>() >= lo && f->get<int64_t>() <= kMaxWindow)
        p.*member = f->get<int>();
      else
        bad(std::string(group) + "." + key, "is not a whole number from " + std::to_string(lo) + " to " + std::to_string(kMaxWindow));
      it->erase(f);
    }
    if (it->empty()) j.erase(it);
  };
  read_pixels("window", {{"width", &Preferences::window_width}, {"height", &Preferences::window_height}}, kMinWindow);
  read_pixels("panels", {{"left", &Preferences::panel_left}, {"right", &Preferences::panel_right}, {"bottom", &Preferences::panel_bottom}},
              kMinPanel);
  if (auto it = j.find("autosave"); it != j.end()) {
    if (it->is_object()) {
      if (auto f = it->find("interval_seconds"); f != it->end()) {
        if (f->is_number() && f->get<double>() >= 0 && f->get<double>() <= kMaxAutosaveSeconds)
          p.autosave_seconds = f->get<double>();
        else
          bad("autosave.interval_seconds", "is not a number of seconds from 0 (never) to " +
                                               std::to_string(static_cast<int>(kMaxAutosaveSeconds)));
        it->erase(f);
      }
      if (it->empty()) j.erase(it);
    } else {
      bad("autosave", "is not an object");
      j.erase(it);
    }
  }
  if (auto it = j.find("display"); it != j.end()) {
    if (it->is_object()) {
      for (const Flag& flag : kDisplayFlags) {
        auto f = it->find(flag.key);
        if (f == it->end()) continue;
        if (f->is_boolean())
          p.*flag.member = f->get<bool>();
        else
          bad(std::string("display.") + flag.key, "is not true or false");
        it->erase(f);
      }
      if (it->empty()) j.erase(it);
    } else {
      bad("display", "is not an object");
      j.erase(it);
    }
  }
}

// Adds to `dst` what `src` has and `dst` lacks, recursively into objects both hold.
void add_missing(Json& dst, const Json& src) {
  for (auto it = src.begin(); it != src.end(); ++it) {
    auto d = dst.find(it.key());
    if (d == dst.end())
      dst[it.key()] = it.value();
    else if (d->is_object() && it->is_object())
      add_missing(*d, *it);
  }
}

}  // namespace

bool operator==(const Preferences& a, const Preferences& b) {
  bool flags = true;
  for (const Flag& f : kDisplayFlags) flags = flags && a.*f.member == b.*f.member;
  return flags && a.recent_files == b.recent_files && a.window_width == b.window_width &&
         a.window_height == b.window_height && a.last_directory == b.last_directory &&
         a.panel_left == b.panel_left && a.panel_right == b.panel_right && a.panel_bottom == b.panel_bottom &&
         a.autosave_seconds == b.autosave_seconds &&
         a.preserved_fields == b.preserved_fields;
}

void add_recent_file(Preferences& prefs, const std::string& path) {
  const std::string abs = absolute_path(path);
  remove_recent_file(prefs, abs);
  prefs.recent_files.insert(prefs.recent_files.begin(), abs);
  if (prefs.recent_files.size() > kMaxRecentFiles) prefs.recent_files.resize(kMaxRecentFiles);
}

bool remove_recent_file(Preferences& prefs, const std::string& path) {
  auto& r = prefs.recent_files;
  const auto old = r.size();
  r.erase(std::remove(r.begin(), r.end(), path), r.end());
  return r.size() != old;
}

std::string preferences_directory(const char* override_dir, const char* xdg_config_home, const char* home) {
  auto set = [](const char* s) { return s && *s; };
  if (set(override_dir)) return absolute_path(override_dir);
  if (set(xdg_config_home) && xdg_config_home[0] == '/')
    return absolute_path(std::string(xdg_config_home) + "/cagewrap");
  if (set(home)) return absolute_path(std::string(home) + "/.config/cagewrap");
  return {};
}

std::string preferences_directory() {
  return preferences_directory(std::getenv("CAGEWRAP_CONFIG_DIR"), std::getenv("XDG_CONFIG_HOME"),
                               std::getenv("HOME"));
}

std::string preferences_path() {
  const std::string dir = preferences_directory();
  return dir.empty() ? std::string() : dir + "/preferences.json";
}

PreferencesLoad load_preferences(const std::string& path) {
  PreferencesLoad out;
  std::error_code ec;
  if (path.empty() || !fs::exists(path, ec)) return out;  // first run: the defaults, quietly
  if (!fs::is_regular_file(path, ec)) {
    out.warnings.push_back(path + ": not a file; using the default preferences");
    return out;
  }
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  if (in) text << in.rdbuf();
  if (!in || in.bad()) {
    out.warnings.push_back(path + ": cannot read the preferences; using the defaults");
    return out;
  }
  Json j = Json::parse(text.str(), nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded() || !j.is_object()) {
    out.warnings.push_back(
        path +
        ": not a valid preferences file (corrupt JSON); using the defaults, and it will be "
        "replaced when preferences are saved");
    return out;
  }
  if (auto f = j.find("format"); f != j.end() && (!f->is_string() || f->get<std::string>() != kFormat)) {
    out.warnings.push_back(path + ": not a cagewrap preferences file (\"format\" is not \"" + kFormat +
                           "\"); using the defaults");
    return out;
  }
  read_known_fields(j, out.prefs, path, out.warnings);
  if (!j.empty()) out.prefs.preserved_fields = j.dump();
  return out;
}

std::string preferences_to_json(const Preferences& prefs) {
  Json j = Json::object();
  j["format"] = kFormat;
  j["version"] = kPreferencesVersion;
  j["recent_files"] = Json::array();
  for (const auto& r : prefs.recent_files)
    if (json_can_hold(r)) j["recent_files"].push_back(r);
  j["window"] = {{"width", prefs.window_width}, {"height", prefs.window_height}};
  j["panels"] = {{"left", prefs.panel_left}, {"right", prefs.panel_right}, {"bottom", prefs.panel_bottom}};
  j["last_directory"] = json_can_hold(prefs.last_directory) ? prefs.last_directory : std::string();
  Json display = Json::object();
  for (const Flag& f : kDisplayFlags) display[f.key] = prefs.*f.member;
  j["display"] = display;
  j["autosave"] = {{"interval_seconds", prefs.autosave_seconds}};
  if (!prefs.preserved_fields.empty()) {  // a newer build's fields, known ones taking precedence
    Json kept = Json::parse(prefs.preserved_fields, nullptr, false);
    if (kept.is_object()) add_missing(j, kept);
  }
  return j.dump(2) + "\n";
}

Status save_preferences(const std::string& path, const Preferences& prefs) {
  if (path.empty())
    return make_error(ErrorCode::kWrite, "no config folder to save the preferences in (HOME is not set)");
  std::error_code ec;
  const fs::path dir = fs::path(path).parent_path();
  if (!dir.empty()) fs::create_directories(dir, ec);
  if (ec)
    return make_error(ErrorCode::kWrite, path + ": could not save the preferences (creating the folder " +
                                             dir.string() + ": " + ec.message() + ")");
  return write_file_atomic(path, preferences_to_json(prefs));
}

}  // namespace cagewrap
