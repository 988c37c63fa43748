// cagewrap bench --mesh M --cage C --posed-cage C2 [--subdivide n] [--variant v|all] [--twist inputs.json] [--gpu] [--json]
//                [--export-skin S.obj] [--score-deformed D.bin]   (bench/peers/: the same meshes in another tool)
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "app/bench_gpu.h"
#include "app/bench_probe.h"
#include "app/bench_reweight.h"
#include "app/cli_common.h"
#include "app/commands.h"
#include "core/deform/deformer.h"
#include "core/deform/lipschitz_probe.h"
#include "core/geometry/mesh_io.h"
#include "core/geometry/subdivide.h"
#include "core/deform/twist.h"

namespace cagewrap::app {

namespace {

// The process's peak resident size since start or since reset_peak_rss() (Linux: VmHWM), else its
// peak since start.
double peak_rss_mb() {
  if (std::FILE* f = std::fopen("/proc/self/status", "r")) {
    char line[256];
    double kb = -1;
    while (std::fgets(line, sizeof line, f))
      if (std::sscanf(line, "VmHWM: %lf kB", &kb) == 1) break;
    std::fclose(f);
    if (kb >= 0) return kb / 1024.0;
  }
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss / 1024.0;
}

// Starts the peak over (Linux >= 4.0: writing 5 to clear_refs resets VmHWM), so that the bandwidth
// probe's arrays measured before the binds are not in the peak memory figure.
void reset_peak_rss() {
  if (std::FILE* f = std::fopen("/proc/self/clear_refs", "w")) {
    std::fputs("5", f);
    std::fclose(f);
  }
}

struct BenchResult {
  std::string variant;
  double bind_s = 0, deform_median_ms = 0, deform_min_ms = 0;
  double binding_bytes_per_vertex = 0, table_bytes_per_vertex = 0, mean_set = 0;
  double table_s = 0;  // making the deformer: the compact table (Deformer::create)
  bool compact = false;
  size_t bytes_read = 0, bytes_written = 0;
  double gbps = 0, quality = 0;
  bool has_twist = false;
  Fidelity twist;
  size_t affected_points = 0, affected_elements = 0;
  std::optional<GpuBenchFigures> gpu;
  ProbeReport lipschitz;  // the automatic probe lines (core/deform/lipschitz_probe.h) at kBenchProbeSamples
  std::optional<ReweightFigures> reweight;
  std::optional<TopologyEditFigures> topology;
};

// Samples per probe line for the bench's Lipschitz line: the probe binds only its own points (a few
// tens of lines of 3 x samples points): about 0.3 s per variant, whatever the skin.
constexpr uint32_t kBenchProbeSamples = 1025;

}  // namespace

void add_bench_command(CLI::App& app, int& exit_code) {
  struct Args {
    std::string mesh, cage, posed, twist, variant_list = variant_name(BindParams{}.variant);
    std::string export_skin, score_deformed, project, clip = "0", table = "compact";
    uint32_t subdivide = 0, changes = 20;
    bool json = false, gpu = false, reweight = false, reweight_verify = false, topology_edit = false;
    BindOptions bind;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("bench", "time bind and deform, measure memory and twist fidelity");
  cmd->add_option("--mesh", args->mesh, "skin mesh at rest (required without --project)");
  cmd->add_option("--cage", args->cage, "cage at rest (required without --project)");
  cmd->add_option("--posed-cage", args->posed, "the same cage, moved (required without --project)");
  cmd->add_option("--project", args->project,
                  "instead: time a project's deformer stack (each deformer's bind and pose, the stack's, the combination)");
  cmd->add_option("--clip", args->clip, "with --project: the clip posed, by name or index")->capture_default_str();
  cmd->add_option("--subdivide", args->subdivide, "cut every skin edge n times first ((n+1)^2 triangles each)");
  cmd->add_option("--changes", args->changes, "cage changes to time (>= 20)")->capture_default_str();
  cmd->add_option("--twist", args->twist, "inputs.json with the analytic twist: report fidelity to it");
  cmd->add_flag("--json", args->json, "print one JSON object instead of a table");
  cmd->add_option("--export-skin", args->export_skin,
                  "write the skin the bench deforms (after --subdivide) to this .obj first, for another tool");
  cmd->add_option("--score-deformed", args->score_deformed,
                  "score another tool's deformed skin for the posed cage instead of timing (raw float32 #P x 3 in "
                  "the skin's vertex order, .bin): its twist fidelity, the same figure (needs --twist)");
  cmd->add_option("--table", args->table,
                  "the table the kernel reads: compact (points in groups of 8, 16-bit ids, 24-bit weights; "
                  "core/deform/kernel_table.h) or float (the binding's own)")
      ->check(CLI::IsMember({"compact", "float"}))
      ->capture_default_str();
  cmd->add_flag("--gpu", args->gpu,
                "also time the OpenGL 4.3 compute path (deform + normals, GL timer queries) in a headless EGL context");
  add_bind_options(*cmd, args->bind);
  cmd->remove_option(cmd->get_option("--variant"));
  args->bind.variant_option = nullptr;  // removed: --variant here takes a list
  cmd->add_option("--variant", args->variant_list, "basic | clamped | extended | all")->capture_default_str();
  cmd->add_flag("--reweight", args->reweight,
                "also time slider drags of local, epsilon and K re-weighted from a candidate cache (each with its new "
                "deformer table)");
  cmd->add_flag("--reweight-verify", args->reweight_verify,
                "with --reweight: bind each step afresh too and check the cache's result is identical");
  cmd->add_flag("--topology-edit", args->topology_edit,
                "also refine one cage face after the bind and time carrying the binding across it (rows of the "
                "points out of its reach kept) against a fresh bind");
  cmd->callback([args, &exit_code] {
    exit_code = 1;
    if (args->changes < 20) {
      std::fprintf(stderr, "error: --changes must be at least 20\n");
      return;
    }
    if (!args->project.empty()) {
      exit_code = bench_stack(args->project, args->clip, args->changes, args->json);
      return;
    }
    if (args->mesh.empty() || args->cage.empty() || args->posed.empty()) {
      std::fprintf(stderr, "error: give --mesh, --cage and --posed-cage (or --project)\n");
      return;
    }
    if (!args->score_deformed.empty() && args->twist.empty()) {
      std::fprintf(stderr, "error: --score-deformed needs --twist (the reference it is scored against)\n");
      return;
    }
    std::vector<std::string> variants;
    if (args->variant_list == "all") variants = {"basic", "clamped", "extended"};
    else variants = {args->variant_list};
    auto mesh = load_mesh_or_report(args->mesh);
    if (!mesh) return;
    auto cage = load_cage_or_report(args->cage);
    if (!cage) return;
    auto posed = load_mesh_or_report(args->posed);
    if (!posed) return;
    if (posed->num_vertices() != cage->num_vertices()) {
      std::fprintf(stderr, "error: %s has %zu vertices but %s has %zu\n", args->posed.c_str(), posed->num_vertices(),
                   args->cage.c_str(), cage->num_vertices());
      return;
    }
    std::optional<Twist> twist;
    if (!args->twist.empty()) {
      auto t = load_twist(args->twist);
      if (!t) {
        report_error(t.error());
        return;
      }
      twist = *t;
    }
    std::unique_ptr<GpuBench> gpu;
    if (args->gpu) {
      auto g = GpuBench::create();
      if (!g) {
        report_error(g.error());
        return;
      }
      gpu = std::move(g).value();
    }
    if (args->subdivide > 0) *mesh = subdivide_edges_uniform(*mesh, args->subdivide);
    const auto& skin = mesh->positions;
    if (!args->export_skin.empty()) {
      if (auto s = save_obj(args->export_skin, skin, *mesh); !s) {
        report_error(s.error());
        return;
      }
    }
    const double diag = bounding_box(skin).diagonal();
    std::vector<glm::vec3> reference;
    if (twist) {
      reference.resize(skin.size());
      for (size_t i = 0; i < skin.size(); ++i) reference[i] = glm::vec3(twist->apply(glm::dvec3(skin[i])));
    }
    if (!args->score_deformed.empty()) {
      auto other = load_bin(args->score_deformed);
      if (!other) {
        report_error(other.error());
        return;
      }
      if (other->size() != skin.size()) {
        std::fprintf(stderr, "error: %s holds %zu points but the skin (%s, --subdivide %u) has %zu\n",
                     args->score_deformed.c_str(), other->size(), args->mesh.c_str(), args->subdivide, skin.size());
        return;
      }
      for (size_t i = 0; i < other->size(); ++i) {
        const glm::vec3& q = (*other)[i];
        if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z)) {
          std::fprintf(stderr, "error: %s: point %zu is not finite\n", args->score_deformed.c_str(), i);
          return;
        }
      }
      const Fidelity f = relative_distance(*other, reference, diag);
      if (args->json)
        std::printf("%s\n", nlohmann::json{{"points", skin.size()}, {"twist", {{"rms", f.rms}, {"max", f.max}}}}.dump(1).c_str());
      else
        std::printf("%s: %zu points, twist rms %.3e max %.3e\n", args->score_deformed.c_str(), skin.size(), f.rms, f.max);
      exit_code = 0;
      return;
    }
    // N distinct cage states between rest and posed; the last is the posed cage itself
    std::vector<std::vector<glm::vec3>> states(args->changes, cage->polygons.positions);
    for (uint32_t k = 0; k < args->changes; ++k) {
      double t = double(k + 1) / args->changes;
      for (size_t v = 0; v < states[k].size(); ++v)
        states[k][v] = glm::vec3(glm::mix(glm::dvec3(cage->polygons.positions[v]), glm::dvec3(posed->positions[v]), t));
    }
    // the memory-bandwidth probe, in the same run and on the same threads, before and after the timings
    // (its arrays are freed before the binds; the peak memory figure is taken before the second)
    const BandwidthProbe probe_before = measure_bandwidth();
    reset_peak_rss();
    std::vector<BenchResult> results;
    std::vector<Tri> triangles;  // for the GPU path's normals
    for (const auto& vname : variants) {
      BindOptions opts = args->bind;
      opts.variant = vname;
      if (!finish_bind_options(opts)) return;
      BenchResult r;
      r.variant = vname;
      auto b = bind_skin(skin, *cage, cage->polygons.positions, opts.params);
      if (!b) {
        report_error(b.error());
        return;
      }
      r.bind_s = b->seconds;
      r.binding_bytes_per_vertex = double(b->bytes()) / skin.size();
      r.mean_set = double(b->total_set_size) / skin.size();
      r.quality = b->quality();
      r.affected_points = b->rigid_points.size();
      r.affected_elements = b->invalid_elements.size();
      const auto tc0 = std::chrono::steady_clock::now();
      auto d = Deformer::create(*b, skin, args->table == "float" ? TableFormat::kFloat : TableFormat::kCompact);
      r.table_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - tc0).count();
      if (!d) {
        report_error(d.error());
        return;
      }
      std::vector<glm::vec3> out(skin.size());
      (void)d->deform(states[0], out);  // warm-up: first touch of the output pages
      std::vector<double> ms;
      for (const auto& state : states) {
        auto t0 = std::chrono::steady_clock::now();
        auto s = d->deform(state, out);
        auto t1 = std::chrono::steady_clock::now();
        if (!s) {
          report_error(s.error());
          return;
        }
        ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
      }
      std::sort(ms.begin(), ms.end());
      r.deform_median_ms = ms[ms.size() / 2];
      r.deform_min_ms = ms.front();
      r.compact = d->kernel_table() != nullptr;
      r.table_bytes_per_vertex = double(d->table_bytes()) / skin.size();
      r.bytes_read = d->bytes_read_per_call();
      r.bytes_written = d->bytes_written_per_call();
      r.gbps = double(r.bytes_read + r.bytes_written) / (r.deform_median_ms * 1e-3) / 1e9;
      if (twist) {  // `out` holds the last state: the posed cage
        r.has_twist = true;
        r.twist = relative_distance(out, reference, diag);
      }
      if (gpu) {
        if (triangles.empty()) triangles = triangulate(*mesh).triangles;
        auto g = gpu->run(*d, triangles, states, out, diag);
        if (!g) {
          report_error(g.error());
          return;
        }
        r.gpu = *g;
      }
      // the Lipschitz figure (issue 18) on the bench's own cages: the automatic probe lines only
      const auto& rest = cage->polygons.positions;
      const auto lines = automatic_probe_lines(*cage, rest, opts.params, probe_scale(*cage, rest, opts.params));
      auto probe = probe_lipschitz(*cage, rest, posed->positions, opts.params, lines, kBenchProbeSamples);
      if (!probe) {
        report_error({probe.error().code, args->cage + ": " + probe.error().message});
        return;
      }
      r.lipschitz = std::move(probe).value();
      if (args->reweight || args->reweight_verify) {
        d = make_error(ErrorCode::kInvalidArgument, "released");  // the timed deformer's table, freed first
        b = make_error(ErrorCode::kInvalidArgument, "released");
        auto rw = bench_reweight(skin, *cage, cage->polygons.positions, opts.params, args->reweight_verify);
        if (!rw) {
          report_error(rw.error());
          return;
        }
        r.reweight = std::move(rw).value();
      }
      if (args->topology_edit) {
        d = make_error(ErrorCode::kInvalidArgument, "released");
        b = make_error(ErrorCode::kInvalidArgument, "released");
        auto te = bench_topology_edit(skin, *cage, cage->polygons.positions, opts.params);
        if (!te) {
          report_error(te.error());
          return;
        }
        r.topology = std::move(te).value();
      }
      results.push_back(r);
    }
    const double peak_mb = peak_rss_mb();
    const BandwidthProbe probe = best_of(probe_before, measure_bandwidth());
    if (args->json) {
      nlohmann::json j;
      j["points"] = skin.size();
      j["elements"] = cage->num_elements();
      j["peak_rss_mb"] = peak_mb;
      j["kernel_isa"] = kernel_isa_name();
      j["bandwidth_probe"] = {{"triad_gbps", probe.triad_gbps},
                              {"read_gbps", probe.read_gbps},
                              {"array_bytes", probe.array_bytes},
                              {"runs", probe.runs},
                              {"threads", probe.threads}};
      if (gpu) j["gpu_device"] = gpu->device();
      for (const auto& r : results) {
        nlohmann::json v{{"variant", r.variant},
                         {"bind_s", r.bind_s},
                         {"deform_median_ms", r.deform_median_ms},
                         {"deform_min_ms", r.deform_min_ms},
                         {"binding_bytes_per_vertex", r.binding_bytes_per_vertex},
                         {"table", r.compact ? "compact" : "float"},
                         {"table_bytes_per_vertex", r.table_bytes_per_vertex},
                         {"table_s", r.table_s},
                         {"probe_ratio", r.gbps / probe.triad_gbps},
                         {"mean_set_size", r.mean_set},
                         {"bytes_read_per_change", r.bytes_read},
                         {"bytes_written_per_change", r.bytes_written},
                         {"effective_gbps", r.gbps},
                         {"cage_quality", r.quality},
                         {"affected_points", r.affected_points},
                         {"affected_elements", r.affected_elements}};
        if (r.has_twist) v["twist"] = {{"rms", r.twist.rms}, {"max", r.twist.max}};
        v["lipschitz"] = {{"worst_step_ratio", r.lipschitz.worst_ratio},
                          {"cage_stretch", r.lipschitz.cage.stretch},
                          {"ratio_over_stretch", r.lipschitz.figure()},
                          {"worst_shrink", r.lipschitz.worst_shrink},
                          {"lines", r.lipschitz.lines.size()},
                          {"samples", r.lipschitz.samples},
                          {"seconds", r.lipschitz.seconds}};
        if (r.reweight) {
          nlohmann::json steps = nlohmann::json::array();
          for (const auto& st : r.reweight->steps) {
            nlohmann::json x{{"slider", st.slider},          {"value", st.value},
                             {"reweight_s", st.reweight_s},  {"table_s", st.table_s},
                             {"cached_points", st.cached_points}, {"queried_points", st.queried_points}};
            if (r.reweight->verified) x["fresh_bind_s"] = st.fresh_s, x["identical"] = st.difference.empty();
            steps.push_back(x);
          }
          v["reweight"] = {{"cache_s", r.reweight->cache_s},
                           {"cache_bytes", r.reweight->cache_bytes},
                           {"entries_per_point", r.reweight->entries_per_point},
                           {"steps", steps}};
        }
        if (r.topology)
          v["topology_edit"] = {{"refined_face", r.topology->face},
                                {"added_elements", r.topology->added_elements},
                                {"removed_elements", r.topology->removed_elements},
                                {"points_registered", r.topology->points},
                                {"seconds", r.topology->seconds},
                                {"fresh_bind_s", r.topology->fresh_s},
                                {"identical", r.topology->difference.empty()}};
        if (r.gpu)
          v["gpu"] = {{"deform_median_ms", r.gpu->deform_ms},
                      {"normals_median_ms", r.gpu->normals_ms},
                      {"total_median_ms", r.gpu->total_ms},
                      {"total_min_ms", r.gpu->total_min_ms},
                      {"wall_deform_median_ms", r.gpu->wall_deform_ms},
                      {"wall_normals_median_ms", r.gpu->wall_normals_ms},
                      {"cpu_maps_median_ms", r.gpu->maps_ms},
                      {"cpu_normals_median_ms", r.gpu->cpu_normals_ms},
                      {"max_distance_to_cpu", r.gpu->max_distance},
                      {"max_normal_angle_to_cpu_degrees", r.gpu->max_normal_degrees},
                      {"gpu_bytes", r.gpu->gpu_bytes},
                      {"upload_bytes_per_change", r.gpu->upload_bytes}};
        j["variants"].push_back(v);
      }
      std::printf("%s\n", j.dump(1).c_str());
    } else {
      std::printf("skin %zu points, cage %zu elements, %u cage changes timed\n", skin.size(), cage->num_elements(),
                  args->changes);
      std::printf("bandwidth probe (same run, %d threads, 3 x %.0f MB, best of %d runs before and after): triad %.1f "
                  "GB/s, read %.1f GB/s\n",
                  probe.threads, probe.array_bytes / 1e6, probe.runs, probe.triad_gbps, probe.read_gbps);
      std::printf("%-9s %8s %8s %10s %9s %9s %9s %7s %9s %11s %7s %6s %8s %10s %10s\n", "variant", "bind s", "table s",
                  "deform ms", "min ms", "B/vertex", "table B/v", "set", "MB read", "MB written", "GB/s", "probe",
                  "quality", "twist rms", "twist max");
      for (const auto& r : results) {
        std::printf("%-9s %8.3f %8.3f %10.2f %9.2f %9.1f %8.1f%s %7.2f %9.1f %11.1f %7.1f %5.0f%% %7.2f%%",
                    r.variant.c_str(), r.bind_s, r.table_s, r.deform_median_ms, r.deform_min_ms,
                    r.binding_bytes_per_vertex, r.table_bytes_per_vertex, r.compact ? "c" : "f", r.mean_set,
                    r.bytes_read / 1e6, r.bytes_written / 1e6, r.gbps, 100 * r.gbps / probe.triad_gbps, 100 * r.quality);
        if (r.has_twist) std::printf(" %10.2e %10.2e", r.twist.rms, r.twist.max);
        std::printf("\n");
      }
      if (gpu) {
        std::printf("GPU path: %s\n", gpu->device().c_str());
        if (gpu->software())
          std::printf("software OpenGL: its timer queries do not see compute work (they read 0) and its 'GPU' is this "
                      "CPU; read the wall times\n");
        std::printf("%-9s %10s %10s %9s %8s %9s %9s %9s %9s %9s %11s %10s %8s\n", "variant", "deform ms", "normals ms",
                    "total ms", "min ms", "wall def", "wall nrm", "maps ms", "CPU def", "CPU nrm", "|GPU-CPU|",
                    "normal deg", "GPU MB");
        for (const auto& r : results) {
          const auto& g = *r.gpu;
          std::printf("%-9s %10.3f %10.3f %9.3f %8.3f %9.2f %9.2f %9.3f %9.2f %9.2f %11.2e %10.2e %8.1f\n",
                      r.variant.c_str(), g.deform_ms, g.normals_ms, g.total_ms, g.total_min_ms, g.wall_deform_ms,
                      g.wall_normals_ms, g.maps_ms, r.deform_median_ms, g.cpu_normals_ms, g.max_distance,
                      g.max_normal_degrees, g.gpu_bytes / 1e6);
        }
      }
      std::printf("table: c = compact (core/deform/kernel_table.h; kernel code: %s), f = the binding's float table; "
                  "probe: the kernel's GB/s as a share of the probe's triad\n",
                  kernel_isa_name());
      std::printf("peak memory %.0f MB\n", peak_mb);
      for (const auto& r : results)
        if (r.topology)
          std::printf("topology edit (%s): face %u refined (%zu elements added, %zu removed): %zu of %zu points "
                      "registered again in %.3f s (fresh bind %.3f s), identical: %s\n",
                      r.variant.c_str(), r.topology->face, r.topology->added_elements, r.topology->removed_elements,
                      r.topology->points, skin.size(), r.topology->seconds, r.topology->fresh_s,
                      r.topology->difference.empty() ? "yes" : ("NO: " + r.topology->difference).c_str());
      for (const auto& r : results) {
        if (!r.reweight) continue;
        const ReweightFigures& f = *r.reweight;
        std::printf("reweight (%s): candidate cache %.3f s, %.1f MB (%.1f elements per point)\n", r.variant.c_str(),
                    f.cache_s, f.cache_bytes / 1e6, f.entries_per_point);
        std::printf("  %-8s %8s %11s %8s %8s %9s%s\n", "slider", "value", "reweight s", "table s", "cached", "queried",
                    f.verified ? "  fresh bind s  identical" : "");
        for (const auto& st : f.steps) {
          std::printf("  %-8s %8.3f %11.3f %8.3f %7.2f%% %9llu", st.slider.c_str(), st.value, st.reweight_s, st.table_s,
                      100.0 * double(st.cached_points) / double(std::max<uint64_t>(1, st.cached_points + st.queried_points)),
                      static_cast<unsigned long long>(st.queried_points));
          if (f.verified) std::printf("  %13.3f  %s", st.fresh_s, st.difference.empty() ? "yes" : ("NO: " + st.difference).c_str());
          std::printf("\n");
        }
      }
      for (const auto& r : results)
        std::printf("lipschitz: worst step ratio %.3f (%.3f x the cage's largest stretch %.3f) over %zu probe lines "
                    "(%s, %u samples, worst shrink %.3f, %.2f s)\n",
                    r.lipschitz.worst_ratio, r.lipschitz.figure(), r.lipschitz.cage.stretch, r.lipschitz.lines.size(),
                    r.variant.c_str(), r.lipschitz.samples, r.lipschitz.worst_shrink, r.lipschitz.seconds);
    }
    for (const auto& r : results)
      if (r.topology && !r.topology->difference.empty()) {
        std::fprintf(stderr, "error: %s: the binding carried across the topology edit differs from a fresh bind (%s)\n",
                     r.variant.c_str(), r.topology->difference.c_str());
        return;
      }
    for (const auto& r : results)
      if (r.reweight)
        for (const auto& st : r.reweight->steps)
          if (!st.difference.empty()) {
            std::fprintf(stderr, "error: %s, %s %.3f: the re-weighted binding differs from a fresh bind (%s)\n",
                         r.variant.c_str(), st.slider.c_str(), st.value, st.difference.c_str());
            return;
          }
    exit_code = 0;
  });
}

}  // namespace cagewrap::app
