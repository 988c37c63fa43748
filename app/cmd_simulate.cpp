// cagewrap simulate --project P [--clip NAME|INDEX|all] [--enable] [--every n] [--json]
// Runs the project's cage simulation (core/rig/clip_sim.h) over clips, as the editor's playback and the
// baked-animation export do, and prints per-frame figures (solve time, largest displacement from
// the skinned cage, energy, largest edge stretch) and a summary with the milliseconds per frame.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <numeric>

#include <nlohmann/json.hpp>

#include "app/cli_common.h"
#include "app/commands.h"
#include "core/cage/cage_attachment.h"
#include "core/rig/clip_sim.h"
#include "core/document/project_io.h"

namespace cagewrap::app {

void add_simulate_command(CLI::App& app, int& exit_code) {
  struct Args {
    std::string project, clip = "all";
    bool enable = false, json = false;
    size_t every = 1;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("simulate", "run a project's cage simulation over its clips and time it");
  cmd->add_option("--project", args->project, "project file (.cagewrap)")->required();
  cmd->add_option("--clip", args->clip, "clip name or index, or 'all'")->capture_default_str();
  cmd->add_flag("--enable", args->enable, "simulate even when the project has its simulation turned off");
  cmd->add_option("--every", args->every, "print every n-th frame (0: the summary only)")->capture_default_str();
  cmd->add_flag("--json", args->json, "print the figures as one JSON object");
  cmd->callback([args, &exit_code] {
    exit_code = 1;
    const std::string& P = args->project;
    auto loaded = load_project_or_report(P);
    if (!loaded) return;
    Document doc = loaded->document;
    const Character& ch = *doc.character;
    if (!doc.cage) {
      std::fprintf(stderr, "error: %s has no cage to simulate\n", P.c_str());
      return;
    }
    if (!doc.sim.enabled && !args->enable) {
      std::fprintf(stderr,
                   "error: %s: the simulation is off (turn it on in the editor's Simulation panel, or pass --enable)\n",
                   P.c_str());
      return;
    }
    doc.sim.enabled = true;
    std::vector<int32_t> clips;
    if (args->clip == "all") {
      for (size_t c = 0; c < ch.clips.size(); ++c) clips.push_back(static_cast<int32_t>(c));
    } else {
      const int32_t c = ch.find_clip(args->clip);
      if (c < 0) {
        std::fprintf(stderr, "error: %s: its character has no clip named or numbered '%s'\n", P.c_str(),
                     args->clip.c_str());
        return;
      }
      clips.push_back(c);
    }
    if (clips.empty()) {
      std::fprintf(stderr, "error: %s: the character has no clips to simulate\n", P.c_str());
      return;
    }
    std::optional<CageAttachment> attachment;
    std::optional<Rig> rig;
    if (!ch.skins.empty() && doc.attachment.mode == AttachmentMode::kFitted) {  // fitted from the binding
      rig = rig_of_project(doc, P);
      if (!rig) return;
      attachment = *rig->attachment();
    } else if (!ch.skins.empty()) {
      auto att = attach_cage(ch, doc.cage_positions(), doc.attachment, doc.cage->elements);
      if (!att) {
        report_error({att.error().code, P + ": attachment: " + att.error().message});
        return;
      }
      attachment = std::move(att).value();
    }
    nlohmann::json out = nlohmann::json::array();
    for (int32_t c : clips) {
      auto sim = ClipSimulation::create(doc, attachment ? &*attachment : nullptr, c);
      if (!sim) {
        report_error({sim.error().code, P + ": " + sim.error().message});
        return;
      }
      const auto t0 = std::chrono::steady_clock::now();
      sim->complete();
      const double total_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      const auto stats = sim->stats();
      std::vector<double> ms;
      double largest = 0.0, strain = 0.0;
      for (const SimFrameStats& s : stats) {
        ms.push_back(s.ms);
        largest = std::max(largest, s.max_offset);
        strain = std::max(strain, s.edge_strain);
      }
      std::vector<double> sorted = ms;
      std::sort(sorted.begin(), sorted.end());
      const double median = sorted[sorted.size() / 2], worst = sorted.back();
      const double mean = std::accumulate(ms.begin(), ms.end(), 0.0) / static_cast<double>(ms.size());
      const CageSim& solver = sim->solver();
      const std::string& name = ch.clips[c].name;
      if (args->json) {
        nlohmann::json frames = nlohmann::json::array();
        for (size_t f = 0; f < stats.size(); ++f)
          frames.push_back({{"time", sim->frame_time(f)}, {"ms", stats[f].ms}, {"max_offset", stats[f].max_offset},
                            {"energy", stats[f].energy}, {"edge_strain", stats[f].edge_strain}});
        out.push_back({{"clip", name},
                       {"frames", stats.size()},
                       {"vertices", solver.num_vertices()},
                       {"free_vertices", solver.num_free()},
                       {"edges", solver.num_edges()},
                       {"substeps", doc.sim.params.substeps},
                       {"ms_per_frame_median", median},
                       {"ms_per_frame_mean", mean},
                       {"ms_per_frame_max", worst},
                       {"total_ms_with_posing", total_ms},
                       {"max_offset", largest},
                       {"max_edge_strain", strain},
                       {"per_frame", frames}});
        continue;
      }
      std::printf("clip '%s': %zu frames at %g fps, %d substeps (dt %.4g s), %zu cage vertices (%zu free), %zu edges\n",
                  name.c_str(), stats.size(), doc.sim.params.frame_rate, doc.sim.params.substeps, solver.dt(),
                  solver.num_vertices(), solver.num_free(), solver.num_edges());
      if (args->every > 0) {
        std::printf("  frame   time s   solve ms   max offset m   edge stretch   energy\n");
        for (size_t f = 0; f < stats.size(); f += args->every)
          std::printf("  %5zu  %7.3f  %9.3f  %13.5f  %12.4f%%  %.4g\n", f, sim->frame_time(f), stats[f].ms,
                      stats[f].max_offset, 100.0 * stats[f].edge_strain, stats[f].energy);
      }
      std::printf("  solve ms/frame: median %.3f, mean %.3f, max %.3f (one thread); %.1f ms in all with posing; "
                  "largest displacement %.4f m; largest edge stretch %.2f%%\n",
                  median, mean, worst, total_ms, largest, 100.0 * strain);
    }
    if (args->json) std::printf("%s\n", out.dump(2).c_str());
    exit_code = 0;
  });
}

}  // namespace cagewrap::app
