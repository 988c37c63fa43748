// cagewrap cage --mesh CHARACTER --faces N [--joint-detail x] [--inflate d] [--no-quads]
//               [--failures points.txt] --out cage.obj
// Builds the automatic cage (paper section 5, step 1) and prints its report.
#include <cstdio>
#include <string>

#include "app/auto_cage_options.h"
#include "app/cli_common.h"
#include "app/commands.h"
#include "core/base/atomic_write.h"
#include "core/rig/auto_cage.h"
#include "core/io/gltf_loader.h"
#include "core/geometry/mesh_io.h"

namespace cagewrap::app {


void add_cage_command(CLI::App& app, int& exit_code) {
  struct Args {
    std::string mesh, out, failures;
    AutoCageOptions cage;
    BindOptions bind;
    bool keep_units = false;
  };
  auto args = std::make_shared<Args>();
  auto* cmd =
      app.add_subcommand("cage", "build a cage around a character automatically (weld, decimate, inflate)");
  cmd->add_option("--mesh", args->mesh, "character (.glb .gltf .fbx .dae .x ...) or mesh (.obj .ply .off .stl)")->required();
  add_keep_units_flag(*cmd, args->keep_units);
  add_auto_cage_options(*cmd, args->cage, "--faces");
  cmd->add_option("--out", args->out, "cage to write (.obj)")->required();
  cmd->add_option("--failures", args->failures,
                  "write the skin vertices failing the cage-quality test, one index a line (.txt)");
  add_bind_options(*cmd, args->bind);
  cmd->callback([args, &exit_code] {
    exit_code = 1;
    if (!has_extension(args->out, ".obj")) {
      std::fprintf(stderr, "error: %s: the cage is written as .obj\n", args->out.c_str());
      return;
    }
    if (!finish_bind_options(args->bind)) return;
    if (!finish_auto_cage_options(args->cage, args->bind.params)) return;
    const AutoCageParams& params = args->cage.params;
    AutoCageProgress progress = terminal_cage_progress();
    Result<AutoCageReport> r = make_error(ErrorCode::kEmpty, "");
    if (is_character_file(args->mesh)) {
      auto c = load_character(args->mesh, {args->keep_units});
      if (!c) {
        report_error(c.error());
        return;
      }
      for (const std::string& w : c->warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
      r = build_auto_cage(*c, params, progress);
    } else {
      auto m = load_mesh_or_report(args->mesh);
      if (!m) return;
      r = build_auto_cage(*m, {}, params, progress);
    }
    if (!r) {
      report_error({r.error().code, args->mesh + ": " + r.error().message});
      return;
    }
    if (auto s = save_obj(args->out, r->cage.positions, r->cage); !s) {
      report_error(s.error());
      return;
    }
    if (!args->failures.empty()) {
      std::string text = "# skin vertices (as `cagewrap skin` orders them) failing the cage-quality test\n";
      for (uint32_t i : r->failures) text += std::to_string(i) + "\n";
      if (auto s = write_file_atomic(args->failures, text); !s) {
        report_error(s.error());
        return;
      }
    }
    print_cage_report(*r, params);
    std::printf("wrote             %s\n", args->out.c_str());
    if (!args->failures.empty()) std::printf("wrote             %s\n", args->failures.c_str());
    exit_code = 0;
  });
}

}  // namespace cagewrap::app
