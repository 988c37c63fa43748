// Autosave: a recovery file of the editor's unsaved work, so that a crash or a kill loses at most
// a few minutes. The file is a project file (core/document/project_io.h) with a "recovery" record naming
// the project the work belongs to and the process that wrote it. It is written atomically
// (core/base/atomic_write.h) into the config folder's recovery/ folder, never over the project or the
// character; only while there are unsaved changes, at most once per interval; and removed when the
// work is safe again (saved, discarded, the editor quit cleanly). At the next start the files left
// behind by editors that no longer run are offered back (list_recovery_files).
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/document/document.h"
#include "core/document/project_io.h"
#include "core/base/result.h"

namespace cagewrap {

inline constexpr double kDefaultAutosaveSeconds = 180.0;

// The folder recovery files go in: `config_dir`/recovery ("" when there is no config folder).
std::string recovery_directory(const std::string& config_dir);

class Autosave {
 public:
  using Clock = std::chrono::steady_clock;

  // Recovery files go into `directory` ("" = off), named `name` (default: one per editor process,
  // "recovery-<start time>-<pid>.cagewrap"); `interval_seconds` <= 0 = off. `now`: the start of
  // the first interval.
  Autosave(std::string directory, double interval_seconds, Clock::time_point now = Clock::now(), std::string name = {});

  bool enabled() const { return !directory_.empty() && interval_ > 0; }
  double interval_seconds() const { return interval_; }
  void set_interval_seconds(double seconds) { interval_ = seconds; }
  const std::string& path() const { return path_; }

  // Called often (every frame). Writes the recovery file when the document has unsaved changes
  // (`dirty`) that were not written yet and the interval has passed since the last write (or since
  // the start); removes it when the document is no longer dirty. Returns what it did, for the log:
  // "autosaved ... to <file>", or an error (retried one interval later); nullopt when nothing.
  std::optional<std::string> tick(const Document& doc, bool dirty, Clock::time_point now = Clock::now());
  // Writes the recovery file now (atomically; creates the folder). Refuses a recovery path that is
  // the document's project or character file.
  Status write(const Document& doc);
  // The work is safe (saved, discarded, the editor quits cleanly): removes the recovery file.
  void discard();

 private:
  std::string directory_, path_;
  double interval_;
  Clock::time_point last_write_;
  uint64_t written_revision_ = 0;  // the document revision in the file; 0 = no file
};

struct RecoveryFile {
  std::string path;
  RecoveryInfo info;
  int64_t modified = 0;  // seconds since the Unix epoch: when the work was autosaved
};

struct RecoveryScan {
  std::vector<RecoveryFile> offer;  // newest first: work that was not saved
  // Recovery files older than their project (it was saved afterwards), removed by the scan; and
  // files that could not be read, left alone. One message each, for the log.
  std::vector<std::string> notes;
};

// The recovery files in `directory` to offer at start: those of editors that no longer run (the
// process named in the file is gone, or is this one) and newer than the project they belong to
// (an untitled document's always). `remove_stale`: delete those older than their project.
RecoveryScan list_recovery_files(const std::string& directory, bool remove_stale = true);

// When the file was last written, in seconds since the Unix epoch; nullopt when it cannot be read.
std::optional<int64_t> modified_seconds(const std::string& path);
// "2026-03-05 14:32:07", local time.
std::string format_local_time(int64_t unix_seconds);

}  // namespace cagewrap
