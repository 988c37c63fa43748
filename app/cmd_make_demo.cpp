// cagewrap make-demo --out assets/demo_character.glb: generates the default document's character.
// --variant arms-down|tail|arms-down+tail|quadruped makes the hard test characters, --units cm writes it in
// centimetres (core/character/demo_character.h).
#include <cstdio>

#include "app/cli_common.h"
#include "app/commands.h"
#include "core/character/demo_character.h"
#include "core/io/gltf_writer.h"
#include "core/geometry/mesh_io.h"

namespace cagewrap::app {

void add_make_demo_command(CLI::App& app, int& exit_code) {
  struct Args {
    std::string out = "assets/demo_character.glb";
    DemoCharacterOptions options;
    std::string variant = "default";
    std::string units = "m";
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("make-demo", "generate the demo character (deterministic) as a .glb");
  cmd->add_option("--out", args->out, "output .glb")->capture_default_str();
  cmd->add_option("--cell-size", args->options.cell_size,
                  "polygonizer grid spacing in metres (sets the vertex count; default 0.015, 0.011 for the tail variants and the quadruped)");
  cmd->add_option("--variant", args->variant,
                  "default | arms-down (hands at the thighs, legs together) | tail (fingers and a 12-bone tail) | "
                  "arms-down+tail | quadruped (four legs, a tail)")
      ->capture_default_str();
  cmd->add_option("--units", args->units, "scene units of the file: m | cm (the same mesh, scaled by 100)")
      ->capture_default_str();
  cmd->callback([args, &exit_code] {
    exit_code = 1;
    if (!has_extension(args->out, ".glb")) {
      std::fprintf(stderr, "error: %s: output must end in .glb\n", args->out.c_str());
      return;
    }
    auto variant = parse_demo_variant(args->variant);
    if (!variant) {
      std::fprintf(stderr, "error: --variant %s: expected default, arms-down, tail, arms-down+tail or quadruped\n",
                   args->variant.c_str());
      return;
    }
    args->options.variant = *variant;
    if (args->units == "m") {
      args->options.unit_scale = 1.0;
    } else if (args->units == "cm") {
      args->options.unit_scale = 100.0;
    } else {
      std::fprintf(stderr, "error: --units %s: expected m or cm\n", args->units.c_str());
      return;
    }
    if (args->options.cell_size == 0) args->options.cell_size = demo_default_cell_size(*variant);
    // 0.00125 m makes about 5,000,000 vertices (the vertex count grows with 1 / cell size squared)
    if (!(args->options.cell_size >= 0.00125 && args->options.cell_size <= 0.1)) {
      std::fprintf(stderr, "error: --cell-size %g is outside 0.00125..0.1 m\n", args->options.cell_size);
      return;
    }
    Character c = make_demo_character(args->options);
    if (auto s = write_glb(args->out, c); !s) {
      report_error(s.error());
      return;
    }
    std::printf("wrote %s: %zu vertices, %zu triangles, %zu joints, %zu clips\n", args->out.c_str(), c.num_vertices(),
                c.num_triangles(), c.num_joints(), c.clips.size());
    exit_code = 0;
  });
}

}  // namespace cagewrap::app
