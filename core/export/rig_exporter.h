// One export as `cagewrap export` and the editor's File > Export window run it: a format, the
// options of core/export/rig_export.h and an output path in; the files written and a report out (what was
// written, its size, the errors against the live rig as lines a person reads).
//   glb:  export_rig + write_glb (atomic: a failure leaves an existing file as it was)
//   obj:  export_obj_sequence (one file per frame; the skin, or the cage for ExportMode::kCage)
//   json: rig_json (core/export/rig_json.h, docs/export-json.md), written atomically; needs no bind
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/export/rig_export.h"

namespace cagewrap {

enum class ExportFormat { kGlb, kObj, kJson };
const char* export_format_name(ExportFormat f);
bool parse_export_format(const std::string& name, ExportFormat& out);

struct ExportRequest {
  ExportFormat format = ExportFormat::kGlb;
  ExportOptions options;  // mode (glb; obj: kCage writes the cage, any other mode the skin), clips, fps
  std::string out;        // glb: F.glb; json: F.json; obj: F.obj or a folder (obj_sequence_paths)
};

// What the request makes, as a person names it: the mode for glb ("baked-skin"), "skin as OBJ" or
// "cage as OBJ", "rig as JSON".
std::string export_kind_name(const ExportRequest& request);

// Checks the output path before any work: the extension the format writes (.glb, .json; .obj or no
// extension for a folder of OBJ files) and, for a file, that its folder exists. Returns a sentence
// naming the path, or "" when it is fine. (run_export also refuses the document's own files.)
std::string check_export_path(const ExportRequest& request);

struct ExportReport {
  std::string what;  // export_kind_name
  size_t frames = 0, morph_targets = 0, keypose_poses = 0;
  std::vector<std::string> files;  // written
  uint64_t bytes = 0;              // their total size
  ExportResult errors;             // glb: the errors against the rig (its `character` is dropped)
  std::vector<std::string> warnings;
  std::string summary;                   // "92 frames, 92 morph targets, wrote F (40.5 MB)"
  std::vector<std::string> error_lines;  // "error at frames: mean 2.4e-08 m, max 3.6e-07 m", ...
};

// Runs the request. `rig` is the document's rig (Rig::create); it may be null for json only.
// Errors name the file; kCancelled when progress.cancel was set (no file is left behind then).
Result<ExportReport> run_export(const Document& doc, Rig* rig, const ExportRequest& request,
                                const ExportProgress& progress = {});

}  // namespace cagewrap
