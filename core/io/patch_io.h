// Files of parametric drivers (docs/patch-format.md):
// - `.cwpatch`: a JSON document {"format": "cagewrap-patch", "version": 1, "grids": [...]}, each grid
//   {"basis": "bspline"|"bezier", "rows": R, "cols": C, "points": R rows of C [x, y, z]};
// - glTF 2.0 (`.gltf`, `.glb`): the same object (without "format") under `extras.cagewrap_patch`
//   of a node or a mesh (the first found, nodes first). write_patch_gltf stores it on a node of its
//   own so that the file round-trips.
// Every error names the file and, for a control point, its grid, row and column.
#pragma once

#include <string>

#include "core/base/json_reader.h"
#include "core/deform/patch_surface.h"

namespace cagewrap {

inline constexpr const char* kPatchFormat = "cagewrap-patch";
inline constexpr int kPatchFormatVersion = 1;
inline constexpr const char* kPatchGltfKey = "cagewrap_patch";

// The driver as the JSON object of the formats (without "format"; control points as doubles).
Json patch_surface_json(const PatchSurface& surface);
// Reads that object; `file` names the source in messages, `path` is the object's JSON path.
Result<PatchSurface> patch_surface_from_json(const Json& j, const std::string& file,
                                             const std::string& path = "");

// .cwpatch, written atomically.
Status save_patch(const std::string& path, const PatchSurface& surface);
Result<PatchSurface> load_patch(const std::string& path);

// glTF: `.gltf` (JSON text) or `.glb` (a JSON chunk only), written atomically; a scene with one node,
// "patch driver", holding the driver in its extras.
Status write_patch_gltf(const std::string& path, const PatchSurface& surface);
// The driver stored in a glTF file's extras (`.gltf` or `.glb`). Errors: no node or mesh holds one,
// a bad driver (named by its node or mesh), an unreadable file.
Result<PatchSurface> load_patch_gltf(const std::string& path);

// By extension: .gltf/.glb through load_patch_gltf, anything else as .cwpatch.
Result<PatchSurface> load_patch_any(const std::string& path);
Status save_patch_any(const std::string& path, const PatchSurface& surface);

}  // namespace cagewrap
