// cagewrap export --project P [--format glb|obj|json] [--mode baked-animation|baked-skin|cage]
//                 [--clips a,b] [--fps 30] [--keypose-steps 3] --out OUT
// Writes a saved project's rig for engines and other tools: binary glTF (core/export/rig_export.h says
// what each mode holds), the skin (or cage) per frame as OBJ files, or the cage, its attachment
// and its keyposes as JSON (docs/export-json.md). Reports sizes, times and errors against the live
// rig; long bakes show their progress on stderr when it is a terminal.
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "app/cli_common.h"
#include "app/commands.h"
#include "core/document/project_io.h"
#include "core/export/rig_exporter.h"

namespace cagewrap::app {

namespace {

// "posing 12/92  13%" rewritten in place on stderr, when stderr is a terminal.
ExportProgress terminal_export_progress() {
  ExportProgress p;
  if (!isatty(STDERR_FILENO)) return p;
  auto last = std::make_shared<std::pair<std::string, int>>("", -1);
  p.on_progress = [last](const char* stage, size_t done, size_t total, double share) {
    const int pct = static_cast<int>(share * 100.0);
    if (last->first == stage && last->second == pct && done < total) return;
    *last = {stage, pct};
    std::fprintf(stderr, "\rexport: %-11s %zu/%zu %3d%%   ", stage, done, total, pct);
    std::fflush(stderr);
  };
  return p;
}

}  // namespace

void add_export_command(CLI::App& app, int& exit_code) {
  struct Args {
    std::string project, format = "glb", mode, out;
    std::vector<std::string> clips;
    double fps = 30.0;
    int keypose_steps = ExportOptions{}.keypose_steps;
    int max_targets = -1;
    double max_error = 0.0;
    int max_influences = 4;
    bool optimize = false;
    bool quantize = false;
    std::string correctives = "baked", hold_out;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "export", "write a project's rig for engines and other tools (.glb, OBJ per frame, JSON)");
  cmd->add_option("--project", args->project, "project file (.cagewrap)")->required();
  cmd->add_option(
         "--format", args->format,
         "glb (binary glTF), obj (the skin per frame, or the cage with --mode cage) or json (the cage, its "
         "attachment to the skeleton and its keyposes: docs/export-json.md)")
      ->capture_default_str();
  cmd->add_option(
      "--mode", args->mode,
      "glb: baked-animation (skin + one morph target per frame), baked-skin (fitted LBS weights + "
      "corrective morph targets) or cage (the cage skinned to the skeleton); obj: cage writes the cage");
  cmd->add_option("--clips", args->clips, "clips to export, by name or index (default: all)")->delimiter(',');
  cmd->add_option("--fps", args->fps, "frames sampled per second of each clip")->capture_default_str();
  cmd->add_option(
         "--keypose-steps", args->keypose_steps,
         "poses per keypose key, swept from rest to the key, that baked-skin fits and every glb mode "
         "measures (0: none)")
      ->capture_default_str();
  cmd->add_option("--max-targets", args->max_targets,
                  "glb skin modes: at most this many corrective morph targets, the principal components of every "
                  "frame's residual, each frame keyed with its weights (default: " + std::to_string(kDefaultMaxTargets) +
                      " for baked-skin, one per frame for baked-animation; 0: one per frame, exact at the frames)");
  cmd->add_option("--max-error", args->max_error,
                  "with compressed targets: the fewest (up to --max-targets) whose largest error over the frames is "
                  "within this length, in the file's units");
  cmd->add_option("--max-influences", args->max_influences,
                  "baked-skin: fitted joints per vertex, 4 (every runtime) or 8 (JOINTS_1/WEIGHTS_1 too, for engines that "
                  "read a second set)")
      ->capture_default_str();
  cmd->add_flag("--optimize", args->optimize,
                "glb: reorder each mesh for the GPU (vertex cache, then fetch order; libmeshoptimizer), writing each "
                "vertex's source index as _CAGEWRAP_SOURCE_INDEX");
  cmd->add_flag("--quantize", args->quantize,
                "glb: KHR_mesh_quantization: 16-bit positions and morph targets, 8-bit normals, 16-bit weights (about a "
                "third smaller; the errors reported are measured on the quantized file)");
  cmd->add_option("--correctives", args->correctives,
                  "baked-skin: baked (the targets keyed per frame in each clip) or pose-driven (each target driven by "
                  "one joint angle, the drivers in the mesh's extras so an engine corrects new animations; "
                  "docs/pose-correctives.md)")
      ->capture_default_str();
  cmd->add_option("--hold-out", args->hold_out,
                  "pose-driven: a clip (name or index, one of those exported) left out of every fit and still "
                  "exported, so its errors are those of an animation the export never saw");
  cmd->add_option("--out", args->out,
                  "glb: F.glb; obj: F.obj (writes F_<clip>_<frame>.obj beside it) or a folder; json: F.json")
      ->required();
  cmd->callback([args, &exit_code] {
    exit_code = 1;
    const std::string& P = args->project;
    const auto start = std::chrono::steady_clock::now();
    ExportRequest request;
    if (!parse_export_format(args->format, request.format)) {
      std::fprintf(stderr, "error: --format '%s' should be glb, obj or json\n", args->format.c_str());
      return;
    }
    if (!args->mode.empty() && !parse_export_mode(args->mode, request.options.mode)) {
      std::fprintf(stderr, "error: --mode '%s' should be baked-animation, baked-skin or cage\n",
                   args->mode.c_str());
      return;
    }
    if (request.format == ExportFormat::kGlb && args->mode.empty()) {
      std::fprintf(stderr, "error: --format glb needs --mode baked-animation, baked-skin or cage\n");
      return;
    }
    if (request.format == ExportFormat::kJson && !args->mode.empty()) {
      std::fprintf(stderr,
                   "error: --mode has no meaning for --format json (it describes the cage rig itself)\n");
      return;
    }
    if (request.format == ExportFormat::kObj && args->mode.empty())
      request.options.mode = ExportMode::kBakedAnimation;
    if (!(args->fps > 0.0) || !std::isfinite(args->fps) || args->fps > 1000.0) {
      std::fprintf(stderr, "error: --fps must be a number of frames per second in (0, 1000]\n");
      return;
    }
    if (args->keypose_steps < 0 || args->keypose_steps > 100) {
      std::fprintf(stderr, "error: --keypose-steps must be a whole number from 0 to 100\n");
      return;
    }
    if (args->max_targets < -1 || args->max_targets > 4096) {
      std::fprintf(stderr, "error: --max-targets must be a whole number from 0 (one per frame) to 4096\n");
      return;
    }
    if (!(args->max_error >= 0.0) || !std::isfinite(args->max_error)) {
      std::fprintf(stderr, "error: --max-error must be a length >= 0 in the file's units\n");
      return;
    }
    if (args->max_error > 0.0 && args->max_targets == 0) {
      std::fprintf(stderr, "error: --max-error picks among compressed targets; --max-targets 0 keeps one per frame\n");
      return;
    }
    if ((args->max_targets >= 0 || args->max_error > 0.0) &&
        (request.format != ExportFormat::kGlb || request.options.mode == ExportMode::kCage)) {
      std::fprintf(stderr, "error: --max-targets and --max-error are for --format glb with a skin mode (baked-skin, baked-animation)\n");
      return;
    }
    if (args->max_influences != 4 && args->max_influences != 8) {
      std::fprintf(stderr, "error: --max-influences must be 4 or 8\n");
      return;
    }
    if (args->max_influences != 4 && (request.format != ExportFormat::kGlb || request.options.mode != ExportMode::kBakedSkin)) {
      std::fprintf(stderr, "error: --max-influences is for --format glb --mode baked-skin (the fitted weights)\n");
      return;
    }
    if (args->optimize && request.format != ExportFormat::kGlb) {
      std::fprintf(stderr, "error: --optimize is for --format glb\n");
      return;
    }
    if (args->quantize && request.format != ExportFormat::kGlb) {
      std::fprintf(stderr, "error: --quantize is for --format glb\n");
      return;
    }
    if (args->correctives != "baked" && args->correctives != "pose-driven") {
      std::fprintf(stderr, "error: --correctives '%s' should be baked or pose-driven\n", args->correctives.c_str());
      return;
    }
    const bool pose_driven = args->correctives == "pose-driven";
    if (pose_driven && (request.format != ExportFormat::kGlb || request.options.mode != ExportMode::kBakedSkin)) {
      std::fprintf(stderr, "error: --correctives pose-driven is for --format glb --mode baked-skin\n");
      return;
    }
    if (!args->hold_out.empty() && !pose_driven) {
      std::fprintf(stderr, "error: --hold-out is for --correctives pose-driven\n");
      return;
    }
    if (pose_driven && args->max_error > 0.0) {
      std::fprintf(stderr, "error: --max-error picks among compressed baked targets; pose-driven targets are counted by --max-targets\n");
      return;
    }
    if (pose_driven) request.options.correctives = ExportOptions::Correctives::kPoseDriven;
    request.options.optimize = args->optimize;
    request.options.quantize = args->quantize;
    request.options.max_influences = args->max_influences;
    request.options.max_targets = args->max_targets;
    request.options.max_error = args->max_error;
    if (args->max_error > 0.0 && args->max_targets < 0 && request.options.mode == ExportMode::kBakedAnimation)
      request.options.max_targets = kDefaultMaxTargets;
    request.options.fps = args->fps;
    request.options.keypose_steps = args->keypose_steps;
    request.out = args->out;
    if (auto bad = check_export_path(request); !bad.empty()) {
      std::fprintf(stderr, "error: %s\n", bad.c_str());
      return;
    }
    auto loaded = load_project_or_report(P);
    if (!loaded) return;
    const Document& doc = loaded->document;
    const Character& ch = *doc.character;
    for (const std::string& name : args->clips) {
      int32_t c = ch.find_clip(name);
      if (c < 0) {
        std::string names;
        for (size_t i = 0; i < ch.clips.size(); ++i) names += (i ? ", " : "") + ch.clips[i].name;
        std::fprintf(stderr,
                     "error: %s: its character %s has no clip named or numbered '%s' (it has %zu: %s)\n",
                     P.c_str(), doc.character_path.c_str(), name.c_str(), ch.clips.size(),
                     names.empty() ? "none" : names.c_str());
        return;
      }
      request.options.clips.push_back(c);
    }
    if (!args->hold_out.empty()) {
      request.options.hold_out = ch.find_clip(args->hold_out);
      if (request.options.hold_out < 0) {
        std::fprintf(stderr, "error: %s: --hold-out '%s': its character %s has no clip by that name or number\n", P.c_str(),
                     args->hold_out.c_str(), doc.character_path.c_str());
        return;
      }
    }
    std::optional<Rig> rig;
    if (request.format != ExportFormat::kJson || doc.attachment.mode == AttachmentMode::kFitted) {
      rig = rig_of_project(doc, P);
      if (!rig) return;
    }
    const ExportProgress progress = terminal_export_progress();
    auto report = run_export(doc, rig ? &*rig : nullptr, request, progress);
    if (progress.on_progress) std::fprintf(stderr, "\n");
    if (!report) {
      report_error({report.error().code, P + ": " + report.error().message});
      return;
    }
    for (const std::string& w : report->warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("exported %s of %s: %s in %.1f s\n", report->what.c_str(), P.c_str(), report->summary.c_str(),
                seconds);
    for (const std::string& line : report->error_lines) std::printf("  %s\n", line.c_str());
    exit_code = 0;
  });
}

}  // namespace cagewrap::app
