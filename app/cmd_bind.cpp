// cagewrap bind --mesh M --cage C [params] [--edits E] --out B
#include <cstdio>

#include "app/cli_common.h"
#include "app/commands.h"
#include "core/io/binding_io.h"
#include "core/geometry/mesh_io.h"
#include "core/io/set_edits_io.h"

namespace cagewrap::app {

void add_bind_command(CLI::App& app, int& exit_code) {
  struct Args {
    std::string mesh, cage, out, edits;
    BindOptions bind;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("bind", "register a skin to a cage and write the binding table");
  cmd->add_option("--mesh", args->mesh, "skin mesh (.obj .ply .off .stl)")->required();
  cmd->add_option("--cage", args->cage, "cage at rest (.obj .ply .off .stl)")->required();
  cmd->add_option("--out", args->out, "binding file to write (.cwb)")->required();
  cmd->add_option("--edits", args->edits,
                  "contributing-set edits to apply (.json, docs/edits-format.md): per-point rules and rules by "
                  "point and face lists");
  add_bind_options(*cmd, args->bind);
  cmd->callback([args, &exit_code] {
    exit_code = 1;
    if (!finish_bind_options(args->bind)) return;
    // never anything else: `--out skin.obj` must not overwrite a mesh with a binding
    if (!has_extension(args->out, ".cwb")) {
      std::fprintf(stderr, "error: %s: the binding file must end in .cwb\n", args->out.c_str());
      return;
    }
    auto mesh = load_mesh_or_report(args->mesh);
    if (!mesh) return;
    auto cage = load_cage_or_report(args->cage);
    if (!cage) return;
    std::vector<SetEdit> edits;
    if (!args->edits.empty()) {
      auto file = load_set_edits(args->edits);
      if (!file) {
        report_error(file.error());
        return;
      }
      auto resolved = resolve_set_edits(*file, args->edits, mesh->positions, *cage);
      if (!resolved) {
        report_error(resolved.error());
        return;
      }
      for (const std::string& w : resolved->warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
      edits = std::move(resolved->edits);
    }
    auto b = bind_skin(mesh->positions, *cage, cage->polygons.positions, args->bind.params, edits, terminal_progress("bind"));
    if (!b) {
      report_error({b.error().code, args->cage + ": " + b.error().message});
      return;
    }
    if (auto s = save_binding(args->out, *b); !s) {
      report_error(s.error());
      return;
    }
    print_bind_summary(*b, args->cage, cage->polygons.num_faces());
    if (!args->edits.empty()) std::printf("set edits         %zu points (%s)\n", edits.size(), args->edits.c_str());
    std::printf("wrote             %s\n", args->out.c_str());
    exit_code = 0;
  });
}

}  // namespace cagewrap::app
