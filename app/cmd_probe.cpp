// cagewrap probe --cage REST --posed POSED [--skin S.obj|.glb [--edits E.json]] [params] [--samples N]
//                [--steps N] [--json]
// A Lipschitz figure for a binding (core/deform/lipschitz_probe.h, issue 18): along lines of densely spaced
// points, the largest step of the deformed line over the spacing, next to the cage's own largest
// stretch, and the same at half the spacing (a jump does not shrink); then the time probe (no skin
// point's step between consecutive frames of the rest-to-pose motion larger than 3 x its average).
// Exit 0 within the limits, 1 over them, 2 on bad input.
#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "app/cli_common.h"
#include "app/commands.h"
#include "core/io/gltf_loader.h"
#include "core/deform/lipschitz_probe.h"
#include "core/geometry/mesh_io.h"
#include "core/io/set_edits_io.h"
#include "core/character/skinning.h"

namespace cagewrap::app {

namespace {

nlohmann::json vec_json(const glm::dvec3& v) { return {v.x, v.y, v.z}; }

// The rest skin of a mesh file or of a glTF character (every primitive, bind pose); nullopt after
// printing the error.
std::optional<std::vector<glm::vec3>> load_skin_or_report(const std::string& path) {
  if (is_character_file(path)) {
    auto c = load_character(path);
    if (!c) {
      report_error(c.error());
      return std::nullopt;
    }
    return skin_character(*c, sample_pose(*c, -1, 0.0));
  }
  auto m = load_mesh_or_report(path);
  if (!m) return std::nullopt;
  return std::move(m->positions);
}

const char* verdict(bool ok) { return ok ? "passed" : "FAILED"; }

}  // namespace

void add_probe_command(CLI::App& app, int& exit_code) {
  struct Args {
    std::string cage, posed, skin, edits;
    uint32_t samples = 2001, steps = 200;
    ProbeLimits limits;
    bool json = false;
    BindOptions bind;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "probe", "a Lipschitz figure for a binding: the largest step of deformed lines of dense points over their "
               "spacing, next to the cage's largest stretch, and steps in time from rest to the pose");
  cmd->add_option("--cage", args->cage, "cage at rest (.obj .ply .off .stl)")->required();
  cmd->add_option("--posed,--posed-cage", args->posed, "the same cage, moved")->required();
  cmd->add_option("--skin", args->skin,
                  "skin mesh (.obj .ply .off .stl) or character (.glb .gltf) at rest: the time probe runs on it "
                  "(else on the probe lines' points), and --edits are its points'");
  cmd->add_option("--edits", args->edits,
                  "contributing-set edits of the skin (.json, docs/edits-format.md): lines through edited points");
  cmd->add_option("--samples", args->samples, "points per probe line (3 to 1000000)")->capture_default_str();
  cmd->add_option("--steps", args->steps, "frames of the time probe from rest to the pose")->capture_default_str();
  cmd->add_option("--max-ratio", args->limits.max_ratio, "limit on the worst step ratio over the cage's stretch")
      ->capture_default_str();
  cmd->add_option("--max-shrink", args->limits.max_shrink,
                  "limit on the largest step at half spacing over the largest at the spacing (0.5: continuous, 1: a jump)")
      ->capture_default_str();
  cmd->add_option("--max-time-ratio", args->limits.max_time_ratio,
                  "limit on a skin point's largest step between frames over its average step")
      ->capture_default_str();
  cmd->add_flag("--json", args->json, "print one JSON object instead of a table");
  add_bind_options(*cmd, args->bind);
  cmd->callback([args, &exit_code] {
    exit_code = 2;  // bad input until the probe has run
    if (!finish_bind_options(args->bind)) return;
    const BindParams& params = args->bind.params;
    if (args->samples < 3 || args->samples > kMaxProbeSamples) {
      std::fprintf(stderr, "error: --samples must be between 3 and %u, not %u\n", kMaxProbeSamples, args->samples);
      return;
    }
    if (args->steps < 1 || args->steps > 100000) {
      std::fprintf(stderr, "error: --steps must be between 1 and 100000, not %u\n", args->steps);
      return;
    }
    for (double limit : {args->limits.max_ratio, args->limits.max_shrink, args->limits.max_time_ratio})
      if (!(limit > 0) || !std::isfinite(limit)) {
        std::fprintf(stderr, "error: --max-ratio, --max-shrink and --max-time-ratio must be positive numbers\n");
        return;
      }
    if (!args->edits.empty() && args->skin.empty()) {
      std::fprintf(stderr, "error: %s: --edits needs the skin they name points of (--skin)\n", args->edits.c_str());
      return;
    }
    auto cage = load_cage_or_report(args->cage);
    if (!cage) return;
    auto posed = load_posed_cage_or_report(args->posed, *cage, args->cage);
    if (!posed) return;
    std::vector<glm::vec3> skin;
    std::vector<SetEdit> edits;
    if (!args->skin.empty()) {
      auto s = load_skin_or_report(args->skin);
      if (!s) return;
      skin = std::move(*s);
      if (auto c = check_skin(skin); !c) {
        report_error({c.error().code, args->skin + ": " + c.error().message});
        return;
      }
    }
    if (!args->edits.empty()) {
      auto file = load_set_edits(args->edits);
      if (!file) {
        report_error(file.error());
        return;
      }
      auto resolved = resolve_set_edits(*file, args->edits, skin, *cage);
      if (!resolved) {
        report_error(resolved.error());
        return;
      }
      for (const std::string& w : resolved->warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
      edits = std::move(resolved->edits);
    }
    const auto& rest = cage->polygons.positions;
    const double h = probe_scale(*cage, rest, params);
    const std::vector<ProbeLine> lines = automatic_probe_lines(*cage, rest, params, h, skin, edits);
    auto report = probe_lipschitz(*cage, rest, posed->positions, params, lines, args->samples,
                                  terminal_progress("probe"));
    if (!report) {
      const bool posed_error = report.error().code == ErrorCode::kNonFinite;
      report_error({report.error().code, (posed_error ? args->posed : args->cage) + ": " + report.error().message});
      return;
    }
    // the time probe: on the skin, else on the probe lines' points
    std::vector<glm::vec3> line_points;
    std::vector<SetEdit> line_edits;
    if (skin.empty()) {
      auto pts = probe_line_points(lines, args->samples);
      if (!pts) {
        report_error({pts.error().code, args->cage + ": " + pts.error().message});
        return;
      }
      line_points = std::move(pts->points);
      line_edits = std::move(pts->edits);
    }
    const bool on_skin = !skin.empty();
    auto time = probe_time_steps(*cage, rest, posed->positions, params, on_skin ? skin : line_points,
                                 on_skin ? edits : line_edits, args->steps, 1e-4, terminal_progress("time probe"));
    if (!time) {
      report_error({time.error().code, (on_skin ? args->skin : args->cage) + ": " + time.error().message});
      return;
    }
    const ProbeReport& r = *report;
    const ProbeLimits& lim = args->limits;
    const bool ratio_ok = ratio_passes(r, lim), continuity_ok = continuity_passes(r, lim), time_ok = time_passes(*time, lim);
    const bool passed = ratio_ok && continuity_ok && time_ok;
    if (args->json) {
      nlohmann::json jl = nlohmann::json::array();
      for (size_t i = 0; i < r.lines.size(); ++i) {
        const LineProbe& l = r.lines[i];
        jl.push_back({{"line", i},
                      {"what", l.what},
                      {"a", vec_json(l.a)},
                      {"b", vec_json(l.b)},
                      {"edited", l.edited},
                      {"spacing", l.spacing},
                      {"step_ratio", l.step_ratio},
                      {"at_t", l.at_t},
                      {"at", vec_json(l.at)},
                      {"half_step_ratio", l.half_step_ratio},
                      {"shrink", l.shrink}});
      }
      nlohmann::json j{{"cage", args->cage},
                       {"posed", args->posed},
                       {"variant", variant_name(r.variant)},
                       {"h", r.h},
                       {"samples", r.samples},
                       {"lines", jl},
                       {"rigid_points", r.rigid_points},
                       {"cage_stretch", r.cage.stretch},
                       {"stretch_element", r.cage.element},
                       {"worst_step_ratio", r.worst_ratio},
                       {"worst_line", r.worst_line},
                       {"ratio_over_stretch", r.figure()},
                       {"worst_shrink", r.worst_shrink},
                       {"worst_shrink_line", r.worst_shrink_line},
                       {"time", {{"on", on_skin ? "skin" : "probe lines"},
                                 {"steps", time->steps},
                                 {"points", time->points},
                                 {"measured", time->measured},
                                 {"worst_ratio", time->worst_ratio},
                                 {"worst_point", time->worst_point},
                                 {"worst_step", time->worst_step},
                                 {"worst_rest", vec_json(time->worst_rest)}}},
                       {"limits", {{"ratio", lim.max_ratio}, {"shrink", lim.max_shrink}, {"time_ratio", lim.max_time_ratio}}},
                       {"ratio_passed", ratio_ok},
                       {"continuity_passed", continuity_ok},
                       {"time_passed", time_ok},
                       {"passed", passed},
                       {"seconds", r.seconds + time->seconds}};
      std::printf("%s\n", j.dump(1).c_str());
    } else {
      std::printf("probe             %s -> %s, variant %s, local %g, epsilon %g, K %u, h %g, %u samples per line\n",
                  args->cage.c_str(), args->posed.c_str(), variant_name(r.variant), params.local, params.epsilon,
                  params.max_elements, r.h, r.samples);
      std::printf("%4s  %-66s %10s %10s %9s %7s\n", "line", "what", "spacing", "step ratio", "at half", "shrink");
      for (size_t i = 0; i < r.lines.size(); ++i) {
        const LineProbe& l = r.lines[i];
        std::printf("%4zu  %-66s %10.3e %10.4f %9.4f %7.3f\n", i, l.what.c_str(), l.spacing, l.step_ratio,
                    l.half_step_ratio, l.shrink);
      }
      const LineProbe& worst = r.lines[r.worst_line];
      std::printf("cage stretch      %.4f (element %u)\n", r.cage.stretch, r.cage.element);
      std::printf("worst step ratio  %.4f on line %zu at (%g, %g, %g) = %.3f x the cage's largest stretch (limit %g): %s\n",
                  r.worst_ratio, r.worst_line, worst.at.x, worst.at.y, worst.at.z, r.figure(), lim.max_ratio,
                  verdict(ratio_ok));
      std::printf("continuity        worst shrink %.3f on line %zu (limit %g; 0.5 continuous, 1 a jump): %s\n",
                  r.worst_shrink, r.worst_shrink_line, lim.max_shrink, verdict(continuity_ok));
      std::printf("time steps        worst step %.3f x the point's average, %s point %u at step %u of %u, %zu of %zu "
                  "points measured (limit %g): %s\n",
                  time->worst_ratio, on_skin ? "skin" : "probe", time->worst_point, time->worst_step, time->steps,
                  time->measured, time->points, lim.max_time_ratio, verdict(time_ok));
      if (r.rigid_points > 0)
        std::printf("note              %u probe points have no contributing element (they follow their nearest "
                    "element rigidly)\n",
                    r.rigid_points);
      std::printf("result            %s\n", verdict(passed));
    }
    exit_code = passed ? 0 : 1;
  });
}

}  // namespace cagewrap::app
