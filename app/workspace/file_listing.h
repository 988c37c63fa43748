// The model behind the editor's file browser: list a folder (folders first, then files, in natural
// order), filter files by extension, hide dot files, move between folders, and turn what the user
// typed into the path to open or save. std::filesystem only: app/file_browser.cpp draws it.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "core/base/result.h"

namespace cagewrap {

struct FileEntry {
  std::string name;  // the entry's name in its folder (no path)
  bool is_directory = false;
  bool is_hidden = false;           // the name starts with '.'
  std::optional<uint64_t> size;     // bytes (files only); nullopt when it could not be read
  std::optional<int64_t> modified;  // seconds since the Unix epoch; nullopt when it could not be read
};

struct FileFilter {
  // Lower-case extensions with the dot (".glb"); empty = every file. Matching ignores case.
  std::vector<std::string> extensions;
  bool show_hidden = false;
};

struct DirectoryListing {
  std::string directory;           // absolute and normalised (no "." or ".." components, no trailing '/')
  std::vector<FileEntry> entries;  // folders first, then files, each in natural_less order
  size_t hidden_count = 0;         // entries left out because they are hidden
  size_t filtered_count = 0;       // files left out because of their extension
};

// True when `name` ends with one of `extensions` (case-insensitive); always true for an empty list.
bool matches_extension(const std::string& name, const std::vector<std::string>& extensions);

// Case-insensitive order in which runs of digits compare by value ("take2" < "take10"); names
// equal but for case fall back to byte order, so the order is total.
bool natural_less(const std::string& a, const std::string& b);

// "~" and "~/x" expanded with $HOME; a relative path made absolute against `base` (the current
// folder when empty); "." and ".." resolved lexically; no trailing '/' except for the root.
std::string absolute_path(const std::string& path, const std::string& base = {});

// The folder above `dir` (the root stays the root).
std::string parent_directory(const std::string& dir);

// The error for a folder that could not be listed, naming it: "the folder X does not exist",
// "X is a file, not a folder", "cannot read the folder X (Permission denied)".
Error directory_error(const std::string& dir, std::error_code ec);

// Lists `dir`. Fails (naming the folder) when it does not exist, is not a folder or cannot be
// read. An entry whose details cannot be read (a broken link) is listed without size or time.
Result<DirectoryListing> list_directory(const std::string& dir, const FileFilter& filter);

// What a Save dialog makes of the name typed in folder `dir`: the path to write, with
// `default_extension` appended when the name has none of `filter_extensions` (so "hero" saves
// "hero.cagewrap", "hero.v2" saves "hero.v2.cagewrap"). An absolute or "~" name ignores `dir`.
// Fails (kInvalidArgument) for an empty name, a name ending in '/', or a name that is a folder.
struct SaveTarget {
  std::string path;
  bool exists = false;  // a file is there: ask before replacing it
};
Result<SaveTarget> resolve_save_name(const std::string& dir, const std::string& typed,
                                     const std::vector<std::string>& filter_extensions,
                                     const std::string& default_extension);

// "0 B", "999 B", "1.5 KB", "12 MB", "3.2 GB" (powers of 1024).
std::string format_size(uint64_t bytes);
// Local time "YYYY-MM-DD HH:MM".
std::string format_time(int64_t seconds_since_epoch);

// The state of a browser dialog: the folder shown, its listing, and the last error. Navigation that
// fails keeps the previous folder and listing and sets `error()`; a success clears it.
class FileBrowserModel {
 public:
  FileBrowserModel() = default;
  explicit FileBrowserModel(FileFilter filter) : filter_(std::move(filter)) {}

  // Shows `dir`; when it cannot be listed, falls back to its nearest listable ancestor, then to the
  // current folder, keeping the error about `dir`. Always leaves a directory shown.
  void open(const std::string& dir);
  // Moves to `dir` (absolute, or relative to the folder shown). Returns false (and sets error())
  // when it cannot be listed; the folder shown stays.
  bool navigate(const std::string& dir);
  bool go_up() { return navigate(parent_directory(directory())); }
  // Lists the folder again (after a toggle or a change on disk).
  bool refresh() { return navigate(directory()); }

  // What to do with the path the user typed in the folder field: a folder is entered; an existing
  // file that passes the filter is chosen (returned, absolute); anything else sets error().
  std::optional<std::string> enter_typed_path(const std::string& typed);

  void set_show_hidden(bool show);
  bool show_hidden() const { return filter_.show_hidden; }
  const FileFilter& filter() const { return filter_; }

  const std::string& directory() const { return listing_.directory; }
  const std::vector<FileEntry>& entries() const { return listing_.entries; }
  const DirectoryListing& listing() const { return listing_; }
  std::string path_of(const FileEntry& e) const;
  const std::string& error() const { return error_; }
  void clear_error() { error_.clear(); }

 private:
  FileFilter filter_;
  DirectoryListing listing_;
  std::string error_;
};

}  // namespace cagewrap
