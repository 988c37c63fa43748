#include "app/auto_cage_options.h"

#include <cstdio>

#include "app/cli_common.h"

namespace cagewrap::app {

CLI::Option* add_auto_cage_options(CLI::App& cmd, AutoCageOptions& o, const std::string& faces_flag) {
  CLI::Option* faces = cmd.add_option(faces_flag, o.params.target_faces,
                                      "target number of cage triangles (the decimation's; quads then pair some of them)")
                           ->capture_default_str();
  cmd.add_flag("--quads,!--no-quads", o.params.quads,
               "pair nearly coplanar triangles into convex quads (the control elements stay the triangles)")
      ->capture_default_str();
  cmd.add_option("--joint-detail", o.params.joint_detail, "extra resolution near joints (0 = uniform)")->capture_default_str();
  cmd.add_option("--joint-radius", o.params.joint_radius, "reach of a joint's detail, share of the bbox diagonal")
      ->capture_default_str();
  cmd.add_option("--inflate", o.params.inflate, "clearance, share of the bbox diagonal (or scene units)")->capture_default_str();
  cmd.add_option("--concave-share", o.params.concave_share, "share of the clearance kept in valleys (1 = uniform)")
      ->capture_default_str();
  cmd.add_flag("--inflate-absolute", o.params.inflate_absolute, "--inflate is in scene units");
  cmd.add_option("--wrap", o.wrap, "auto: wrap separate/open pieces in closed offset surfaces (one per piece); always; never")
      ->check(CLI::IsMember({"auto", "always", "never"}))
      ->capture_default_str();
  cmd.add_flag("--one-surface", o.one_surface, "when wrapping, one offset surface around all pieces instead of one per piece");
  cmd.add_flag("--no-fit", o.no_fit, "do not push the cage out where skin points stay outside");
  return faces;
}

bool finish_auto_cage_options(AutoCageOptions& o, const BindParams& bind) {
  o.params.bind = bind;
  o.params.fit_skin = !o.no_fit;
  o.params.shell_per_piece = !o.one_surface;
  o.params.wrap = o.wrap == "always" ? WrapMode::kAlways : o.wrap == "never" ? WrapMode::kNever : WrapMode::kAuto;
  if (auto s = validate(o.params); !s) {
    report_error(s.error());
    return false;
  }
  return true;
}

AutoCageProgress terminal_cage_progress() {
  AutoCageProgress progress;
  BindProgress bar = terminal_progress("cage");
  if (bar.on_progress) progress.on_progress = [bar](const char*, double f) { bar.on_progress(f); };
  return progress;
}

namespace {
const char* yes_no(bool b) {
  return b ? "yes" : "no";
}

}  // namespace

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

bool add_automatic_cage(Document& doc, const AutoCageParams& params, const std::string& character_path, bool quiet) {
  auto r = build_auto_cage(*doc.character, params, terminal_cage_progress());
  if (!r) {
    report_error({r.error().code, character_path + ": " + r.error().message});
    return false;
  }
  auto cage = make_cage(r->cage, "automatic cage");
  if (!cage) {
    report_error(cage.error());
    return false;
  }
  if (!quiet) print_cage_report(*r, params);
  doc = with_cage(doc, std::make_shared<const Cage>(std::move(cage).value()));
  return true;
}

}  // namespace cagewrap::app
