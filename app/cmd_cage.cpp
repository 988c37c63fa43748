// cagewrap cage --mesh CHARACTER --faces N [--joint-detail x] [--inflate d] [--no-quads]
//               [--failures points.txt] --out cage.obj
// Builds the automatic cage (paper section 5, step 1) and prints its report.
#include <cstdio>
#include <string>

#include "app/cli_common.h"
#include "app/commands.h"
#include "core/atomic_write.h"
#include "core/auto_cage.h"
#include "core/gltf_loader.h"
#include "core/mesh_io.h"

namespace cagewrap::app {

namespace {
const char* yes_no(bool b) {
  return b ? "yes" : "no";
}

void print_cage_report(const AutoCageReport& r, const AutoCageParams& p) {
  std::printf("input             %u vertices, %u triangles\n", r.input_vertices, r.input_triangles);
  std::printf("welded            %u vertices, %u triangles dropped\n", r.welded_vertices,
              r.dropped_triangles);
  std::printf("joints            %u\n", r.joints);
  if (r.wrapped && r.shells > 1)
    std::printf("wrapped           yes (%u closed offset surfaces, %u triangles)\n", r.shells,
                r.wrap_triangles);
  else if (r.wrapped)
    std::printf("wrapped           yes (offset surface of %u triangles)\n", r.wrap_triangles);
  else
    std::printf("wrapped           no\n");
  std::printf("faces             %u (%u quads, %u triangles)\n", r.faces, r.quads, r.faces - r.quads);
  std::printf("elements          %u triangles\n", r.triangles);
  std::printf("vertices          %u\n", r.vertices);
  if (p.inflate_absolute)
    std::printf("inflate           %.6g\n", r.inflate_distance);
  else
    std::printf("inflate           %.6g (%.4g of the bbox diagonal)\n", r.inflate_distance, p.inflate);
  std::printf("closed            %s (%u boundary edges, %u components)\n", yes_no(r.check.closed()),
              r.check.boundary_edges, r.check.components);
  std::printf("non-manifold      %u edges\n", r.check.non_manifold_edges);
  std::printf("misoriented       %u edges\n", r.check.misoriented_edges);
  std::printf("self-crossings    %u edge-triangle pairs\n", r.check.self_intersections);
  std::printf("piece crossings   %u edge-triangle pairs (closed pieces passing through each other)\n",
              r.check.piece_crossings);
  std::printf("degenerate        %u triangles\n", r.check.degenerate_triangles);
  std::printf("needles           %u triangles (worst aspect %.3g, limit %.3g)\n", r.check.needle_triangles,
              r.check.worst_aspect, kNeedleAspect);
  std::printf("outside points    %u\n", r.outside_points);
  std::printf("max outside       %.6g\n", r.max_outside);
  std::printf("max distance      %.6g\n", r.max_distance);
  std::printf("quality           %.2f%% of skin points close to and projecting inside an element\n",
              100.0 * r.quality);
  std::printf("failing points    %zu\n", r.failures.size());
  std::printf("seconds           %.3f (bind for the quality figure %.3f)\n", r.seconds, r.bind_seconds);
  std::printf("warnings          %zu\n", r.warnings.size());
  for (const std::string& w : r.warnings) std::printf("  %s\n", w.c_str());
}
}  // namespace

void add_cage_command(CLI::App& app, int& exit_code) {
  struct Args {
    std::string mesh, out, failures;
    AutoCageParams params;
    bool no_fit = false;
    bool one_surface = false;
    std::string wrap = "auto";
    BindOptions bind;
  };
  auto args = std::make_shared<Args>();
  auto* cmd =
      app.add_subcommand("cage", "build a cage around a character automatically (weld, decimate, inflate)");
  cmd->add_option("--mesh", args->mesh, "character (.glb .gltf) or mesh (.obj .ply .off .stl)")->required();
  cmd->add_option("--faces", args->params.target_faces,
                  "target number of cage triangles (the decimation's; quads then pair some of them)")
      ->capture_default_str();
  cmd->add_flag("--quads,!--no-quads", args->params.quads,
                "pair nearly coplanar triangles into convex quads (the control elements stay the triangles)")
      ->capture_default_str();
  cmd->add_option("--joint-detail", args->params.joint_detail, "extra resolution near joints (0 = uniform)")
      ->capture_default_str();
  cmd->add_option("--joint-radius", args->params.joint_radius,
                  "reach of a joint's detail, share of the bbox diagonal")
      ->capture_default_str();
  cmd->add_option("--inflate", args->params.inflate, "clearance, share of the bbox diagonal (or scene units)")
      ->capture_default_str();
  cmd->add_option("--concave-share", args->params.concave_share,
                  "share of the clearance kept in valleys (1 = uniform)")
      ->capture_default_str();
  cmd->add_flag("--inflate-absolute", args->params.inflate_absolute, "--inflate is in scene units");
  cmd->add_option("--wrap", args->wrap,
                  "auto: wrap separate/open pieces in closed offset surfaces (one per piece); always; never")
      ->check(CLI::IsMember({"auto", "always", "never"}))
      ->capture_default_str();
  cmd->add_flag("--one-surface", args->one_surface,
                "when wrapping, one offset surface around all pieces instead of one per piece");
  cmd->add_flag("--no-fit", args->no_fit, "do not push the cage out where skin points stay outside");
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
    args->params.bind = args->bind.params;
    args->params.fit_skin = !args->no_fit;
    args->params.shell_per_piece = !args->one_surface;
    args->params.wrap = args->wrap == "always"  ? WrapMode::kAlways
                        : args->wrap == "never" ? WrapMode::kNever
                                                : WrapMode::kAuto;
    if (auto s = validate(args->params); !s) {
      report_error(s.error());
      return;
    }
    AutoCageProgress progress;
    BindProgress bar = terminal_progress("cage");
    if (bar.on_progress) progress.on_progress = [bar](const char*, double f) { bar.on_progress(f); };
    Result<AutoCageReport> r = make_error(ErrorCode::kEmpty, "");
    if (has_extension(args->mesh, ".glb") || has_extension(args->mesh, ".gltf")) {
      auto c = load_character(args->mesh);
      if (!c) {
        report_error(c.error());
        return;
      }
      for (const std::string& w : c->warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
      r = build_auto_cage(*c, args->params, progress);
    } else {
      auto m = load_mesh_or_report(args->mesh);
      if (!m) return;
      r = build_auto_cage(*m, {}, args->params, progress);
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
    print_cage_report(*r, args->params);
    std::printf("wrote             %s\n", args->out.c_str());
    if (!args->failures.empty()) std::printf("wrote             %s\n", args->failures.c_str());
    exit_code = 0;
  });
}

}  // namespace cagewrap::app
