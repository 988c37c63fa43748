// The .cagewrap project file: a JSON document naming the character file (relative to the project)
// with its content hash, and holding the cage, the binding parameters, the set edits, the cage
// attachment settings and the keyposes. docs/project-format.md describes every field; this build
// writes kProjectVersion and reads every version up to it (version 1 has no attachment and no
// keyposes: the defaults).
#pragma once

#include <string>
#include <vector>

#include "core/document.h"
#include "core/result.h"

namespace cagewrap {

inline constexpr int kProjectVersion = 2;
inline constexpr const char* kProjectFormat = "cagewrap-project";
inline constexpr const char* kProjectExtension = ".cagewrap";

// Writes atomically (path.tmp beside it, fsync, rename over); the old file survives any failure.
// Refuses to write over the character file, non-finite cage positions, parameters that fail
// validate(), and paths JSON cannot hold (not UTF-8): nothing is written then. The character is
// recorded relative to the project's folder. Does not change `doc` (History::mark_saved does).
Status save_project(const std::string& path, const Document& doc);

struct ProjectLoad {
  Document document;  // project_path = the path given; character_path absolute (resolved against its folder)
  // Content hash mismatch (the character file changed since the save), unknown fields kept or dropped.
  std::vector<std::string> warnings;
  bool character_relocated = false;  // loaded from `character_override`: the file on disk names another
};

// Loads a project and its character. `character_override`, when not empty, replaces the character
// path the project names (the "locate it" answer). Errors name the file and the JSON path
// (`cage.faces[12][3]`). When the character file does not exist the error is kFileNotFound and
// `*missing_character` (if given) is set to the path looked for, so the editor can offer a file
// dialog and call again with the override; it is left empty on every other outcome.
Result<ProjectLoad> load_project(const std::string& path, const std::string& character_override = {},
                                 std::string* missing_character = nullptr);

}  // namespace cagewrap
