// cagewrap skin --character F [--clip NAME|INDEX] [--time t] [--loop] --out skin.obj|.bin
// Writes the file's own linear blend skinning at a time: every primitive, in file order.
#include <cstdio>

#include "app/cli_common.h"
#include "app/commands.h"
#include "core/io/gltf_loader.h"
#include "core/geometry/mesh_io.h"
#include "core/character/skinning.h"

namespace cagewrap::app {

void add_skin_command(CLI::App& app, int& exit_code) {
  struct Args {
    std::string character, clip, out;
    double time = 0.0;
    bool loop = false;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("skin", "write a character's linear blend skinning at a clip time");
  cmd->add_option("--character", args->character, "character file (.glb, .gltf)")->required();
  cmd->add_option("--clip", args->clip, "clip name or index (default: the file's rest pose)");
  cmd->add_option("--time", args->time, "seconds into the clip (clamped to the clip)")->capture_default_str();
  cmd->add_flag("--loop", args->loop, "wrap the time into the clip instead of clamping");
  cmd->add_option("--out", args->out, "skinned positions: .obj (with triangles), or .bin (raw float32 N x 3)")->required();
  cmd->callback([args, &exit_code] {
    exit_code = 1;
    if (!positions_output_or_report(args->out)) return;
    auto c = load_character(args->character);
    if (!c) {
      report_error(c.error());
      return;
    }
    for (const std::string& w : c->warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    int32_t clip = -1;
    if (!args->clip.empty()) {
      clip = c->find_clip(args->clip);
      if (clip < 0) {
        std::string names;
        for (size_t i = 0; i < c->clips.size(); ++i) names += (i ? ", " : "") + c->clips[i].name;
        std::fprintf(stderr, "error: %s: no clip named or numbered '%s' (it has %zu: %s)\n", args->character.c_str(),
                     args->clip.c_str(), c->clips.size(), names.empty() ? "none" : names.c_str());
        return;
      }
    }
    if (!std::isfinite(args->time)) {
      std::fprintf(stderr, "error: --time must be a finite number of seconds\n");
      return;
    }
    std::vector<glm::vec3> out = skin_character(*c, sample_pose(*c, clip, args->time, args->loop));
    PolyMesh topology = combined_topology(*c);
    if (auto s = save_positions(args->out, out, topology); !s) {
      report_error(s.error());
      return;
    }
    if (clip >= 0)
      std::printf("skinned %zu vertices of %zu primitives at clip %d ('%s') t=%g s, wrote %s\n", out.size(),
                  c->primitives.size(), clip, c->clips[clip].name.c_str(),
                  clip_time(args->time, c->clips[clip].duration, args->loop), args->out.c_str());
    else
      std::printf("skinned %zu vertices of %zu primitives in the rest pose, wrote %s\n", out.size(),
                  c->primitives.size(), args->out.c_str());
    exit_code = 0;
  });
}

}  // namespace cagewrap::app
