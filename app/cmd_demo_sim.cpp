// cagewrap demo-sim belly|cape --out P.cagewrap [--character C.glb] [--cage C.obj]
// Writes the simulated-cage use cases on the demo character (core/rig/demo_sim.h) as projects:
//   belly: the demo character and cage with the belly's cage vertices soft (jiggles in the walk);
//   cape:  the demo character with a cape (written beside the project as <name>.glb) and its cage
//          extended by a cloth sheet that drapes and swings, colliding with the skeleton.
#include <cstdio>
#include <filesystem>

#include "app/cli_common.h"
#include "app/commands.h"
#include "app/workspace/scene.h"
#include "core/rig/demo_sim.h"
#include "core/io/gltf_loader.h"
#include "core/io/gltf_writer.h"
#include "core/geometry/mesh_io.h"
#include "core/document/project_io.h"

namespace cagewrap::app {

void add_demo_sim_command(CLI::App& app, int& exit_code) {
  struct Args {
    std::string which, out, character, cage;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("demo-sim", "write a simulated-cage demo project (belly jiggle or cape)");
  cmd->add_option("which", args->which, "belly or cape")->required()->check(CLI::IsMember({"belly", "cape"}));
  cmd->add_option("--out", args->out, "project file to write (.cagewrap)")->required();
  cmd->add_option("--character", args->character, "the demo character (.glb; default: the bundled one)");
  cmd->add_option("--cage", args->cage, "the demo cage (default: the bundled one beside the character)");
  cmd->callback([args, &exit_code] {
    exit_code = 1;
    if (!has_extension(args->out, kProjectExtension)) {
      std::fprintf(stderr, "error: %s: output must end in %s\n", args->out.c_str(), kProjectExtension);
      return;
    }
    if (args->character.empty()) args->character = demo_character_path();
    if (args->character.empty()) {
      std::fprintf(stderr, "error: the bundled demo character (assets/demo_character.glb) was not found; give --character\n");
      return;
    }
    if (args->cage.empty()) args->cage = demo_cage_path(args->character);
    if (args->cage.empty()) {
      std::fprintf(stderr, "error: %s: no demo_cage.obj beside it; give --cage\n", args->character.c_str());
      return;
    }
    auto doc = document_from_files(args->character, args->cage);
    if (!doc) {
      report_error(doc.error());
      return;
    }
    if (args->which == "belly") {
      *doc = with_sim(*doc, demo_belly_sim(doc->cage_positions()));
    } else {
      auto cape = make_demo_cape(*doc->character, doc->cage->polygons);
      if (!cape) {
        report_error({cape.error().code, args->character + ": " + cape.error().message});
        return;
      }
      const std::string glb = std::filesystem::path(args->out).replace_extension(".glb").string();
      if (auto s = write_glb(glb, cape->character); !s) {
        report_error(s.error());
        return;
      }
      auto made = document_from_files(glb, "");
      if (!made) {
        report_error(made.error());
        return;
      }
      auto cage = make_cage(cape->cage, "demo cage with a cape");
      if (!cage) {
        report_error(cage.error());
        return;
      }
      *doc = with_sim(with_params(with_cage(*made, std::make_shared<const Cage>(std::move(cage).value())), cape->params),
                      cape->sim);
      std::printf("wrote %s (the demo character with a cape: %zu vertices)\n", glb.c_str(),
                  doc->character->num_vertices());
    }
    if (auto s = save_project(args->out, *doc); !s) {
      report_error(s.error());
      return;
    }
    size_t free = 0;
    for (const SimVertex& v : doc->sim.vertices) free += !v.pinned;
    std::printf("wrote %s: %s demo, cage of %zu vertices, %zu simulated (the rest pinned)\n", args->out.c_str(),
                args->which.c_str(), doc->cage->num_vertices(), free);
    exit_code = 0;
  });
}

}  // namespace cagewrap::app
