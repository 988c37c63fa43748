#include "app/cli_common.h"

#include <unistd.h>

#include <cstdio>
#include <mutex>

#include "core/document/binding_cache.h"
#include "core/geometry/mesh_io.h"
#include "core/io/patch_io.h"

namespace cagewrap::app {

void add_bind_options(CLI::App& cmd, BindOptions& o) {
  o.local_option =
      cmd.add_option("--local", o.params.local, "falloff exponent of 1/(1+d^local)")->capture_default_str();
  o.epsilon_option = cmd.add_option("--epsilon", o.params.epsilon, "keep elements with weight >= epsilon * strongest")
                         ->capture_default_str();
  o.max_elements_option =
      cmd.add_option("-K,--max-elements", o.params.max_elements, "at most K elements per point")->capture_default_str();
  o.scale_option =
      cmd.add_option("--scale", o.params.scale, "distance unit h (0 = mean cage edge length, 1 = raw scene units)")
          ->capture_default_str();
  o.max_distance_option =
      cmd.add_option("--max-distance", o.params.max_distance,
                     "elements farther than this (scene units) never drive a point; 0 = none")
          ->capture_default_str();
  o.variant_option = cmd.add_option("--variant", o.variant, "basic | clamped | extended")->capture_default_str();
}

bool finish_bind_options(BindOptions& o) {
  if (!parse_variant(o.variant, o.params.variant)) {
    std::fprintf(stderr, "error: unknown variant '%s' (use basic, clamped or extended)\n", o.variant.c_str());
    return false;
  }
  if (auto v = validate(o.params); !v) {
    std::fprintf(stderr, "error: %s\n", v.error().message.c_str());
    return false;
  }
  return true;
}

bool any_bind_option(const BindOptions& o) {
  for (const CLI::Option* opt : {o.local_option, o.epsilon_option, o.max_elements_option, o.scale_option, o.max_distance_option,
                                 o.variant_option})
    if (opt && opt->count() > 0) return true;
  return false;
}

std::optional<BindParams> bind_options_over(const BindOptions& o, const BindParams& base) {
  auto given = [](const CLI::Option* opt) { return opt && opt->count() > 0; };
  BindParams p = base;
  if (given(o.variant_option) && !parse_variant(o.variant, p.variant)) {
    std::fprintf(stderr, "error: unknown variant '%s' (use basic, clamped or extended)\n", o.variant.c_str());
    return std::nullopt;
  }
  if (given(o.local_option)) p.local = o.params.local;
  if (given(o.epsilon_option)) p.epsilon = o.params.epsilon;
  if (given(o.max_elements_option)) p.max_elements = o.params.max_elements;
  if (given(o.scale_option)) p.scale = o.params.scale;
  if (given(o.max_distance_option)) p.max_distance = o.params.max_distance;
  if (auto v = validate(p); !v) {
    std::fprintf(stderr, "error: %s\n", v.error().message.c_str());
    return std::nullopt;
  }
  return p;
}

std::string bind_options_differing(const BindOptions& o, const BindParams& bound) {
  std::string out;
  auto given = [](const CLI::Option* opt) { return opt && opt->count() > 0; };
  auto add = [&](const char* name, const std::string& mine, const std::string& theirs) {
    if (!out.empty()) out += ", ";
    out += std::string(name) + " " + mine + " (the binding's: " + theirs + ")";
  };
  auto num = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return std::string(buf);
  };
  if (given(o.variant_option) && o.params.variant != bound.variant)
    add("--variant", variant_name(o.params.variant), variant_name(bound.variant));
  if (given(o.local_option) && o.params.local != bound.local) add("--local", num(o.params.local), num(bound.local));
  if (given(o.epsilon_option) && o.params.epsilon != bound.epsilon)
    add("--epsilon", num(o.params.epsilon), num(bound.epsilon));
  if (given(o.max_elements_option) && o.params.max_elements != bound.max_elements)
    add("--max-elements", std::to_string(o.params.max_elements), std::to_string(bound.max_elements));
  if (given(o.scale_option) && o.params.scale != bound.scale) add("--scale", num(o.params.scale), num(bound.scale));
  if (given(o.max_distance_option) && o.params.max_distance != bound.max_distance)
    add("--max-distance", num(o.params.max_distance), num(bound.max_distance));
  return out;
}

bool positions_output_or_report(const std::string& path) {
  if (has_extension(path, ".obj") || has_extension(path, ".bin")) return true;
  std::fprintf(stderr, "error: %s: output must end in .obj or .bin\n", path.c_str());
  return false;
}

void add_keep_units_flag(CLI::App& cmd, bool& keep) {
  cmd.add_flag("--keep-units", keep,
               "FBX, Collada, .x, ...: read the character in the file's own units and up axis (default: brought to metres, Y up)");
}

int report_error(const Error& e) {
  std::fprintf(stderr, "error: %s\n", e.message.c_str());
  return 1;
}

std::optional<PolyMesh> load_mesh_or_report(const std::string& path) {
  auto m = load_mesh(path);
  if (!m) {
    report_error(m.error());
    return std::nullopt;
  }
  return std::move(m).value();
}

std::optional<ProjectLoad> load_project_or_report(const std::string& path) {
  auto loaded = load_project(path);
  if (!loaded) {
    report_error(loaded.error());
    return std::nullopt;
  }
  for (const std::string& w : loaded->warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  return std::move(loaded).value();
}

std::optional<Cage> load_cage_or_report(const std::string& path) {
  auto m = load_mesh_or_report(path);
  if (!m) return std::nullopt;
  auto c = make_cage(std::move(*m), path);
  if (!c) {
    report_error(c.error());
    return std::nullopt;
  }
  return std::move(c).value();
}

std::shared_ptr<const PatchDriver> load_driver_or_report(const std::string& path, const std::string& posed_path, uint32_t density) {
  if (density < 1 || density > 1024) {
    std::fprintf(stderr, "error: --patch-density %u: use 1..1024\n", density);
    return nullptr;
  }
  auto surface = load_patch_any(path);
  if (!surface) {
    report_error(surface.error());
    return nullptr;
  }
  auto driver = std::make_shared<PatchDriver>();
  driver->rest = *surface;
  driver->posed = std::move(surface).value();
  if (!posed_path.empty()) {
    auto posed = load_patch_any(posed_path);
    if (!posed) {
      report_error(posed.error());
      return nullptr;
    }
    bool same_grids = posed->grids.size() == driver->rest.grids.size();
    for (size_t g = 0; same_grids && g < posed->grids.size(); ++g)
      same_grids = posed->grids[g].rows == driver->rest.grids[g].rows && posed->grids[g].cols == driver->rest.grids[g].cols &&
                   posed->grids[g].basis == driver->rest.grids[g].basis;
    if (!same_grids) {
      std::fprintf(stderr, "error: %s: its grids are not those of %s (the same grids, sizes and basis, moved)\n", posed_path.c_str(),
                   path.c_str());
      return nullptr;
    }
    driver->posed = std::move(posed).value();
  }
  driver->density = density;
  driver->drive_skin = true;
  return driver;
}

std::optional<PolyMesh> load_posed_cage_or_report(const std::string& path, const Cage& cage, const std::string& cage_path) {
  auto posed = load_mesh_or_report(path);
  if (!posed) return std::nullopt;
  if (posed->num_vertices() != cage.num_vertices() || posed->num_faces() != cage.polygons.num_faces()) {
    std::fprintf(stderr, "error: %s: the posed cage has %zu vertices and %zu faces but the cage %s has %zu and %zu\n",
                 path.c_str(), posed->num_vertices(), posed->num_faces(), cage_path.c_str(), cage.num_vertices(),
                 cage.polygons.num_faces());
    return std::nullopt;
  }
  return posed;
}

void print_bind_summary(const Binding& b, const std::string& cage_path, size_t num_polygons) {
  std::printf("points            %u\n", b.num_points);
  std::printf("elements          %zu (triangles of %zu polygons)\n", b.elements.size(), num_polygons);
  std::printf("variant           %s  local %g  epsilon %g  K %u  h %g%s\n", variant_name(b.params.variant),
              b.params.local, b.params.epsilon, b.params.max_elements, b.h, b.params.scale > 0 ? "" : " (mean edge)");
  std::printf("set size          mean %.2f  max %u\n", b.num_points ? double(b.total_set_size) / b.num_points : 0.0,
              b.max_set_size);
  std::printf("binding           %.1f bytes per skin vertex\n", b.num_points ? double(b.bytes()) / b.num_points : 0.0);
  std::printf("affected elements %zu", b.invalid_elements.size());
  for (size_t i = 0; i < b.invalid_elements.size() && i < 20; ++i) {
    uint32_t e = b.invalid_elements[i];
    std::printf("%s%u (%s)", i ? ", " : ": ", e, element_status_name(b.element_status[e]));
  }
  if (b.invalid_elements.size() > 20) std::printf(" and %zu more", b.invalid_elements.size() - 20);
  std::printf("\n");
  std::printf("affected points   %zu", b.rigid_points.size());
  for (size_t i = 0; i < b.rigid_points.size() && i < 20; ++i) std::printf("%s%u", i ? ", " : ": ", b.rigid_points[i]);
  if (b.rigid_points.size() > 20) std::printf(" and %zu more", b.rigid_points.size() - 20);
  std::printf("%s\n", b.rigid_points.empty() ? "" : " (empty set: follow their nearest valid element rigidly)");
  std::printf("cage quality      %.2f%% of points lie within %g h of an element and project inside it\n",
              100.0 * b.quality(), b.params.close_distance);
  if (b.separation_applied)
    std::printf("separation        %u points kept from %llu elements of unconnected parts (%u steps)\n",
                b.separated_points, static_cast<unsigned long long>(b.total_separated), b.params.separation_steps);
  std::printf("seconds           %.3f\n", b.seconds);
  if (!b.invalid_elements.empty())
    std::fprintf(stderr, "warning: %s: %zu cage element(s) were skipped (listed above)\n", cage_path.c_str(),
                 b.invalid_elements.size());
}

BindProgress terminal_progress(const char* label) {
  BindProgress p;
  if (!isatty(STDERR_FILENO)) return p;
  auto last = std::make_shared<int>(-1);
  auto mutex = std::make_shared<std::mutex>();
  p.on_progress = [label, last, mutex](double f) {
    std::lock_guard lock(*mutex);
    int pct = static_cast<int>(f * 100);
    if (pct == *last) return;
    *last = pct;
    std::fprintf(stderr, "\r%s %3d%%%s", label, pct, pct >= 100 ? "\n" : "");
  };
  return p;
}

std::optional<Rig> rig_of_project(const Document& doc, const std::string& project) {
  if (!doc.cage) {
    std::fprintf(stderr, "error: %s: the project has no cage yet; give it one (cagewrap new --cage, or the editor)\n",
                 project.c_str());
    return std::nullopt;
  }
  // what the stack leaves out is said: a solo or a mute left on by mistake would ship a different rig
  if (doc.stack.solo >= 0 && deformer_count(doc) > 1)
    std::fprintf(stderr, "warning: %s: deformer %d '%s' is soloed: the other deformers are left out (cagewrap deformer set --solo none)\n",
                 project.c_str(), doc.stack.solo, deformer_name(doc, static_cast<size_t>(doc.stack.solo)).c_str());
  else
    for (size_t d = 0; d < deformer_count(doc); ++d)
      if (deformer_muted(doc, d))
        std::fprintf(stderr, "warning: %s: deformer %zu '%s' is muted: it is left out\n", project.c_str(), d,
                     deformer_name(doc, d).c_str());
  // the cached bindings (the document's cage's and each layer's), those still the project's
  StackBindingCache cached = load_stack_binding_caches(doc);
  for (const std::string& why : cached.not_used)
    std::fprintf(stderr, "warning: binding cache not used: %s; binding again (`cagewrap project %s --cache-binding` refreshes it)\n",
                 why.c_str(), project.c_str());
  if (cached.used + cached.drivers_used > 0) {
    const size_t moving = moving_deformers(doc), drivers = moving_drivers(doc);
    const bool all = cached.used == moving && cached.drivers_used == drivers;
    auto rig = Rig::create(doc, std::move(cached.bindings), terminal_progress("bind"), std::move(cached.drivers));
    if (rig) {
      if (deformer_count(doc) == 1 && drivers == 0)
        std::fprintf(stderr, "note: %s: using the cached binding %s (no bind)\n", project.c_str(), doc.binding_cache.file.c_str());
      else
        std::fprintf(stderr, "note: %s: using the cached bindings of %zu of %zu deformers%s (%s)\n", project.c_str(), cached.used, moving,
                     drivers ? (" and " + std::to_string(cached.drivers_used) + " of " + std::to_string(drivers) + " parametric drivers").c_str() : "",
                     all ? "no bind" : "the others bound");
      return std::move(rig).value();
    }
    std::fprintf(stderr, "warning: %s: the cached binding was not used (%s); binding again\n", project.c_str(),
                 rig.error().message.c_str());
  }
  auto rig = Rig::create(doc, terminal_progress("bind"));
  if (!rig) {
    report_error({rig.error().code, project + ": " + rig.error().message});
    return std::nullopt;
  }
  return std::move(rig).value();
}

SaveOptions save_options_caching(const Rig& rig, const Document& doc) {
  SaveOptions options;
  options.binding = &rig.binding();
  for (size_t i = 0; i < doc.layers.size(); ++i) options.layer_bindings.push_back(rig.layer_binding(i));
  for (size_t i = 0; i < driver_count(doc); ++i) options.driver_bindings.push_back(rig.driver_binding(i));
  return options;
}

}  // namespace cagewrap::app
