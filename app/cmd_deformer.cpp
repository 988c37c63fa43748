// cagewrap deformer list|add|remove|set --project P.cagewrap [...] [--out Q.cagewrap]
// The project's deformer stack, headless (issue 21, docs/deformer-stack.md): its own cage and the
// layers over it (a fine face or hand cage, a garment cage), each with a name, an optional skin mask
// and a mute switch, and how their skins combine.
//   list                                   the stack, one line per deformer
//   add --cage C [--name N] [--mask-joints a,b | --mask-primitives 0,2] [binding options]
//   remove (--name N | --index I)          I: 1 = the first layer (0 is the project's own cage)
//   set (--name N | --index I) [--rename N2] [--mute | --unmute] [--hide | --show]
//       [--mask-joints a,b | --mask-primitives 0,2 | --no-mask] [--to K]   (move it to position K among the layers)
//   set --index 0 [--mute | --unmute] [--hide | --show]   (the project's own cage)
//   set --stack in_order|sum|blend [--exponent m] [--solo D|none]
//   set --driver [--mute | --unmute] [--after K|last] [--mask-joints a,b | --mask-primitives 0,2 | --no-mask]
//       [binding options] (the parametric driver: its switch, its place among the layers, its mask and its own
//       binding parameters)
// Every change checks what it can first (the cage, the names, the mask), writes P again (or Q), and
// prints the stack. Errors name the project, the layer and what is wrong; nothing is written then.
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "app/cli_common.h"
#include "app/commands.h"
#include "core/character/skin_mask.h"
#include "core/document/project_io.h"

namespace cagewrap::app {

namespace {

void print_stack(const Document& doc) {
  const auto cage_line = [](const Cage& c) {
    return std::to_string(c.num_vertices()) + " vertices, " + std::to_string(c.polygons.num_faces()) + " faces";
  };
  std::printf("stack      %s%s (%zu deformer%s)\n", stack_mode_name(doc.stack.mode),
              doc.stack.mode == StackMode::kBlend ? (" m=" + std::to_string(doc.stack.exponent)).c_str() : "",
              1 + doc.layers.size(), doc.layers.empty() ? "" : "s");
  // what leaves a deformer out, or hides its cage in the editor
  const auto flags = [&doc](size_t d) {
    std::string f;
    const bool own = d == 0 ? doc.stack.base_muted : doc.layers[d - 1].muted;
    if (own) f += ", muted";
    else if (deformer_muted(doc, d)) f += ", left out (deformer " + std::to_string(doc.stack.solo) + " is soloed)";
    if (doc.stack.solo == static_cast<int32_t>(d)) f += ", soloed";
    if (deformer_hidden(doc, d)) f += ", hidden";
    return f;
  };
  std::printf("  0  %-16s %s, %s%s\n", "(project cage)", doc.cage ? cage_line(*doc.cage).c_str() : "no cage",
              variant_name(doc.params.variant), flags(0).c_str());
  const auto mask_line = [](const std::shared_ptr<const std::vector<float>>& m, const std::string& source) {
    if (!m) return std::string("no mask");
    size_t moved = 0;
    for (float w : *m) moved += w > 0.0f ? 1 : 0;
    return "mask " + (source.empty() ? std::string("painted") : source) + " (" + std::to_string(moved) + " of " +
           std::to_string(m->size()) + " skin vertices)";
  };
  // the parametric driver, where it sits (only in_order has an order)
  const auto driver_line = [&](size_t after) {
    if (!doc.patch_driver || driver_position(doc) != after) return;
    const PatchDriver& p = *doc.patch_driver;
    const DriverPlacement& place = doc.driver_place;
    std::string f = p.drive_skin ? "" : ", muted";
    if (p.drive_skin && !driver_moves_skin(doc)) f += ", left out (deformer " + std::to_string(doc.stack.solo) + " is soloed)";
    const BindParams& b = driver_params(doc);
    char binding[96];
    std::snprintf(binding, sizeof binding, "%s binding local %g epsilon %g K %u", place.params ? "own" : "the cage's", b.local,
                  b.epsilon, b.max_elements);
    std::printf("  D  %-16s parametric driver, %zu control points, density %u, %s, %zu keypose set%s, %s, %s%s\n", "(driver)",
                p.rest.num_control_points(), p.density, binding, place.keyposes.size(), place.keyposes.size() == 1 ? "" : "s",
                mask_line(place.mask, place.mask_source).c_str(),
                place.after < 0 ? "after every layer" : ("after layer " + std::to_string(driver_position(doc))).c_str(), f.c_str());
  };
  driver_line(0);
  for (size_t i = 0; i < doc.layers.size(); ++i) {
    const DeformerLayer& l = doc.layers[i];
    std::printf("  %zu  %-16s %s, %s, %s%s\n", i + 1, l.name.c_str(), cage_line(*l.cage).c_str(), variant_name(l.params.variant),
                mask_line(l.mask, l.mask_source).c_str(), flags(i + 1).c_str());
    driver_line(i + 1);
  }
}

struct MaskArgs {
  std::string joints, primitives;
  bool none = false;
};

void add_mask_options(CLI::App& cmd, MaskArgs& m, bool with_none) {
  auto* j = cmd.add_option("--mask-joints", m.joints, "mask: these joints and their children, feathered by the skin weights (a,b,c; -name leaves one out: spine,-neck)");
  auto* p = cmd.add_option("--mask-primitives", m.primitives, "mask: these primitives of the character, by index (0,2)");
  j->excludes(p);
  if (with_none) cmd.add_flag("--no-mask", m.none, "no mask: the layer may move every skin point")->excludes(j)->excludes(p);
}

// A deformer's mask (`mask`, `source`) as the options say; false (printed) when it cannot be made.
bool apply_mask(const Document& doc, const MaskArgs& m, const std::string& name, std::shared_ptr<const std::vector<float>>& out,
                std::string& source, const std::string& project) {
  if (m.none) {
    out = nullptr;
    source.clear();
    return true;
  }
  std::string spec;
  if (!m.joints.empty()) spec = "joints " + m.joints;
  else if (!m.primitives.empty()) spec = "primitives " + m.primitives;
  else return true;  // unchanged
  auto mask = skin_mask_from_source(*doc.character, spec);
  source = spec;
  if (!mask) {
    std::fprintf(stderr, "error: %s: deformer '%s': %s\n", project.c_str(), name.c_str(), mask.error().message.c_str());
    return false;
  }
  out = std::make_shared<const std::vector<float>>(std::move(mask).value());
  return true;
}
bool apply_mask(const Document& doc, const MaskArgs& m, DeformerLayer& l, const std::string& project) {
  return apply_mask(doc, m, l.name, l.mask, l.mask_source, project);
}

// The layer named `name`, or at 1-based `index`; -1 (printed) when there is none.
long find_layer(const Document& doc, const std::string& name, long index, const std::string& project) {
  if (!name.empty()) {
    for (size_t i = 0; i < doc.layers.size(); ++i)
      if (doc.layers[i].name == name) return static_cast<long>(i);
    std::fprintf(stderr, "error: %s: has no deformer named '%s'%s\n", project.c_str(), name.c_str(),
                 doc.layers.empty() ? " (it has no layers: `cagewrap deformer add`)" : "");
    return -1;
  }
  if (index >= 1 && static_cast<size_t>(index) <= doc.layers.size()) return index - 1;
  if (index == 0)
    std::fprintf(stderr, "error: %s: deformer 0 is the project's own cage: edit it with `cagewrap new` or the editor\n", project.c_str());
  else
    std::fprintf(stderr, "error: %s: has no deformer %ld (its layers are 1 to %zu)\n", project.c_str(), index, doc.layers.size());
  return -1;
}

// Writes the project (to `out` when given) and prints the stack; the exit code.
int save_and_print(const Document& doc, const std::string& project, const std::string& out) {
  const std::string to = out.empty() ? project : out;
  if (auto s = save_project(to, doc); !s) return report_error(s.error());
  std::printf("wrote      %s\n", to.c_str());
  print_stack(doc);
  return 0;
}

}  // namespace

void add_deformer_command(CLI::App& app, int& exit_code) {
  struct Args {
    std::string project, out, cage, name, rename, stack;
    long index = -1, to = -1;
    double exponent = -1.0;
    bool mute = false, unmute = false, hide = false, show = false, driver = false;
    std::string solo, after;
    MaskArgs mask;
    BindOptions bind;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("deformer", "list and edit a project's deformers: its own cage and more cages over it");
  cmd->require_subcommand(1);
  auto common = [&](CLI::App* sub) {
    sub->add_option("--project", args->project, "project file (.cagewrap)")->required();
    sub->add_option("--out", args->out, "write the result here instead of over the project");
  };
  auto load = [args]() -> std::optional<Document> {
    auto loaded = load_project_or_report(args->project);
    if (!loaded) return std::nullopt;
    return loaded->document;
  };

  auto* list = cmd->add_subcommand("list", "print the stack");
  common(list);
  list->callback([args, load, &exit_code] {
    exit_code = 1;
    auto doc = load();
    if (!doc) return;
    print_stack(*doc);
    exit_code = 0;
  });

  auto* add = cmd->add_subcommand("add", "add a cage as a new layer at the end of the stack");
  common(add);
  add->add_option("--cage", args->cage, "the layer's cage at rest (.obj .ply .off .stl)")->required();
  add->add_option("--name", args->name, "its name (default: the cage file's name)");
  add_mask_options(*add, args->mask, false);
  add_bind_options(*add, args->bind);
  add->callback([args, load, &exit_code] {
    exit_code = 1;
    if (!finish_bind_options(args->bind)) return;
    auto doc = load();
    if (!doc) return;
    auto cage = load_cage_or_report(args->cage);
    if (!cage) return;
    DeformerLayer l;
    l.name = args->name.empty() ? std::filesystem::path(args->cage).stem().string() : args->name;
    for (const DeformerLayer& other : doc->layers)
      if (other.name == l.name) {
        std::fprintf(stderr, "error: %s: already has a deformer named '%s' (give another with --name)\n", args->project.c_str(),
                     l.name.c_str());
        return;
      }
    l.cage = std::make_shared<const Cage>(std::move(*cage));
    l.params = args->bind.params;
    l.attachment = doc->attachment;
    l.attachment.overrides.clear();  // they named the project cage's vertices
    if (!apply_mask(*doc, args->mask, l, args->project)) return;
    std::vector<DeformerLayer> layers = doc->layers;
    layers.push_back(std::move(l));
    exit_code = save_and_print(with_layers(*doc, std::move(layers)), args->project, args->out);
  });

  auto* remove = cmd->add_subcommand("remove", "remove a layer");
  common(remove);
  remove->add_option("--name", args->name, "the layer's name");
  remove->add_option("--index", args->index, "or its place: 1 = the first layer");
  remove->callback([args, load, &exit_code] {
    exit_code = 1;
    auto doc = load();
    if (!doc) return;
    const long i = find_layer(*doc, args->name, args->index, args->project);
    if (i < 0) return;
    std::vector<DeformerLayer> layers = doc->layers;
    std::printf("removed    %s\n", layers[size_t(i)].name.c_str());
    layers.erase(layers.begin() + i);
    exit_code = save_and_print(with_layers(*doc, std::move(layers)), args->project, args->out);
  });

  auto* set = cmd->add_subcommand("set", "change a deformer (name, mute, mask, place, binding parameters) or the stack's mode");
  common(set);
  set->add_option("--name", args->name, "the layer's name");
  set->add_option("--index", args->index, "or its place: 1 = the first layer");
  set->add_option("--rename", args->rename, "a new name");
  auto* mute = set->add_flag("--mute", args->mute, "leave it out of the stack (kept in the project)");
  set->add_flag("--unmute", args->unmute, "put it back into the stack")->excludes(mute);
  auto* hide = set->add_flag("--hide", args->hide, "hide its cage in the editor (saved with the project)");
  set->add_flag("--show", args->show, "show its cage in the editor again")->excludes(hide);
  set->add_option("--solo", args->solo, "only this deformer moves the skin (0 = the project's cage, 1 = the first layer; none = off)");
  set->add_option("--to", args->to, "move it to this place among the layers (1 = first)");
  set->add_flag("--driver", args->driver, "change the project's parametric driver (its mute, mask, keyposes kept, place)");
  set->add_option("--after", args->after, "with --driver: the number of layers before it (0 = right after the project's cage; last = after them all)");
  add_mask_options(*set, args->mask, true);
  set->add_option("--stack", args->stack, "how the skins combine: in_order, sum or blend (docs/deformer-stack.md)");
  set->add_option("--exponent", args->exponent, "the blend's exponent m (>= 0)");
  add_bind_options(*set, args->bind);  // given ones change that deformer's binding parameters
  set->callback([args, load, &exit_code] {
    exit_code = 1;
    auto doc = load();
    if (!doc) return;
    Document d = *doc;
    if (!args->stack.empty() || args->exponent >= 0.0) {
      DeformerStack stack = d.stack;
      if (!args->stack.empty() && !parse_stack_mode(args->stack, stack.mode)) {
        std::fprintf(stderr, "error: --stack '%s': use in_order, sum or blend\n", args->stack.c_str());
        return;
      }
      if (args->exponent >= 0.0) stack.exponent = args->exponent;
      d = with_stack(d, stack);
    } else if (args->exponent != -1.0) {
      std::fprintf(stderr, "error: --exponent %g: the blend's exponent must be >= 0\n", args->exponent);
      return;
    }
    if (!args->solo.empty()) {
      DeformerStack stack = d.stack;
      if (args->solo == "none") {
        stack.solo = -1;
      } else {
        char* end = nullptr;
        const long v = std::strtol(args->solo.c_str(), &end, 10);
        if (*end || v < 0 || static_cast<size_t>(v) >= deformer_count(d)) {
          std::fprintf(stderr, "error: %s: --solo '%s': the deformers are 0 to %zu (or none)\n", args->project.c_str(),
                       args->solo.c_str(), d.layers.size());
          return;
        }
        stack.solo = static_cast<int32_t>(v);
      }
      d = with_stack(d, stack);
    }
    const bool switches = args->mute || args->unmute || args->hide || args->show;
    const bool params = any_bind_option(args->bind);
    const bool layer_change = !args->rename.empty() || switches || args->to >= 0 || !args->mask.joints.empty() ||
                              !args->mask.primitives.empty() || args->mask.none || params;
    if (args->driver) {  // the parametric driver: its switch, place and mask
      if (!d.patch_driver) {
        std::fprintf(stderr, "error: %s: has no parametric driver (cagewrap new --patch, or the editor's Rig > Parametric driver)\n",
                     args->project.c_str());
        return;
      }
      if (!args->name.empty() || args->index >= 0 || !args->rename.empty() || args->to >= 0 || args->hide || args->show) {
        std::fprintf(stderr, "error: %s: --driver takes --mute, --unmute, --after, the mask options and binding parameters only\n",
                     args->project.c_str());
        return;
      }
      if (args->mute || args->unmute) {
        PatchDriver p = *d.patch_driver;
        p.drive_skin = args->unmute;
        d = with_patch_driver(d, std::make_shared<const PatchDriver>(std::move(p)));
      }
      DriverPlacement place = d.driver_place;
      if (!args->after.empty()) {
        char* end = nullptr;
        const long v = std::strtol(args->after.c_str(), &end, 10);
        if (args->after == "last") {
          place.after = -1;
        } else if (*end || args->after.empty() || v < 0 || static_cast<size_t>(v) > d.layers.size()) {
          std::fprintf(stderr, "error: %s: --after '%s': give 0 to %zu layers, or last\n", args->project.c_str(), args->after.c_str(),
                       d.layers.size());
          return;
        } else {
          place.after = static_cast<int32_t>(v);
        }
      }
      if (!apply_mask(d, args->mask, "driver", place.mask, place.mask_source, args->project)) return;
      if (params) {  // its own binding parameters, starting from those it binds with now
        auto p = bind_options_over(args->bind, driver_params(d));
        if (!p) return;
        place.params = *p;
      }
      d = with_driver_place(d, std::move(place));
    } else if (!args->after.empty()) {
      std::fprintf(stderr, "error: %s: --after places the parametric driver: give --driver too\n", args->project.c_str());
      return;
    } else if (args->index == 0 && args->name.empty()) {  // the project's own cage: only its switches
      if (!args->rename.empty() || args->to >= 0 || !args->mask.joints.empty() || !args->mask.primitives.empty() || args->mask.none) {
        std::fprintf(stderr, "error: %s: deformer 0 is the project's own cage: it can be muted, hidden, soloed or given binding "
                             "parameters, not renamed, moved or masked\n", args->project.c_str());
        return;
      }
      DeformerStack stack = d.stack;
      if (args->mute) stack.base_muted = true;
      if (args->unmute) stack.base_muted = false;
      if (args->hide) stack.base_hidden = true;
      if (args->show) stack.base_hidden = false;
      d = with_stack(d, stack);
      if (params) {
        auto p = bind_options_over(args->bind, d.params);
        if (!p) return;
        d = with_params(d, *p);
      }
    } else if (layer_change || !args->name.empty() || args->index >= 0) {
      const long i = find_layer(d, args->name, args->index, args->project);
      if (i < 0) return;
      std::vector<DeformerLayer> layers = d.layers;
      DeformerLayer& l = layers[size_t(i)];
      if (!args->rename.empty()) {
        for (size_t k = 0; k < layers.size(); ++k)
          if (long(k) != i && layers[k].name == args->rename) {
            std::fprintf(stderr, "error: %s: already has a deformer named '%s'\n", args->project.c_str(), args->rename.c_str());
            return;
          }
        l.name = args->rename;
      }
      if (args->mute) l.muted = true;
      if (args->unmute) l.muted = false;
      if (args->hide) l.hidden = true;
      if (args->show) l.hidden = false;
      if (params) {
        auto p = bind_options_over(args->bind, l.params);
        if (!p) return;
        l.params = *p;
      }
      if (!apply_mask(d, args->mask, l, args->project)) return;
      if (args->to >= 0) {
        if (args->to < 1 || size_t(args->to) > layers.size()) {
          std::fprintf(stderr, "error: --to %ld: the layers are 1 to %zu\n", args->to, layers.size());
          return;
        }
        DeformerLayer moved = std::move(l);
        layers.erase(layers.begin() + i);
        layers.insert(layers.begin() + (args->to - 1), std::move(moved));
      }
      d = with_layers(d, std::move(layers));
    }
    exit_code = save_and_print(d, args->project, args->out);
  });
}

}  // namespace cagewrap::app
