// cagewrap deform --mesh M --cage C --posed-cage C2 [--binding B] [params] --out M2.obj|.bin
#include <cstdio>

#include "app/cli_common.h"
#include "app/commands.h"
#include "core/io/binding_io.h"
#include "core/deform/deformer.h"
#include "core/geometry/mesh_io.h"

namespace cagewrap::app {

void add_deform_command(CLI::App& app, int& exit_code) {
  struct Args {
    std::string mesh, cage, posed, binding, out;
    BindOptions bind;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("deform", "deform a skin by a posed cage");
  cmd->add_option("--mesh", args->mesh, "skin mesh at rest")->required();
  cmd->add_option("--cage", args->cage, "cage at rest")->required();
  cmd->add_option("--posed-cage", args->posed, "the same cage, moved")->required();
  cmd->add_option("--binding", args->binding, "binding from `cagewrap bind` (otherwise bind now)");
  cmd->add_option("--out", args->out, "deformed skin: .obj, or .bin (raw float32 N x 3)")->required();
  add_bind_options(*cmd, args->bind);
  cmd->callback([args, &exit_code] {
    exit_code = 1;
    if (!finish_bind_options(args->bind)) return;
    if (!positions_output_or_report(args->out)) return;
    auto mesh = load_mesh_or_report(args->mesh);
    if (!mesh) return;
    auto cage = load_cage_or_report(args->cage);
    if (!cage) return;
    auto posed = load_posed_cage_or_report(args->posed, *cage, args->cage);
    if (!posed) return;
    Binding binding;
    if (!args->binding.empty()) {
      auto b = load_binding(args->binding);
      if (!b) {
        report_error(b.error());
        return;
      }
      binding = std::move(b).value();
      // a saved binding fixes the bind parameters: options asking for others cannot be honoured
      if (std::string differ = bind_options_differing(args->bind, binding.params); !differ.empty()) {
        std::fprintf(stderr,
                     "error: %s: the binding was made with other parameters than given: %s; bind again with "
                     "them, or leave them out to deform with the binding's\n",
                     args->binding.c_str(), differ.c_str());
        return;
      }
      if (binding.num_cage_vertices != cage->num_vertices() || binding.elements != cage->elements) {
        std::fprintf(stderr, "error: %s: the binding was made for a cage of %u vertices and %zu elements, not %s (%zu and %zu)\n",
                     args->binding.c_str(), binding.num_cage_vertices, binding.elements.size(), args->cage.c_str(),
                     cage->num_vertices(), cage->num_elements());
        return;
      }
    } else {
      auto b = bind_skin(mesh->positions, *cage, cage->polygons.positions, args->bind.params, {}, terminal_progress("bind"));
      if (!b) {
        report_error({b.error().code, args->cage + ": " + b.error().message});
        return;
      }
      binding = std::move(b).value();
    }
    auto deformer = Deformer::create(binding, mesh->positions);
    if (!deformer) {
      report_error({deformer.error().code, (args->binding.empty() ? args->mesh : args->binding) + ": " + deformer.error().message});
      return;
    }
    std::vector<glm::vec3> out(mesh->num_vertices());
    if (auto s = deformer->deform(posed->positions, out); !s) {
      report_error({s.error().code, args->posed + ": " + s.error().message});
      return;
    }
    if (auto s = save_positions(args->out, out, *mesh); !s) {
      report_error(s.error());
      return;
    }
    std::printf("deformed %zu points with %s, wrote %s\n", out.size(), variant_name(binding.params.variant),
                args->out.c_str());
    exit_code = 0;
  });
}

}  // namespace cagewrap::app
