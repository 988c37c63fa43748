#include "core/export/rig_exporter.h"

#include <cstdio>
#include <filesystem>

#include "core/base/atomic_write.h"
#include "core/io/gltf_writer.h"
#include "core/geometry/mesh_io.h"
#include "core/rig/fidelity.h"
#include "core/export/rig_json.h"

namespace cagewrap {

namespace fs = std::filesystem;

const char* export_format_name(ExportFormat f) {
  switch (f) {
    case ExportFormat::kGlb:
      return "glb";
    case ExportFormat::kObj:
      return "obj";
    case ExportFormat::kJson:
      return "json";
  }
  return "?";
}

bool parse_export_format(const std::string& name, ExportFormat& out) {
  for (ExportFormat f : {ExportFormat::kGlb, ExportFormat::kObj, ExportFormat::kJson})
    if (name == export_format_name(f)) {
      out = f;
      return true;
    }
  return false;
}

std::string export_kind_name(const ExportRequest& request) {
  switch (request.format) {
    case ExportFormat::kGlb:
      return export_mode_name(request.options.mode);
    case ExportFormat::kObj:
      return request.options.mode == ExportMode::kCage ? "cage as OBJ" : "skin as OBJ";
    case ExportFormat::kJson:
      return "rig as JSON";
  }
  return "?";
}

std::string check_export_path(const ExportRequest& request) {
  const std::string& out = request.out;
  if (out.empty()) return "no output file given";
  const fs::path path(out);
  const std::string ext = path.extension().string();
  bool folder = false;
  switch (request.format) {
    case ExportFormat::kGlb:
      if (!has_extension(out, ".glb")) return out + ": a glb export is written to a .glb file";
      break;
    case ExportFormat::kJson:
      if (!has_extension(out, ".json")) return out + ": a json export is written to a .json file";
      break;
    case ExportFormat::kObj:
      folder = !has_extension(out, ".obj");
      if (folder && !ext.empty() && !fs::is_directory(path))
        return out + ": an obj export is written to F.obj (as F_<clip>_<frame>.obj) or into a folder";
      break;
  }
  std::error_code ec;
  if (!folder && fs::is_directory(path, ec)) return out + ": is a folder, not a file";
  const fs::path parent = path.parent_path();
  if (!folder && !parent.empty() && !fs::is_directory(parent, ec))
    return out + ": the folder " + parent.string() + " does not exist";
  return "";
}

namespace {

std::string megabytes(uint64_t bytes) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f MB", double(bytes) / 1e6);
  return buf;
}

// In the file's units (metres for a character of plausible size, else "scene units", core/rig/fidelity.h),
// with the largest error as a share of the skin's diagonal.
std::string error_line(const std::string& what, const ExportError& e, double diagonal) {
  char buf[256];
  const std::string units = scene_units(diagonal);
  std::snprintf(buf, sizeof buf, "%-46s mean %.3g %s, max %.3g %s (%.2f%% of the diagonal)", (what + ":").c_str(), e.mean,
                units.c_str(), e.max, units.c_str(), diagonal > 0 ? 100 * e.max / diagonal : 0.0);
  return buf;
}

uint64_t file_size_or_zero(const std::string& path) {
  std::error_code ec;
  const auto n = fs::file_size(path, ec);
  return ec ? 0 : n;
}

Result<ExportReport> run_glb(const Document& doc, Rig& rig, const ExportRequest& request,
                             const ExportProgress& progress) {
  auto result = export_rig(doc, rig, request.options, progress);
  if (!result) return result.error();
  // a character kept in its file's units and axes (--keep-units): the glTF is metres, Y up all the same
  if (doc.character && doc.character->to_metres)
    if (auto s = add_root_node(result->character, "cagewrap_to_metres", *doc.character->to_metres); !s) return s.error();
  if (progress.on_progress) progress.on_progress("writing", 0, 1, 1.0);
  if (auto s = write_glb(request.out, result->character, "cagewrap export",
                           result->quantization ? &*result->quantization : nullptr); !s) return s.error();
  ExportReport r;
  r.frames = result->frames;
  r.morph_targets = result->morph_targets;
  r.keypose_poses = result->keypose_poses;
  r.files = {request.out};
  r.bytes = file_size_or_zero(request.out);
  r.warnings = result->warnings;
  r.summary = std::to_string(r.frames) + " frames, " + std::to_string(r.morph_targets) +
              " morph targets, wrote " + request.out + " (" + megabytes(r.bytes) + ")";
  const ExportMode mode = request.options.mode;
  const std::string poses = std::to_string(r.keypose_poses) + " keypose poses";
  if (mode == ExportMode::kBakedSkin) {
    r.error_lines.push_back(error_line("error at frames, skeleton only", result->fitted, result->diagonal));
    r.error_lines.push_back("skin: up to " + std::to_string(result->influences) + " joints a vertex (asked " +
                            std::to_string(request.options.max_influences) + ")");
  }
  if (mode == ExportMode::kCage) {
    r.error_lines.push_back(error_line("cage error at frames", result->at_frames, result->diagonal));
    if (r.keypose_poses)
      r.error_lines.push_back(error_line("cage error at " + poses + " (left out)", result->at_keyposes, result->diagonal));
  } else {
    r.error_lines.push_back(error_line("error at frames", result->at_frames, result->diagonal));
    r.error_lines.push_back(error_line("error between frames", result->between_frames, result->diagonal));
    if (result->vs_file.samples)
      r.error_lines.push_back(error_line("against the file's own skinning, at frames", result->vs_file, result->diagonal));
  }
  if (mode == ExportMode::kBakedSkin && r.keypose_poses)
    r.error_lines.push_back(error_line("error at " + poses + ", skeleton only", result->at_keyposes, result->diagonal));
  if (mode != ExportMode::kCage) {
    const int asked = corrective_targets(request.options);
    if (request.options.correctives == ExportOptions::Correctives::kPoseDriven) {
      std::string names;
      for (size_t k = 0; k < result->pose_features.size() && k < 4; ++k) names += (k ? ", " : "") + result->pose_features[k];
      if (result->pose_features.size() > 4) names += ", ...";
      r.error_lines.push_back("correctives: " + std::to_string(r.morph_targets) + " pose-driven targets (of " +
                              std::to_string(result->residual_rank) + " components), weighted by " +
                              std::to_string(result->pose_features.size()) + " joint-angle ramps (" + names + ")");
    } else if (asked > 0) {
      char line[256];
      std::snprintf(line, sizeof line, "correctives: %zu of the residuals' %zu components (at most %d), largest residual left %.3g %s",
                    r.morph_targets, result->residual_rank, asked, result->basis_error, scene_units(result->diagonal).c_str());
      r.error_lines.push_back(line);
    } else {
      r.error_lines.push_back("correctives: one per frame (exact at the frames)");
    }
    for (const ExportResult::ClipErrors& c : result->clips) {
      r.error_lines.push_back(error_line("clip '" + c.name + "' (" + std::to_string(c.frames) + " frames" +
                                             (c.held_out ? ", held out of the fit" : "") + ") at frames",
                                         c.at_frames, result->diagonal));
      if (c.between_frames.samples)
        r.error_lines.push_back(error_line("clip '" + c.name + "' between frames", c.between_frames, result->diagonal));
      if (c.held_out && c.fitted.samples)
        r.error_lines.push_back(error_line("clip '" + c.name + "' at frames, skeleton alone", c.fitted, result->diagonal));
    }
  }
  if (request.options.optimize) {
    char line[160];
    std::snprintf(line, sizeof line, "GPU order: vertex cache misses per triangle %.3f before, %.3f after (32 entries)",
                  result->acmr_before, result->acmr_after);
    r.error_lines.push_back(line);
  }
  if (result->quantization) {
    double step = 0.0;
    for (const GlbQuantization::Dequant& d : result->quantization->skins) step = std::max(step, d.step);
    for (const auto& [node, d] : result->quantization->nodes) step = std::max(step, d.step);
    char line[200];
    std::snprintf(line, sizeof line, "quantized (KHR_mesh_quantization): positions in steps of %.3g %s, normals 8-bit, weights 16-bit",
                  step, scene_units(result->diagonal).c_str());
    r.error_lines.push_back(line);
  }
  const auto& z = result->sizes;
  r.error_lines.push_back("sizes: mesh " + megabytes(z.mesh) + ", skin " + megabytes(z.skin) + ", morph targets " + megabytes(z.targets) +
                          ", animation " + megabytes(z.animation) + " (file " + megabytes(r.bytes) + ")");
  result->character = Character{};
  r.errors = std::move(result).value();
  return r;
}

Result<ExportReport> run_obj(const Document& doc, Rig& rig, const ExportRequest& request,
                             const ExportProgress& progress) {
  auto seq = export_obj_sequence(doc, rig, request.options, request.out, progress);
  if (!seq) return seq.error();
  ExportReport r;
  r.frames = seq->frames;
  r.files = seq->files;
  r.bytes = seq->bytes;
  r.summary = std::to_string(r.frames) + " frames, wrote " + std::to_string(r.files.size()) + " OBJ files";
  if (!r.files.empty())
    r.summary += " " + r.files.front() +
                 (r.files.size() > 1 ? " .. " + fs::path(r.files.back()).filename().string() : "");
  r.summary += " (" + megabytes(r.bytes) + ")";
  r.error_lines.push_back("exact: the live rig's " +
                          std::string(request.options.mode == ExportMode::kCage ? "posed cage" : "skin") +
                          " at every frame");
  return r;
}

Result<ExportReport> run_json(const Document& doc, const Rig* rig, const ExportRequest& request) {
  auto json = rig_json(doc, rig ? rig->attachment() : nullptr);
  if (!json) return json.error();
  if (auto s = write_file_atomic(request.out, json->text); !s) return s.error();
  ExportReport r;
  r.files = {request.out};
  r.bytes = file_size_or_zero(request.out);
  r.summary = std::to_string(json->vertices) + " cage vertices, " + std::to_string(json->faces) + " faces, " +
              std::to_string(json->keypose_sets) + " keypose set(s), wrote " + request.out + " (" +
              megabytes(r.bytes) + ")";
  if (!json->attached)
    r.warnings.push_back("the character has no skin: the cage follows no skeleton (attachment null)");
  return r;
}

}  // namespace

Result<ExportReport> run_export(const Document& doc, Rig* rig, const ExportRequest& request,
                                const ExportProgress& progress) {
  if (auto bad = check_export_path(request); !bad.empty())
    return make_error(ErrorCode::kInvalidArgument, bad);
  for (const std::string& mine : {doc.character_path, doc.project_path}) {
    std::error_code ec;
    if (!mine.empty() && fs::exists(request.out, ec) && fs::equivalent(request.out, mine, ec))
      return make_error(ErrorCode::kInvalidArgument,
                        request.out + ": is the document's own " +
                            (mine == doc.character_path ? "character" : "project") +
                            " file; export elsewhere");
  }
  if (request.format == ExportFormat::kJson) {
    size_t layers = 0;
    for (const DeformerLayer& l : doc.layers) layers += l.muted ? 0 : 1;
    if (layers)  // a JSON rig describes one cage: the other deformers would be lost without a word
      return make_error(ErrorCode::kUnsupportedFormat,
                        request.out + ": the rig JSON describes one cage, and this project has " + std::to_string(layers) +
                            " more deformer(s): export a baked mode (glb or obj), which carries the whole stack");
    for (size_t i = 0; i < driver_count(doc); ++i) {
      const DriverRef d = driver_at(doc, i);
      if (driver_moves_skin(doc, i) && (!(d.driver->posed == d.driver->rest) || !d.place->keyposes.empty()))
        return make_error(ErrorCode::kUnsupportedFormat,
                          request.out + ": the rig JSON describes one cage, and this project's parametric driver" +
                              (driver_count(doc) > 1 ? " '" + driver_name(doc, i) + "'" : std::string()) +
                              " moves the skin: export a baked mode (glb or obj), which carries it");
    }
  }
  if ((request.format != ExportFormat::kJson || doc.attachment.mode == AttachmentMode::kFitted) && !rig)
    return make_error(ErrorCode::kInvalidArgument, "the document's rig is not bound yet");
  Result<ExportReport> r = request.format == ExportFormat::kGlb   ? run_glb(doc, *rig, request, progress)
                           : request.format == ExportFormat::kObj ? run_obj(doc, *rig, request, progress)
                                                                  : run_json(doc, rig, request);
  if (r) r->what = export_kind_name(request);
  return r;
}

}  // namespace cagewrap
