// The set edits file (docs/edits-format.md): contributing-set edits saved apart from a project, for
// `cagewrap bind --edits` and for moving edits between projects. JSON, versioned: per-point rules
// (`edits`: exclude / include element ids, `only`) and rules by point and face lists (`rules`: a
// SetEditMode applied to skin points and cage polygons, optionally X-mirrored), resolved in order
// against a skin and a cage. Also the per-edit JSON the project file shares.
#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "core/deform/binding.h"
#include "core/cage/cage.h"
#include "core/base/json_reader.h"
#include "core/base/result.h"
#include "core/deform/set_editing.h"

namespace cagewrap {

inline constexpr int kSetEditsVersion = 1;
inline constexpr const char* kSetEditsFormat = "cagewrap-set-edits";

// A rule by lists: `mode` applied to the elements of `faces` for `points` (apply_set_edit).
struct SetEditRule {
  SetEditMode mode = SetEditMode::kRemove;
  std::vector<uint32_t> points;   // skin points
  std::vector<uint32_t> faces;    // cage polygons
  double mirror_tolerance = 0.0;  // > 0: also the X-mirrored points and faces, within this (scene units)
};

struct SetEditsFile {
  std::vector<SetEdit> edits;      // per-point rules, as written
  std::vector<SetEditRule> rules;  // applied after `edits`, in order
  int64_t num_points = -1;         // the skin the file was made for; -1 = not recorded
  int64_t num_elements = -1;       // the cage's control elements; -1 = not recorded
};

// Parses the file; errors name the file and the JSON path (`rules[2].mode is "erase"; expected
// remove, add, only or reset`). Ranges are checked by resolve_set_edits, which knows the skin and cage.
Result<SetEditsFile> load_set_edits(const std::string& path);

// The edit list `file` (loaded from `path`, for messages) describes for this skin and cage: its
// edits, then its rules applied in order; canonical. Errors name the file and the JSON path: a
// recorded point or element count that differs (kTopologyMismatch), a point, element or face out of
// range (kIndexOutOfRange). Warnings: mirrored points and faces with no counterpart, by rule.
struct ResolvedSetEdits {
  std::vector<SetEdit> edits;
  std::vector<std::string> warnings;
};
Result<ResolvedSetEdits> resolve_set_edits(const SetEditsFile& file, const std::string& path,
                                           std::span<const glm::vec3> skin_rest, const Cage& cage);

// The edits of `file` (loaded from `path`) for a parametric driver, whose element ids are its samples:
// per-point edits only (rules by cage faces do not apply), each point below `num_points` and each sample
// below `num_samples`, and the recorded counts (when given) those. Canonical. Errors name the file, the
// point and the sample.
Result<std::vector<SetEdit>> resolve_sample_edits(const SetEditsFile& file, const std::string& path, size_t num_points,
                                                  size_t num_samples);

// Writes `edits` (made canonical) as per-point rules with the skin's point count and the cage's
// element count, atomically (core/base/atomic_write.h).
Status save_set_edits(const std::string& path, std::span<const SetEdit> edits, size_t num_points,
                      size_t num_elements);

// ---- shared with the project file (project_io.cpp)

// {"point": 12, "exclude": [3, 4], "include": []} (and "only": true when set), one line.
std::string set_edit_json(const SetEdit& edit);
// One edit object at `path`; element ids must be below `num_elements` (kIndexOutOfRange otherwise,
// naming `path.exclude[k]`). Fails through the reader (JsonLoadFailure).
SetEdit read_set_edit(const JsonReader& r, const Json& e, const std::string& path,
                      size_t num_elements = std::numeric_limits<size_t>::max());

}  // namespace cagewrap
