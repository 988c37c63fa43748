// cagewrap patch fit|deform|demo|bench: parametric drivers (docs/parametric-drivers.md)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <glm/common.hpp>
#include <nlohmann/json.hpp>

#include "app/cli_common.h"
#include "app/commands.h"
#include "core/base/atomic_write.h"
#include "core/geometry/mesh_io.h"
#include "core/deform/patch_binding.h"
#include "core/deform/patch_demo.h"
#include "core/deform/patch_fit.h"
#include "core/io/patch_io.h"
#include "core/geometry/subdivide.h"

namespace cagewrap::app {

namespace {

std::optional<PatchSurface> load_patch_or_report(const std::string& path) {
  auto p = load_patch_any(path);
  if (!p) {
    report_error(p.error());
    return std::nullopt;
  }
  return std::move(p).value();
}

// Binding options without --variant (a parametric driver is always the basic variant), and
// --density when `density` is given.
void add_patch_bind_options(CLI::App& cmd, BindOptions& opts, uint32_t* density) {
  add_bind_options(cmd, opts);
  cmd.remove_option(cmd.get_option("--variant"));
  opts.variant_option = nullptr;
  opts.variant = "basic";
  if (density)
    cmd.add_option("--density", *density, "samples per knot span along u and v (1 = the knot values)")
        ->capture_default_str();
}

std::vector<uint32_t> parse_list(const std::string& s, const char* what, bool& ok) {
  std::vector<uint32_t> out;
  ok = true;
  size_t i = 0;
  while (i < s.size()) {
    size_t j = s.find(',', i);
    if (j == std::string::npos) j = s.size();
    const std::string item = s.substr(i, j - i);
    char* end = nullptr;
    const unsigned long v = std::strtoul(item.c_str(), &end, 10);
    if (item.empty() || *end != '\0' || v > UINT32_MAX) {
      std::fprintf(stderr, "error: %s: \"%s\" is not a whole number >= 0\n", what, item.c_str());
      ok = false;
      return {};
    }
    out.push_back(static_cast<uint32_t>(v));
    i = j + 1;
  }
  return out;
}

void add_fit(CLI::App& parent, int& exit_code) {
  struct Args {
    std::string cage, faces, out;
    PatchFitOptions fit;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = parent.add_subcommand("fit", "fit a bicubic B-spline grid to a rectangle of cage quads");
  cmd->add_option("--cage", args->cage, "cage (OBJ, PLY, OFF, STL)")->required();
  cmd->add_option("--faces", args->faces, "the faces, as polygon indices from 0: 3,4,5,...")->required();
  cmd->add_option("--rows", args->fit.rows, "control points along v (0: one per vertex line, at least 4)");
  cmd->add_option("--cols", args->fit.cols, "control points along u (0: one per vertex line, at least 4)");
  cmd->add_option("--smoothing", args->fit.smoothing, "weight of the control points' second differences")
      ->capture_default_str();
  cmd->add_option("--out", args->out, "driver: .cwpatch, .gltf or .glb")->required();
  cmd->callback([args, &exit_code] {
    exit_code = 1;
    bool ok = false;
    const std::vector<uint32_t> faces = parse_list(args->faces, "--faces", ok);
    if (!ok) return;
    auto cage = load_mesh_or_report(args->cage);
    if (!cage) return;
    auto grid = fit_patch_to_faces(*cage, cage->positions, faces, args->fit);
    if (!grid) {
      report_error({grid.error().code, args->cage + ": " + grid.error().message});
      return;
    }
    if (auto s = save_patch_any(args->out, PatchSurface{{*grid}}); !s) {
      report_error(s.error());
      return;
    }
    std::printf("fitted a %u x %u control-point B-spline grid to %zu faces of %s, wrote %s\n", grid->rows,
                grid->cols, faces.size(), args->cage.c_str(), args->out.c_str());
    exit_code = 0;
  });
}

void add_deform(CLI::App& parent, int& exit_code) {
  struct Args {
    std::string mesh, patch, posed, out;
    BindOptions bind;
    uint32_t density = 2;
  };
  auto args = std::make_shared<Args>();
  auto* cmd =
      parent.add_subcommand("deform", "bind a skin to a patch driver and deform it by the posed driver");
  cmd->add_option("--mesh", args->mesh, "skin mesh at rest")->required();
  cmd->add_option("--patch", args->patch, "driver at rest (.cwpatch, .gltf, .glb)")->required();
  cmd->add_option("--posed-patch", args->posed, "the same driver, control points moved")->required();
  cmd->add_option("--out", args->out, "deformed skin: .obj, or .bin (raw float32 N x 3)")->required();
  add_patch_bind_options(*cmd, args->bind, &args->density);
  cmd->callback([args, &exit_code] {
    exit_code = 1;
    if (!finish_bind_options(args->bind)) return;
    if (!positions_output_or_report(args->out)) return;
    auto mesh = load_mesh_or_report(args->mesh);
    if (!mesh) return;
    auto rest = load_patch_or_report(args->patch);
    if (!rest) return;
    auto posed = load_patch_or_report(args->posed);
    if (!posed) return;
    auto b = bind_skin_to_patches(mesh->positions, *rest, args->density, args->bind.params,
                                  terminal_progress("bind"));
    if (!b) {
      report_error({b.error().code, args->patch + ": " + b.error().message});
      return;
    }
    auto d = PatchDeformer::create(*b, mesh->positions, *rest, args->density);
    if (!d) {
      report_error({d.error().code, args->patch + ": " + d.error().message});
      return;
    }
    std::vector<glm::vec3> out(mesh->num_vertices());
    if (auto s = d->deform(*posed, out); !s) {
      report_error({s.error().code, args->posed + ": " + s.error().message});
      return;
    }
    if (auto s = save_positions(args->out, out, *mesh); !s) {
      report_error(s.error());
      return;
    }
    std::printf(
        "bound %u points to %u samples (density %u, %zu degenerate) in %.3f s: mean set %.2f, max %u\n",
        b->num_points, b->num_samples, args->density, b->invalid_elements.size(), b->seconds,
        double(b->total_set_size) / b->num_points, b->max_set_size);
    std::printf("deformed %zu points, wrote %s\n", out.size(), args->out.c_str());
    exit_code = 0;
  });
}

void add_demo(CLI::App& parent, int& exit_code) {
  struct Args {
    std::string dir;
    uint32_t resolution = 8;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = parent.add_subcommand(
      "demo", "write the generated patch test case: skin, driver, twisted driver, twist");
  cmd->add_option("--out-dir", args->dir,
                  "folder to write mesh.obj, driver.cwpatch, driver_posed.cwpatch, inputs.json")
      ->required();
  cmd->add_option("--resolution", args->resolution, "skin vertices per unit length")->capture_default_str();
  cmd->callback([args, &exit_code] {
    exit_code = 1;
    std::error_code ec;
    std::filesystem::create_directories(args->dir, ec);
    const PatchDemo demo = make_patch_demo(args->resolution);
    const std::string dir = args->dir + "/";
    nlohmann::json inputs{{"source", "cagewrap patch demo"},
                          {"twist",
                           {{"axis", demo.twist.axis},
                            {"center", {demo.twist.center.x, demo.twist.center.y, demo.twist.center.z}},
                            {"lo", demo.twist.lo},
                            {"hi", demo.twist.hi},
                            {"twist_deg", demo.twist.degrees}}}};
    for (const Status& s : {save_obj(dir + "mesh.obj", demo.skin.positions, demo.skin),
                            save_patch(dir + "driver.cwpatch", demo.driver),
                            save_patch(dir + "driver_posed.cwpatch", twisted(demo.driver, demo.twist)),
                            write_file_atomic(dir + "inputs.json", inputs.dump(1) + "\n")})
      if (!s) {
        report_error(s.error());
        return;
      }
    std::printf("wrote %smesh.obj (%zu vertices), driver.cwpatch, driver_posed.cwpatch, inputs.json\n",
                dir.c_str(), demo.skin.num_vertices());
    exit_code = 0;
  });
}

struct DensityFigures {
  uint32_t density = 0, samples = 0;
  double bind_s = 0, median_ms = 0, min_ms = 0, mean_set = 0;
  Fidelity twist, reference;
};

void add_bench(CLI::App& parent, int& exit_code) {
  struct Args {
    std::string mesh, patch, twist, densities = "1,2,4,8";
    uint32_t demo = 0, subdivide = 0, changes = 20, reference = 32;
    bool json = false;
    BindOptions bind;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = parent.add_subcommand("bench",
                                    "the sampling density's speed/fidelity trade-off: bind s, deform ms, "
                                    "twist fidelity, distance to a dense reference");
  cmd->add_option("--demo", args->demo,
                  "use the generated case (`patch demo`) at this resolution instead of files");
  cmd->add_option("--mesh", args->mesh, "skin mesh at rest");
  cmd->add_option("--patch", args->patch, "driver at rest");
  cmd->add_option("--twist", args->twist,
                  "inputs.json whose analytic twist poses the driver's control points");
  cmd->add_option("--subdivide", args->subdivide, "cut every skin edge n times first");
  cmd->add_option("--densities", args->densities, "densities to time, comma-separated")
      ->capture_default_str();
  cmd->add_option("--reference", args->reference, "density of the reference the others are measured against")
      ->capture_default_str();
  cmd->add_option("--changes", args->changes, "driver changes to time (>= 20)")->capture_default_str();
  cmd->add_flag("--json", args->json, "print one JSON object instead of a table");
  add_patch_bind_options(*cmd, args->bind, nullptr);
  cmd->callback([args, &exit_code] {
    exit_code = 1;
    if (!finish_bind_options(args->bind)) return;
    bool ok = false;
    const std::vector<uint32_t> densities = parse_list(args->densities, "--densities", ok);
    if (!ok) return;
    if (args->changes < 20) {
      std::fprintf(stderr, "error: --changes must be at least 20\n");
      return;
    }
    PolyMesh mesh;
    PatchSurface rest;
    Twist twist;
    if (args->demo > 0) {
      PatchDemo demo = make_patch_demo(args->demo);
      mesh = std::move(demo.skin);
      rest = std::move(demo.driver);
      twist = demo.twist;
    } else {
      if (args->mesh.empty() || args->patch.empty() || args->twist.empty()) {
        std::fprintf(stderr, "error: give --demo N, or --mesh, --patch and --twist\n");
        return;
      }
      auto m = load_mesh_or_report(args->mesh);
      if (!m) return;
      mesh = std::move(*m);
      auto p = load_patch_or_report(args->patch);
      if (!p) return;
      rest = std::move(*p);
      auto t = load_twist(args->twist);
      if (!t) {
        report_error(t.error());
        return;
      }
      twist = *t;
    }
    if (args->subdivide > 0) mesh = subdivide_edges_uniform(mesh, args->subdivide);
    const auto& skin = mesh.positions;
    const double diag = bounding_box(skin).diagonal();
    std::vector<glm::vec3> twisted_skin(skin.size());
    for (size_t i = 0; i < skin.size(); ++i) twisted_skin[i] = glm::vec3(twist.apply(glm::dvec3(skin[i])));
    // N driver states between rest and the twisted driver; the last is the twisted driver itself
    const PatchSurface posed = twisted(rest, twist);
    const std::vector<glm::dvec3> from = rest.control_points(), to = posed.control_points();
    std::vector<PatchSurface> states(args->changes, rest);
    for (uint32_t k = 0; k < args->changes; ++k) {
      std::vector<glm::dvec3> p(from.size());
      for (size_t i = 0; i < p.size(); ++i) p[i] = glm::mix(from[i], to[i], double(k + 1) / args->changes);
      states[k].set_control_points(p);
    }
    auto run = [&](uint32_t density, DensityFigures& f, std::vector<glm::vec3>& out) -> bool {
      auto b = bind_skin_to_patches(skin, rest, density, args->bind.params, terminal_progress("bind"));
      if (!b) {
        report_error(b.error());
        return false;
      }
      auto d = PatchDeformer::create(*b, skin, rest, density);
      if (!d) {
        report_error(d.error());
        return false;
      }
      out.assign(skin.size(), glm::vec3(0.f));
      (void)d->deform(states[0], out);  // warm-up
      std::vector<double> ms;
      for (const PatchSurface& s : states) {
        const auto t0 = std::chrono::steady_clock::now();
        if (auto st = d->deform(s, out); !st) {
          report_error(st.error());
          return false;
        }
        ms.push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      }
      std::sort(ms.begin(), ms.end());
      f.density = density;
      f.samples = b->num_samples;
      f.bind_s = b->seconds;
      f.median_ms = ms[ms.size() / 2];
      f.min_ms = ms.front();
      f.mean_set = double(b->total_set_size) / skin.size();
      f.twist = relative_distance(out, twisted_skin, diag);
      return true;
    };
    DensityFigures ref_fig;
    std::vector<glm::vec3> reference;
    if (!run(args->reference, ref_fig, reference)) return;
    std::vector<DensityFigures> rows;
    for (uint32_t density : densities) {
      DensityFigures f;
      std::vector<glm::vec3> out;
      if (!run(density, f, out)) return;
      f.reference = relative_distance(out, reference, diag);
      rows.push_back(f);
    }
    if (args->json) {
      nlohmann::json j{{"points", skin.size()},
                       {"control_points", rest.num_control_points()},
                       {"reference_density", args->reference},
                       {"rows", nlohmann::json::array()}};
      for (const DensityFigures& f : rows)
        j["rows"].push_back({{"density", f.density},
                             {"samples", f.samples},
                             {"bind_s", f.bind_s},
                             {"deform_median_ms", f.median_ms},
                             {"deform_min_ms", f.min_ms},
                             {"mean_set", f.mean_set},
                             {"twist", {{"rms", f.twist.rms}, {"max", f.twist.max}}},
                             {"reference", {{"rms", f.reference.rms}, {"max", f.reference.max}}}});
      std::printf("%s\n", j.dump(1).c_str());
    } else {
      std::printf(
          "%zu skin points, %zu control points; distances relative to the skin's diagonal; reference: "
          "density %u "
          "(%u samples, twist rms %.2e)\n",
          skin.size(), rest.num_control_points(), args->reference, ref_fig.samples, ref_fig.twist.rms);
      std::printf("%8s %8s %8s %10s %10s %6s %10s %10s %10s %10s\n", "density", "samples", "bind s",
                  "median ms", "min ms", "set", "twist rms", "twist max", "ref rms", "ref max");
      for (const DensityFigures& f : rows)
        std::printf("%8u %8u %8.3f %10.3f %10.3f %6.2f %10.2e %10.2e %10.2e %10.2e\n", f.density, f.samples,
                    f.bind_s, f.median_ms, f.min_ms, f.mean_set, f.twist.rms, f.twist.max, f.reference.rms,
                    f.reference.max);
    }
    exit_code = 0;
  });
}

}  // namespace

void add_patch_command(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand(
      "patch", "parametric drivers: fit one to cage faces, deform a skin by one, benchmark");
  cmd->require_subcommand(1);
  add_fit(*cmd, exit_code);
  add_deform(*cmd, exit_code);
  add_demo(*cmd, exit_code);
  add_bench(*cmd, exit_code);
}

}  // namespace cagewrap::app
