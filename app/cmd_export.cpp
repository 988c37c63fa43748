// cagewrap export --project P --mode baked-animation|baked-skin|cage [--clips a,b] [--fps 30]
//                 --out out.glb
// Writes a saved project's rig as binary glTF for engines and other tools (core/rig_export.h says
// what each mode holds) and reports its error against the live rig.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "app/cli_common.h"
#include "app/commands.h"
#include "core/gltf_writer.h"
#include "core/mesh_io.h"
#include "core/project_io.h"
#include "core/rig.h"
#include "core/rig_export.h"

namespace cagewrap::app {

void add_export_command(CLI::App& app, int& exit_code) {
  struct Args {
    std::string project, mode, out;
    std::vector<std::string> clips;
    double fps = 30.0;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("export", "write a project's rig as a .glb for engines and other tools");
  cmd->add_option("--project", args->project, "project file (.cagewrap)")->required();
  cmd->add_option("--mode", args->mode,
                  "baked-animation (skin + one morph target per frame), baked-skin (fitted LBS weights + "
                  "corrective morph targets) or cage (the cage skinned to the skeleton)")
      ->required();
  cmd->add_option("--clips", args->clips, "clips to export, by name or index (default: all)")->delimiter(',');
  cmd->add_option("--fps", args->fps, "frames sampled per second of each clip")->capture_default_str();
  cmd->add_option("--out", args->out, "output .glb")->required();
  cmd->callback([args, &exit_code] {
    exit_code = 1;
    const std::string& P = args->project;
    const auto start = std::chrono::steady_clock::now();
    ExportOptions options;
    if (!parse_export_mode(args->mode, options.mode)) {
      std::fprintf(stderr, "error: --mode '%s' should be baked-animation, baked-skin or cage\n",
                   args->mode.c_str());
      return;
    }
    if (!has_extension(args->out, ".glb")) {
      std::fprintf(stderr, "error: %s: output must end in .glb\n", args->out.c_str());
      return;
    }
    if (!(args->fps > 0.0) || !std::isfinite(args->fps) || args->fps > 1000.0) {
      std::fprintf(stderr, "error: --fps must be a number of frames per second in (0, 1000]\n");
      return;
    }
    options.fps = args->fps;
    auto loaded = load_project(P);
    if (!loaded) {
      report_error(loaded.error());
      return;
    }
    for (const std::string& w : loaded->warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
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
      options.clips.push_back(c);
    }
    auto rig = rig_of_project(doc, P);
    if (!rig) return;
    auto result = export_rig(doc, *rig, options);
    if (!result) {
      report_error({result.error().code, P + ": " + result.error().message});
      return;
    }
    for (const std::string& w : result->warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    if (auto s = write_glb(args->out, result->character, "cagewrap export"); !s) {
      report_error(s.error());
      return;
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::error_code ec;
    const auto bytes = std::filesystem::file_size(args->out, ec);
    std::printf("exported %s of %s: %zu frames, %zu morph targets, wrote %s (%.1f MB) in %.1f s\n",
                export_mode_name(options.mode), P.c_str(), result->frames, result->morph_targets,
                args->out.c_str(), ec ? 0.0 : double(bytes) / 1e6, seconds);
    auto line = [](const char* what, const ExportError& e) {
      std::printf("  %-34s mean %.3g m, max %.3g m\n", what, e.mean, e.max);
    };
    if (options.mode == ExportMode::kBakedSkin) line("error at frames, skeleton only:", result->fitted);
    line(options.mode == ExportMode::kCage ? "cage error at frames:" : "error at frames:", result->at_frames);
    if (options.mode != ExportMode::kCage) line("error between frames:", result->between_frames);
    exit_code = 0;
  });
}

}  // namespace cagewrap::app
