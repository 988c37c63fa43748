#include "app/workspace/autosave.h"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <ctime>
#include <filesystem>
#include <fstream>

#include "core/base/json_reader.h"

namespace cagewrap {

namespace fs = std::filesystem;

namespace {

// Whether the file was modified at or after `than` (nanoseconds counted: a save and an autosave in
// the same second are ordered).
bool modified_not_before(const std::string& path, const std::string& than) {
  struct stat a, b;
  if (::stat(path.c_str(), &a) != 0 || ::stat(than.c_str(), &b) != 0) return false;
  return a.st_mtim.tv_sec != b.st_mtim.tv_sec ? a.st_mtim.tv_sec > b.st_mtim.tv_sec
                                              : a.st_mtim.tv_nsec >= b.st_mtim.tv_nsec;
}

// A cagewrap editor with this process id is running (not this process).
bool editor_running(int64_t pid) {
  if (pid <= 0 || pid == ::getpid()) return false;
  if (::kill(static_cast<pid_t>(pid), 0) != 0 && errno != EPERM) return false;
  std::ifstream comm("/proc/" + std::to_string(pid) + "/comm");
  std::string name;
  std::getline(comm, name);
  return !comm || name == "cagewrap";  // without /proc, a live process is taken to be one
}

bool same_path(const std::string& a, const std::string& b) {
  if (a.empty() || b.empty()) return false;
  std::error_code ec;
  return fs::absolute(a).lexically_normal() == fs::absolute(b).lexically_normal() || fs::equivalent(a, b, ec);
}

}  // namespace

std::optional<int64_t> modified_seconds(const std::string& path) {
  struct stat st;
  if (::stat(path.c_str(), &st) != 0) return std::nullopt;
  return static_cast<int64_t>(st.st_mtim.tv_sec);
}

std::string recovery_directory(const std::string& config_dir) {
  return config_dir.empty() ? std::string() : (fs::path(config_dir) / "recovery").string();
}

Autosave::Autosave(std::string directory, double interval_seconds, Clock::time_point now, std::string name)
    : directory_(std::move(directory)), interval_(interval_seconds), last_write_(now) {
  if (name.empty())
    name = "recovery-" + std::to_string(std::time(nullptr)) + "-" + std::to_string(::getpid()) + kProjectExtension;
  if (!directory_.empty()) path_ = (fs::path(directory_) / name).string();
}

std::optional<std::string> Autosave::tick(const Document& doc, bool dirty, Clock::time_point now) {
  if (!enabled()) return std::nullopt;
  if (!dirty) {
    if (written_revision_ == 0) return std::nullopt;
    discard();
    return "the work is saved: removed the recovery file " + path_;
  }
  if (doc.revision == written_revision_ || now - last_write_ < std::chrono::duration<double>(interval_))
    return std::nullopt;
  last_write_ = now;  // a failure is retried one interval later, not every frame
  const auto t0 = Clock::now();
  if (auto s = write(doc); !s) return "error: autosave failed: " + s.error().message;
  char ms[32];
  std::snprintf(ms, sizeof ms, "%.0f ms", std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
  return "autosaved the unsaved work to " + path_ + " (" + ms + ")";
}

Status Autosave::write(const Document& doc) {
  if (path_.empty()) return make_error(ErrorCode::kWrite, "no config folder for the recovery file (HOME is not set)");
  if (same_path(path_, doc.project_path) || same_path(path_, doc.character_path))
    return make_error(ErrorCode::kInvalidArgument, path_ + ": the recovery file would replace the project or the character");
  std::error_code ec;
  fs::create_directories(directory_, ec);
  if (ec) return make_error(ErrorCode::kWrite, path_ + ": could not create the folder " + directory_ + " (" + ec.message() + ")");
  SaveOptions options;
  options.recovery = RecoveryInfo{doc.project_path.empty() ? std::string() : fs::absolute(doc.project_path).lexically_normal().string(),
                                  static_cast<int64_t>(::getpid())};
  if (auto s = save_project(path_, doc, options); !s) return s;
  written_revision_ = doc.revision;
  return Ok{};
}

void Autosave::discard() {
  if (!path_.empty()) {
    std::error_code ec;
    fs::remove(path_, ec);
  }
  written_revision_ = 0;
}

RecoveryScan list_recovery_files(const std::string& directory, bool remove_stale) {
  RecoveryScan scan;
  std::error_code ec;
  if (directory.empty() || !fs::is_directory(directory, ec)) return scan;
  for (const auto& entry : fs::directory_iterator(directory, ec)) {
    const std::string path = entry.path().string();
    if (entry.path().extension() != kProjectExtension || !entry.is_regular_file(ec)) continue;
    auto json = read_json_file(path);
    if (!json || !json->is_object() || !json->contains("recovery") || !(*json)["recovery"].is_object()) {
      scan.notes.push_back("warning: " + path + ": not a readable recovery file; left alone");
      continue;
    }
    const Json& r = (*json)["recovery"];
    RecoveryFile f;
    f.path = path;
    f.info.project = r.value("project", std::string());
    f.info.pid = r.contains("pid") && r["pid"].is_number_integer() ? r["pid"].get<int64_t>() : 0;
    f.modified = modified_seconds(path).value_or(0);
    if (editor_running(f.info.pid)) continue;  // another editor's work in progress
    if (!f.info.project.empty() && modified_not_before(f.info.project, path)) {
      if (remove_stale) fs::remove(path, ec);
      scan.notes.push_back("the recovery file " + path + " is older than its project " + f.info.project +
                           (remove_stale ? " (saved since): removed" : " (saved since)"));
      continue;
    }
    scan.offer.push_back(std::move(f));
  }
  std::sort(scan.offer.begin(), scan.offer.end(),
            [](const RecoveryFile& a, const RecoveryFile& b) { return a.modified > b.modified; });
  return scan;
}

std::string format_local_time(int64_t unix_seconds) {
  const std::time_t t = static_cast<std::time_t>(unix_seconds);
  std::tm tm{};
  localtime_r(&t, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%d %H:%M:%S", &tm);
  return text;
}

}  // namespace cagewrap
