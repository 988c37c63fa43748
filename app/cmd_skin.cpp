// cagewrap skin --character F [--clip NAME|INDEX] [--time t] [--loop] [--region-joints a,b] --out skin.obj|.bin
// Writes the file's own linear blend skinning at a time: every primitive, in file order; with
// --region-joints, only the triangles whose points those joints move (a mesh to wrap a garment cage around).
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <sstream>

#include "app/cli_common.h"
#include "app/commands.h"
#include "core/io/gltf_loader.h"
#include "core/geometry/mesh_io.h"
#include "core/character/skin_mask.h"
#include "core/character/skinning.h"

namespace cagewrap::app {

void add_skin_command(CLI::App& app, int& exit_code) {
  struct Args {
    std::string character, clip, out, region;
    double time = 0.0;
    bool loop = false, keep_units = false;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("skin", "write a character's linear blend skinning at a clip time");
  cmd->add_option("--character", args->character, "character file (.glb .gltf .fbx .dae .x .b3d .ms3d .smd .md5mesh)")->required();
  add_keep_units_flag(*cmd, args->keep_units);
  cmd->add_option("--clip", args->clip, "clip name or index (default: the file's rest pose)");
  cmd->add_option("--time", args->time, "seconds into the clip (clamped to the clip)")->capture_default_str();
  cmd->add_flag("--loop", args->loop, "wrap the time into the clip instead of clamping");
  cmd->add_option("--out", args->out, "skinned positions: .obj (with triangles), or .bin (raw float32 N x 3)")->required();
  cmd->add_option("--region-joints", args->region,
                  "only the triangles whose points these joints and their children move (skin weights over 0.5; a,b,c; "
                  "-name leaves one out: spine,-neck): a region of the skin as a mesh, e.g. to build a garment cage around");
  cmd->callback([args, &exit_code] {
    exit_code = 1;
    if (!positions_output_or_report(args->out)) return;
    auto c = load_character(args->character, {args->keep_units});
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
    if (!args->region.empty()) {
      std::vector<std::string> names;
      std::stringstream in(args->region);
      for (std::string item; std::getline(in, item, ',');)
        if (!item.empty()) names.push_back(item);
      auto mask = joint_region_mask(*c, names);
      if (!mask) {
        std::fprintf(stderr, "error: %s: --region-joints: %s\n", args->character.c_str(), mask.error().message.c_str());
        return;
      }
      // the region's triangles, their points renumbered in skin order
      std::vector<uint32_t> index(out.size(), UINT32_MAX);
      std::vector<glm::vec3> kept;
      PolyMesh region;
      for (size_t f = 0; f < topology.num_faces(); ++f) {
        const auto face = topology.face(f);
        if (!std::all_of(face.begin(), face.end(), [&](uint32_t v) { return (*mask)[v] > 0.5f; })) continue;
        std::vector<uint32_t> ids;
        for (uint32_t v : face) {
          if (index[v] == UINT32_MAX) index[v] = static_cast<uint32_t>(kept.size()), kept.push_back(out[v]);
          ids.push_back(index[v]);
        }
        region.add_face(ids);
      }
      if (region.num_faces() == 0) {
        std::fprintf(stderr, "error: %s: --region-joints %s: no triangle of the skin lies in that region\n", args->character.c_str(),
                     args->region.c_str());
        return;
      }
      region.positions = kept;
      std::printf("region %s: %zu of %zu triangles, %zu points\n", args->region.c_str(), region.num_faces(), topology.num_faces(),
                  kept.size());
      out = std::move(kept);
      topology = std::move(region);
    }
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
