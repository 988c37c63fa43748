#include "app/workspace/file_listing.h"

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>

namespace cagewrap {

namespace fs = std::filesystem;

namespace {

char lower(char c) {
  return static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
}
bool is_digit(char c) {
  return c >= '0' && c <= '9';
}

std::string trimmed(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return {};
  return s.substr(b, s.find_last_not_of(" \t\r\n") + 1 - b);
}

std::string extension_list(const std::vector<std::string>& extensions) {
  std::string out;
  for (size_t i = 0; i < extensions.size(); ++i)
    out += (i ? (i + 1 == extensions.size() ? " or " : ", ") : "") + extensions[i];
  return out;
}

}  // namespace

bool matches_extension(const std::string& name, const std::vector<std::string>& extensions) {
  if (extensions.empty()) return true;
  for (const auto& ext : extensions) {
    if (name.size() <= ext.size()) continue;  // ".glb" alone is a hidden file, not a glTF
    bool same = true;
    for (size_t i = 0; i < ext.size() && same; ++i)
      same = lower(name[name.size() - ext.size() + i]) == lower(ext[i]);
    if (same) return true;
  }
  return false;
}

bool natural_less(const std::string& a, const std::string& b) {
  size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (is_digit(a[i]) && is_digit(b[j])) {
      // compare the digit runs by value: skip leading zeros, then longer is larger, then digit by digit
      size_t ia = i, jb = j;
      while (ia < a.size() && a[ia] == '0') ++ia;
      while (jb < b.size() && b[jb] == '0') ++jb;
      size_t ea = ia, eb = jb;
      while (ea < a.size() && is_digit(a[ea])) ++ea;
      while (eb < b.size() && is_digit(b[eb])) ++eb;
      if (ea - ia != eb - jb) return ea - ia < eb - jb;
      for (size_t k = 0; k < ea - ia; ++k)
        if (a[ia + k] != b[jb + k]) return a[ia + k] < b[jb + k];
      i = ea;
      j = eb;
      continue;
    }
    const char ca = lower(a[i]), cb = lower(b[j]);
    if (ca != cb) return ca < cb;
    ++i;
    ++j;
  }
  if (i < a.size() || j < b.size()) return j < b.size();  // the one that ran out first is smaller
  return a < b;  // equal but for case or leading zeros: byte order keeps the order total
}

std::string absolute_path(const std::string& path, const std::string& base) {
  std::string p = path;
  if (!p.empty() && p[0] == '~' && (p.size() == 1 || p[1] == '/')) {
    const char* home = std::getenv("HOME");
    if (home && *home) p = std::string(home) + p.substr(1);
  }
  fs::path out(p);
  if (out.is_relative()) {
    std::error_code ec;
    fs::path b = base.empty() ? fs::current_path(ec) : fs::path(base);
    out = b / out;
  }
  std::string s = out.lexically_normal().string();
  while (s.size() > 1 && s.back() == '/') s.pop_back();
  return s.empty() ? "/" : s;
}

std::string parent_directory(const std::string& dir) {
  std::string abs = absolute_path(dir);
  std::string parent = fs::path(abs).parent_path().string();
  return parent.empty() ? "/" : parent;
}

Error directory_error(const std::string& dir, std::error_code ec) {
  if (ec == std::errc::no_such_file_or_directory)
    return make_error(ErrorCode::kFileNotFound, "the folder " + dir + " does not exist");
  if (ec == std::errc::not_a_directory)
    return make_error(ErrorCode::kInvalidArgument, dir + " is a file, not a folder");
  return make_error(ErrorCode::kFileUnreadable, "cannot read the folder " + dir + " (" + ec.message() + ")");
}

Result<DirectoryListing> list_directory(const std::string& dir, const FileFilter& filter) {
  DirectoryListing listing;
  listing.directory = absolute_path(dir);
  std::error_code ec;
  const fs::file_status status = fs::status(listing.directory, ec);
  if (status.type() == fs::file_type::not_found)
    return directory_error(listing.directory, std::make_error_code(std::errc::no_such_file_or_directory));
  if (ec) return directory_error(listing.directory, ec);
  if (!fs::is_directory(status))
    return directory_error(listing.directory, std::make_error_code(std::errc::not_a_directory));
  fs::directory_iterator it(listing.directory, ec);
  if (ec) return directory_error(listing.directory, ec);
  for (; it != fs::directory_iterator(); it.increment(ec)) {
    if (ec) return directory_error(listing.directory, ec);
    FileEntry e;
    e.name = it->path().filename().string();
    e.is_hidden = !e.name.empty() && e.name[0] == '.';
    if (e.is_hidden && !filter.show_hidden) {
      ++listing.hidden_count;
      continue;
    }
    struct stat st;  // follows links; a broken link keeps no size or time
    const bool have = ::stat(it->path().c_str(), &st) == 0;
    e.is_directory = have && S_ISDIR(st.st_mode);
    if (!e.is_directory && !matches_extension(e.name, filter.extensions)) {
      ++listing.filtered_count;
      continue;
    }
    if (have) {
      if (!e.is_directory) e.size = static_cast<uint64_t>(st.st_size);
      e.modified = static_cast<int64_t>(st.st_mtime);
    }
    listing.entries.push_back(std::move(e));
  }
  if (ec) return directory_error(listing.directory, ec);
  std::sort(listing.entries.begin(), listing.entries.end(), [](const FileEntry& a, const FileEntry& b) {
    if (a.is_directory != b.is_directory) return a.is_directory;
    return natural_less(a.name, b.name);
  });
  return listing;
}

Result<SaveTarget> resolve_save_name(const std::string& dir, const std::string& typed,
                                     const std::vector<std::string>& filter_extensions,
                                     const std::string& default_extension) {
  const std::string name = trimmed(typed);
  if (name.empty()) return make_error(ErrorCode::kInvalidArgument, "type a file name to save in " + dir);
  if (name.back() == '/')
    return make_error(ErrorCode::kInvalidArgument, "\"" + name + "\" names a folder: type a file name");
  const std::string last = fs::path(name).filename().string();  // as typed, before ".." is resolved
  if (last == "." || last == ".." || last == "~")
    return make_error(ErrorCode::kInvalidArgument, "\"" + name + "\" names a folder: type a file name");
  SaveTarget target;
  target.path = absolute_path(name, dir);
  const std::string file = fs::path(target.path).filename().string();
  if (!matches_extension(file, filter_extensions)) target.path += default_extension;
  std::error_code ec;
  const std::string parent = fs::path(target.path).parent_path().string();
  if (!fs::is_directory(parent, ec))
    return make_error(ErrorCode::kFileNotFound,
                      "cannot save " + target.path + ": the folder " + parent + " does not exist");
  const fs::file_status st = fs::status(target.path, ec);
  if (fs::is_directory(st))
    return make_error(ErrorCode::kInvalidArgument, target.path + " is a folder: type a file name");
  target.exists = fs::exists(st);
  return target;
}

std::string format_size(uint64_t bytes) {
  if (bytes < 1024) return std::to_string(bytes) + " B";
  const char* units[] = {"KB", "MB", "GB", "TB", "PB"};
  double v = static_cast<double>(bytes) / 1024.0;
  int u = 0;
  while (v >= 1024.0 && u < 4) {
    v /= 1024.0;
    ++u;
  }
  char buf[32];
  if (v < 10.0)
    std::snprintf(buf, sizeof buf, "%.1f %s", v, units[u]);
  else
    std::snprintf(buf, sizeof buf, "%.0f %s", v, units[u]);
  return buf;
}

std::string format_time(int64_t seconds_since_epoch) {
  const std::time_t t = static_cast<std::time_t>(seconds_since_epoch);
  std::tm tm{};
  if (!localtime_r(&t, &tm)) return "?";
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M", &tm);
  return buf;
}

// ---------------------------------------------------------------- FileBrowserModel

std::string FileBrowserModel::path_of(const FileEntry& e) const {
  return directory() == "/" ? "/" + e.name : directory() + "/" + e.name;
}

bool FileBrowserModel::navigate(const std::string& dir) {
  auto listed = list_directory(absolute_path(dir, directory()), filter_);
  if (!listed) {
    error_ = listed.error().message;
    return false;
  }
  listing_ = std::move(listed).value();
  error_.clear();
  return true;
}

void FileBrowserModel::open(const std::string& dir) {
  const std::string wanted = absolute_path(dir.empty() ? "." : dir);
  if (navigate(wanted)) return;
  const std::string why = error_;
  std::string up = wanted;
  while (up != "/" && !navigate(up = parent_directory(up))) {
  }
  if (directory().empty() && !navigate(absolute_path("."))) navigate("/");
  error_ = why;
}

std::optional<std::string> FileBrowserModel::enter_typed_path(const std::string& typed) {
  const std::string t = trimmed(typed);
  if (t.empty()) return std::nullopt;
  const std::string abs = absolute_path(t, directory());
  std::error_code ec;
  const fs::file_status st = fs::status(abs, ec);
  if (fs::is_directory(st)) {
    navigate(abs);
    return std::nullopt;
  }
  if (!fs::exists(st)) {
    error_ = abs + " does not exist";
    return std::nullopt;
  }
  const std::string name = fs::path(abs).filename().string();
  if (!matches_extension(name, filter_.extensions)) {
    error_ = name + " is not a " + extension_list(filter_.extensions) + " file";
    return std::nullopt;
  }
  navigate(parent_directory(abs));
  return abs;
}

void FileBrowserModel::set_show_hidden(bool show) {
  if (filter_.show_hidden == show) return;
  filter_.show_hidden = show;
  refresh();
}

}  // namespace cagewrap
