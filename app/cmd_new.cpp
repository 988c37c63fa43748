// cagewrap new --character F [--cage C] [params] --out P.cagewrap
#include <cstdio>

#include "app/cli_common.h"
#include "app/commands.h"
#include "core/document.h"
#include "core/project_io.h"

namespace cagewrap::app {

void add_new_command(CLI::App& app, int& exit_code) {
  struct Args {
    std::string character, cage, out;
    BindOptions bind;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("new", "make a project (.cagewrap) from a character and a cage");
  cmd->add_option("--character", args->character, "character (.glb .gltf)")->required();
  cmd->add_option("--cage", args->cage, "cage at rest (.obj .ply .off .stl); without it the project has no cage yet");
  cmd->add_option("--out", args->out, "project file to write (.cagewrap)")->required();
  add_bind_options(*cmd, args->bind);
  cmd->callback([args, &exit_code] {
    exit_code = 1;
    if (!finish_bind_options(args->bind)) return;
    auto doc = document_from_files(args->character, args->cage);
    if (!doc) {
      report_error(doc.error());
      return;
    }
    *doc = with_params(*doc, args->bind.params);
    if (auto s = save_project(args->out, *doc); !s) {
      report_error(s.error());
      return;
    }
    const Character& c = *doc->character;
    std::printf("character  %s: %zu vertices, %zu joints, %zu clips\n", args->character.c_str(), c.num_vertices(),
                c.num_joints(), c.clips.size());
    if (doc->cage)
      std::printf("cage       %s: %zu vertices, %zu faces\n", args->cage.c_str(), doc->cage->num_vertices(),
                  doc->cage->polygons.num_faces());
    else
      std::printf("cage       none\n");
    std::printf("wrote      %s\n", args->out.c_str());
    exit_code = 0;
  });
}

}  // namespace cagewrap::app
