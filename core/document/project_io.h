// The .cagewrap project file: a JSON document naming the character file (relative to the project)
// with its content hash, or embedding it, and holding the cage, the binding parameters, the set
// edits, the cage attachment settings, the keyposes and the record of a cached binding.
// docs/project-format.md describes every field; this build reads every version up to
// kProjectVersion (version 1 has no attachment and no keyposes: the defaults) and writes the
// oldest version that holds the document (4 only with deformer layers, 3 when it embeds the character).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/document/document.h"
#include "core/base/result.h"

namespace cagewrap {

inline constexpr int kProjectVersion = 4;
inline constexpr const char* kProjectFormat = "cagewrap-project";
inline constexpr const char* kProjectExtension = ".cagewrap";

// An editor recovery file (app/workspace/autosave.h) is a project file with this record in it.
struct RecoveryInfo {
  std::string project;  // the project the unsaved work belongs to (absolute); "" = never saved
  int64_t pid = 0;      // the editor process that wrote it
  bool operator==(const RecoveryInfo&) const = default;
};

struct SaveOptions {
  // With doc.cache_binding: the document's binding, written beside the project as its cache
  // (core/document/binding_cache.h) just before the project. Without one, a still valid record of the
  // document's (same file, same inputs) is kept, else the project records that nothing is cached.
  const Binding* binding = nullptr;
  // The same for each layer of the stack (index = layer; missing or null = keep a valid record or none);
  // layer i's cache is binding_cache_path(path, i + 1).
  std::vector<const Binding*> layer_bindings;
  // The same for each parametric driver (index = driver_at's number); driver i's cache is
  // driver_binding_cache_path(path, i).
  std::vector<const Binding*> driver_bindings;
  // Writing a recovery file: recorded in it; no binding cache is written then.
  std::optional<RecoveryInfo> recovery;
};

// Writes atomically (path.tmp beside it, fsync, rename over); the old file survives any failure.
// Refuses to write over the character file, non-finite cage positions, parameters that fail
// validate(), and paths JSON cannot hold (not UTF-8): nothing is written then. The character is
// recorded relative to the project's folder (and embedded when doc.embedded_character is set).
// Does not change `doc` (History::mark_saved does).
Status save_project(const std::string& path, const Document& doc, const SaveOptions& options = {});

struct ProjectLoad {
  Document document;  // project_path = the path given; character_path absolute (resolved against its folder)
  // Content hash mismatch (the character file changed since the save), unknown fields kept or dropped.
  std::vector<std::string> warnings;
  bool character_relocated = false;  // loaded from `character_override`: the file on disk names another
  std::optional<RecoveryInfo> recovery;  // set when the file is an editor recovery file
};

// Loads a project and its character (from the project itself when it is embedded: no other file is
// read, `character_override` is ignored). `character_override`, when not empty, replaces the
// character path the project names (the "locate it" answer). Errors name the file and the JSON path
// (`cage.faces[12][3]`). When the character file does not exist the error is kFileNotFound and
// `*missing_character` (if given) is set to the path looked for, so the editor can offer a file
// dialog and call again with the override; it is left empty on every other outcome.
Result<ProjectLoad> load_project(const std::string& path, const std::string& character_override = {},
                                 std::string* missing_character = nullptr);

}  // namespace cagewrap
