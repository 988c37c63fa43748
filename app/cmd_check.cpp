// cagewrap check --project P | --character C [--cage K | --auto-cage N] [--clip NAME]... [--fps f]
//                [--max-worst x] [--max-rms x] [--max-stretch x] [--json]
// Poses the rig at every clip's frames and compares it with the character's own linear blend
// skinning (core/rig/fidelity.h): worst and RMS vertex distance as a share of the bounding-box diagonal,
// the largest skin-edge stretch, and where each happens. Exit 0 within the thresholds, 2 over them,
// 1 on an error.
#include <cstdio>
#include <sstream>

#include <nlohmann/json.hpp>

#include "app/auto_cage_options.h"
#include "app/cli_common.h"
#include "app/commands.h"
#include "core/character/skin_mask.h"
#include "core/rig/fidelity.h"
#include "core/document/project_io.h"

namespace cagewrap::app {

namespace {

std::string joint_name(const Skeleton& sk, int32_t j) {
  return j >= 0 && size_t(j) < sk.size() ? sk.node(j).name : std::string("-");
}

nlohmann::json frame_json(const FrameFidelity& f, const Skeleton& sk, double diagonal) {
  return {{"clip", f.clip},
          {"time", f.time},
          {"worst", f.worst},
          {"worst_length", f.worst * diagonal},
          {"rms", f.rms},
          {"worst_vertex", f.worst_vertex},
          {"worst_joint", joint_name(sk, f.worst_joint)},
          {"stretch", f.stretch},
          {"squash", f.squash},
          {"stretch_edge", {f.stretch_edge[0], f.stretch_edge[1]}},
          {"stretch_joint", joint_name(sk, f.stretch_joint)}};
}

nlohmann::json clip_json(const ClipFidelity& c, const Skeleton& sk, double diagonal) {
  return {{"clip", c.clip},
          {"name", c.name},
          {"frames", c.frames},
          {"rms_all", c.rms_all},
          {"worst", frame_json(c.worst, sk, diagonal)},
          {"rms", frame_json(c.rms, sk, diagonal)},
          {"stretch", frame_json(c.stretch, sk, diagonal)}};
}

nlohmann::json fidelity_json(const FidelityReport& r, const Skeleton& sk) {
  nlohmann::json clips = nlohmann::json::array();
  for (const ClipFidelity& c : r.clips) clips.push_back(clip_json(c, sk, r.diagonal));
  nlohmann::json failures = nlohmann::json::array();
  for (const std::string& f : r.failures(sk)) failures.push_back(f);
  return {{"diagonal", r.diagonal},
          {"units", r.units},
          {"vertices", r.vertices},
          {"edges_judged", r.edges_judged},
          {"thresholds", {{"worst", r.thresholds.worst}, {"rms", r.thresholds.rms}, {"stretch", r.thresholds.stretch}}},
          {"passed", r.passed()},
          {"failures", failures},
          {"overall", clip_json(r.overall, sk, r.diagonal)},
          {"clips", clips}};
}

void print_fidelity_table(const FidelityReport& r, const Skeleton& sk) {
  std::printf("fidelity to the character's own skinning: %zu vertices, %zu edges judged, diagonal %s\n", r.vertices,
              r.edges_judged, format_length(r.diagonal, r.units).c_str());
  std::printf("%-16s %6s %8s %8s %-14s %7s %8s %8s %-14s\n", "clip", "frames", "worst%", "at s", "worst joint",
              "RMS%", "stretch", "at s", "stretch joint");
  auto row = [&](const ClipFidelity& c) {
    std::printf("%-16s %6zu %8.3f %8.3f %-14s %7.3f %8.2f %8.3f %-14s\n", c.name.c_str(), c.frames,
                100 * c.worst.worst, c.worst.time, joint_name(sk, c.worst.worst_joint).c_str(), 100 * c.rms.rms,
                c.stretch.stretch, c.stretch.time, joint_name(sk, c.stretch.stretch_joint).c_str());
  };
  for (const ClipFidelity& c : r.clips) row(c);
  row(r.overall);
  std::printf("worst vertex %s (vertex %u); thresholds: worst %.3g%%, RMS %.3g%%, stretch %.3gx\n",
              format_length(r.overall.worst.worst * r.diagonal, r.units).c_str(), r.overall.worst.worst_vertex,
              100 * r.thresholds.worst, 100 * r.thresholds.rms, r.thresholds.stretch);
  const auto failures = r.failures(sk);
  if (failures.empty()) std::printf("passed\n");
  for (const std::string& f : failures) std::printf("FAILED: %s\n", f.c_str());
}

}  // namespace

void add_check_command(CLI::App& app, int& exit_code) {
  struct Args {
    std::string project, character, cage, region_joints;
    std::vector<std::string> clips;
    FidelityOptions options;
    AutoCageOptions auto_cage;
    CLI::Option* auto_cage_option = nullptr;
    bool json = false, no_rest = false, keep_units = false;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "check", "compare a rig with the character's own skinning at every clip's frames (worst vertex, RMS, edge stretch)");
  cmd->add_option("--project", args->project, "project (.cagewrap)");
  cmd->add_option("--character", args->character,
                  "character (.glb .gltf .fbx .dae .x ...): checks the default rig (the automatic cage unless --cage is given)");
  add_keep_units_flag(*cmd, args->keep_units);
  cmd->add_option("--cage", args->cage, "with --character: the cage at rest (.obj .ply .off .stl)");
  args->auto_cage_option = add_auto_cage_options(*cmd, args->auto_cage, "--auto-cage");
  args->auto_cage_option->description("with --character: the automatic cage's triangle count (default 2000)");
  cmd->add_option("--clip", args->clips, "clip name or index (repeatable; default every clip)");
  cmd->add_option("--fps", args->options.fps, "frames per second sampled along each clip, on top of 10/30/50/70/90%")
      ->capture_default_str();
  cmd->add_flag("--no-rest", args->no_rest, "do not judge the rest pose");
  cmd->add_option("--max-worst", args->options.thresholds.worst, "threshold: worst vertex, share of the diagonal")
      ->capture_default_str();
  cmd->add_option("--max-rms", args->options.thresholds.rms, "threshold: RMS at the worst frame, share of the diagonal")
      ->capture_default_str();
  cmd->add_option("--max-stretch", args->options.thresholds.stretch, "threshold: largest skin-edge stretch")
      ->capture_default_str();
  cmd->add_option("--region-joints", args->region_joints,
                  "judge only the skin these joints and their children move (a,b,c: their skin weights over 0.5; -name leaves one out: spine,-neck)");
  cmd->add_flag("--json", args->json, "print the report as JSON");
  cmd->callback([args, &exit_code] {
    exit_code = 1;
    if (args->project.empty() == args->character.empty()) {
      std::fprintf(stderr, "error: give either --project or --character\n");
      return;
    }
    if (!args->project.empty() && (!args->cage.empty() || args->auto_cage_option->count() || args->keep_units)) {
      std::fprintf(stderr, "error: --cage, --auto-cage and --keep-units go with --character; a project has its cage and units\n");
      return;
    }
    if (!(args->options.fps >= 0 && args->options.fps <= 1000)) {
      std::fprintf(stderr, "error: --fps must be in 0..1000\n");
      return;
    }
    args->options.rest = !args->no_rest;
    Document doc;
    std::string name;
    if (!args->project.empty()) {
      auto loaded = load_project_or_report(args->project);
      if (!loaded) return;
      doc = std::move(loaded->document);
      name = args->project;
      if (!doc.cage) {
        std::fprintf(stderr, "error: %s: the project has no cage yet\n", name.c_str());
        return;
      }
    } else {
      auto d = document_from_files(args->character, args->cage, {args->keep_units});
      if (!d) {
        report_error(d.error());
        return;
      }
      doc = std::move(d).value();
      name = args->character;
      if (!doc.cage) {
        if (!finish_auto_cage_options(args->auto_cage, doc.params)) return;
        if (!add_automatic_cage(doc, args->auto_cage.params, args->character, args->json)) return;
      }
    }
    const Character& ch = *doc.character;
    if (ch.skins.empty()) {
      std::fprintf(stderr, "error: %s: the character has no skin: there is no skinning to compare with\n", name.c_str());
      return;
    }
    for (const std::string& c : args->clips) {
      const int32_t i = ch.find_clip(c);
      if (i < 0) {
        std::fprintf(stderr, "error: %s: no clip named or numbered '%s'\n", name.c_str(), c.c_str());
        return;
      }
      args->options.clips.push_back(i);
    }
    if (!args->region_joints.empty()) {
      std::vector<std::string> names;
      std::stringstream in(args->region_joints);
      for (std::string item; std::getline(in, item, ',');)
        if (!item.empty()) names.push_back(item);
      auto region = joint_region_mask(ch, names);
      if (!region) {
        std::fprintf(stderr, "error: %s: --region-joints: %s\n", name.c_str(), region.error().message.c_str());
        return;
      }
      args->options.region = std::move(region).value();
      if (!args->json) std::printf("region: the skin of joints %s\n", args->region_joints.c_str());
    }
    std::optional<Rig> rig = rig_of_project(doc, name);
    if (!rig) return;
    if (!args->json) {
      const Binding& b = rig->binding();
      std::printf("rig: %u skin points, cage quality %.1f%%, %zu fallback points\n", b.num_points, 100 * b.quality(),
                  b.rigid_points.size());
    }
    auto report = check_fidelity(doc, *rig, args->options);
    if (!report) {
      report_error({report.error().code, name + ": " + report.error().message});
      return;
    }
    if (args->json)
      std::printf("%s\n", fidelity_json(*report, ch.skeleton).dump(2).c_str());
    else
      print_fidelity_table(*report, ch.skeleton);
    exit_code = report->passed() ? 0 : 2;
  });
}

}  // namespace cagewrap::app
