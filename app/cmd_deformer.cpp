// cagewrap deformer list|add|remove|set --project P.cagewrap [...] [--out Q.cagewrap]
// The project's deformer stack, headless (issue 21, docs/deformer-stack.md): its own cage and the
// layers over it (a fine face or hand cage, a garment cage), each with a name, an optional skin mask
// and a mute switch, and how their skins combine.
//   list                                   the stack, one line per deformer
//   add --cage C [--name N] [--mask-joints a,b | --mask-primitives 0,2 | --mask-weights F] [binding options]
//   add --patch F [--posed-patch G] [--patch-density n] [--name N] [--after K|last] [mask] [binding options]
//                                          (a parametric driver: the first, or one more)
//   remove (--name N | --index I)          I: 1 = the first layer (0 is the project's own cage)
//   remove --driver [--name N]             a parametric driver (default: the first)
//   set (--name N | --index I) [--rename N2] [--mute | --unmute] [--hide | --show]
//       [--mask-joints a,b | --mask-primitives 0,2 | --no-mask] [--to K]   (move it to position K among the layers)
//   set --index 0 [--mute | --unmute] [--hide | --show]   (the project's own cage)
//   set --stack in_order|sum|blend [--exponent m] [--solo D|none]
//   set --driver [--name N] [--rename N2] [--mute | --unmute] [--after K|last] [--mask-joints a,b |
//       --mask-primitives 0,2 | --no-mask] [binding options] (a parametric driver, the first unless --name says
//       which: its name, switch, place among the layers, mask and own binding parameters)
// Every change checks what it can first (the cage, the names, the mask), writes P again (or Q), and
// prints the stack. Errors name the project, the layer and what is wrong; nothing is written then.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include <nlohmann/json.hpp>

#include "app/cli_common.h"
#include "app/commands.h"
#include "core/character/skin_mask.h"
#include "core/deform/patch_binding.h"
#include "core/deform/set_editing.h"
#include "core/document/project_io.h"
#include "core/io/set_edits_io.h"

namespace cagewrap::app {

namespace {

void print_stack(const Document& doc) {
  const auto cage_line = [](const Cage& c) {
    return std::to_string(c.num_vertices()) + " vertices, " + std::to_string(c.polygons.num_faces()) + " faces";
  };
  const size_t nd = driver_count(doc);
  std::printf("stack      %s%s (%zu deformer%s%s)\n", stack_mode_name(doc.stack.mode),
              doc.stack.mode == StackMode::kBlend ? (" m=" + std::to_string(doc.stack.exponent)).c_str() : "",
              1 + doc.layers.size(), doc.layers.empty() ? "" : "s",
              nd == 0 ? "" : (", " + std::to_string(nd) + " parametric driver" + (nd == 1 ? "" : "s")).c_str());
  // what leaves a deformer out, or hides its cage in the editor
  const auto flags = [&doc](size_t d) {
    std::string f;
    const bool own = d == 0 ? doc.stack.base_muted : doc.layers[d - 1].muted;
    if (own) f += ", muted";
    else if (deformer_muted(doc, d))
      f += soloed_driver(doc) ? ", left out (driver '" + doc.stack.solo_driver + "' is soloed)"
                              : ", left out (deformer " + std::to_string(doc.stack.solo) + " is soloed)";
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
  // the parametric drivers, where each sits (only in_order has an order): D (or D2, D3...) and the name
  const auto driver_line = [&](size_t after) {
    for (size_t i = 0; i < driver_count(doc); ++i) {
      const DriverRef r = driver_at(doc, i);
      if (driver_position(doc, *r.place) != after) continue;
      const PatchDriver& p = *r.driver;
      const DriverPlacement& place = *r.place;
      std::string f = p.drive_skin ? "" : ", muted";
      if (p.drive_skin && !driver_moves_skin(doc, i))
        f += soloed_driver(doc) ? ", left out (driver '" + doc.stack.solo_driver + "' is soloed)"
                                : ", left out (deformer " + std::to_string(doc.stack.solo) + " is soloed)";
      if (soloed_driver(doc) == i) f += ", soloed";
      const BindParams& b = driver_params(doc, place);
      char binding[96];
      std::snprintf(binding, sizeof binding, "%s binding local %g epsilon %g K %u", place.params ? "own" : "the cage's", b.local,
                    b.epsilon, b.max_elements);
      if (place.hidden) f += ", hidden";
      if (!place.set_edits.empty()) f += ", " + std::to_string(place.set_edits.size()) + " set edit" + (place.set_edits.size() == 1 ? "" : "s");
      if (place.attachment)
        f += std::string(", attached ") + attachment_mode_name(place.attachment->mode) +
             (place.attachment->overrides.empty() ? "" : " (" + std::to_string(place.attachment->overrides.size()) + " assigned)");
      const std::string label = i == 0 ? "D" : "D" + std::to_string(i + 1);
      const std::string name = place.name.empty() ? "(" + driver_name(doc, i) + ")" : place.name;
      std::printf("  %-3s%-16s parametric driver, %zu control points, density %u, %s, %zu keypose set%s, %s, %s%s\n", label.c_str(),
                  name.c_str(), p.rest.num_control_points(), p.density, binding, place.keyposes.size(),
                  place.keyposes.size() == 1 ? "" : "s", mask_line(place.mask, place.mask_source).c_str(),
                  place.after < 0 ? "after every layer" : ("after layer " + std::to_string(driver_position(doc, place))).c_str(), f.c_str());
    }
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
  std::string joints, primitives, meshes, weights;
  bool none = false;
};

// A painted mask from a file: one weight in [0, 1] per skin vertex (skin order), as a JSON array or numbers
// separated by white space (as the project file's "mask" holds them, or as a DCC tool writes a weight map).
Result<std::vector<float>> read_mask_weights(const std::string& path, size_t expected) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return make_error(ErrorCode::kFileUnreadable, path + ": cannot be read");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<float> out;
  const size_t first = text.find_first_not_of(" \t\r\n");
  if (first != std::string::npos && text[first] == '[') {
    auto j = nlohmann::json::parse(text, nullptr, false);
    if (j.is_discarded() || !j.is_array()) return make_error(ErrorCode::kParse, path + ": not a JSON array of weights");
    if (j.size() != expected)
      return make_error(ErrorCode::kTopologyMismatch, path + ": " + std::to_string(j.size()) + " weights, but the skin has " +
                                                          std::to_string(expected) + " vertices");
    out.reserve(expected);
    for (size_t i = 0; i < j.size(); ++i) {
      if (!j[i].is_number()) return make_error(ErrorCode::kParse, path + ": weight " + std::to_string(i) + " is not a number");
      out.push_back(j[i].get<float>());
    }
  } else {
    std::istringstream s(text);
    std::string word;
    while (s >> word) {
      if (out.size() == expected)
        return make_error(ErrorCode::kTopologyMismatch, path + ": more weights than the skin's " + std::to_string(expected) + " vertices");
      char* end = nullptr;
      const float v = std::strtof(word.c_str(), &end);
      if (*end) return make_error(ErrorCode::kParse, path + ": weight " + std::to_string(out.size()) + " ('" + word + "') is not a number");
      out.push_back(v);
    }
    if (out.size() != expected)
      return make_error(ErrorCode::kTopologyMismatch, path + ": " + std::to_string(out.size()) + " weights, but the skin has " +
                                                          std::to_string(expected) + " vertices");
  }
  for (size_t i = 0; i < out.size(); ++i)
    if (!(out[i] >= 0.0f && out[i] <= 1.0f))
      return make_error(ErrorCode::kInvalidArgument, path + ": weight " + std::to_string(i) + " (skin vertex " + std::to_string(i) +
                                                         ") is " + std::to_string(out[i]) + "; weights are 0 to 1");
  return out;
}

void add_mask_options(CLI::App& cmd, MaskArgs& m, bool with_none) {
  auto* j = cmd.add_option("--mask-joints", m.joints, "mask: these joints and their children, feathered by the skin weights (a,b,c; -name leaves one out: spine,-neck)");
  auto* p = cmd.add_option("--mask-primitives", m.primitives, "mask: these primitives of the character, by index (0,2)");
  auto* w = cmd.add_option("--mask-weights", m.weights,
                           "mask: painted weights, one per skin vertex in [0, 1] (a JSON array, or numbers separated by white space)");
  auto* me = cmd.add_option("--mask-meshes", m.meshes, "mask: every primitive of these glTF meshes, by name or index (body,head)");
  j->excludes(p);
  w->excludes(j)->excludes(p);
  me->excludes(j)->excludes(p)->excludes(w);
  if (with_none)
    cmd.add_flag("--no-mask", m.none, "no mask: the layer may move every skin point")->excludes(j)->excludes(p)->excludes(w)->excludes(me);
}

// A deformer's mask (`mask`, `source`) as the options say; false (printed) when it cannot be made.
bool apply_mask(const Document& doc, const MaskArgs& m, const std::string& name, std::shared_ptr<const std::vector<float>>& out,
                std::string& source, const std::string& project) {
  if (m.none) {
    out = nullptr;
    source.clear();
    return true;
  }
  if (!m.weights.empty()) {
    auto w = read_mask_weights(m.weights, doc.character->num_vertices());
    if (!w) {
      std::fprintf(stderr, "error: %s: deformer '%s': mask: %s\n", project.c_str(), name.c_str(), w.error().message.c_str());
      return false;
    }
    out = std::make_shared<const std::vector<float>>(std::move(w).value());
    source.clear();  // painted
    return true;
  }
  std::string spec;
  if (!m.joints.empty()) spec = "joints " + m.joints;
  else if (!m.primitives.empty()) spec = "primitives " + m.primitives;
  else if (!m.meshes.empty()) spec = "meshes " + m.meshes;
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

// The parametric driver named `name` ("" = the first), as driver_at numbers them; -1 (printed) when there is none.
long find_driver(const Document& doc, const std::string& name, const std::string& project) {
  if (driver_count(doc) == 0) {
    std::fprintf(stderr, "error: %s: has no parametric driver (cagewrap deformer add --patch, cagewrap new --patch, or the editor's "
                         "Rig > Parametric driver)\n", project.c_str());
    return -1;
  }
  if (name.empty()) return 0;
  for (size_t i = 0; i < driver_count(doc); ++i)
    if (driver_name(doc, i) == name) return static_cast<long>(i);
  std::string names;
  for (size_t i = 0; i < driver_count(doc); ++i) names += (i ? ", " : "") + driver_name(doc, i);
  std::fprintf(stderr, "error: %s: has no parametric driver named '%s' (its drivers: %s)\n", project.c_str(), name.c_str(), names.c_str());
  return -1;
}

// Whether `name` is free for a new deformer: no layer and no driver has it (else printed).
bool name_free(const Document& doc, const std::string& name, const std::string& project) {
  bool taken = false;
  for (const DeformerLayer& l : doc.layers) taken = taken || l.name == name;
  for (size_t i = 0; i < driver_count(doc); ++i) taken = taken || driver_name(doc, i) == name;
  if (taken) std::fprintf(stderr, "error: %s: already has a deformer named '%s' (give another with --name)\n", project.c_str(), name.c_str());
  return !taken;
}

// `--attach MODE` and `--attach-point I:JOINT` (repeatable) into `place.attachment` (MODE closest: none,
// each control point to its closest limb); false (printed) when a mode, point or joint is not there.
bool parse_driver_attachment(const Document& d, const std::string& mode, const std::vector<std::string>& points,
                             size_t num_control_points, DriverPlacement& place, const std::string& project) {
  if (mode.empty() && points.empty()) return true;
  if (mode == "closest") {
    if (!points.empty()) {
      std::fprintf(stderr, "error: %s: --attach closest takes no --attach-point (give rigid, smooth or skin_weights)\n", project.c_str());
      return false;
    }
    place.attachment.reset();
    return true;
  }
  AttachmentSettings a = place.attachment ? *place.attachment : AttachmentSettings{AttachmentMode::kRigid};
  if (!mode.empty() && (!parse_attachment_mode(mode, a.mode) || a.mode == AttachmentMode::kFitted)) {
    std::fprintf(stderr, "error: %s: --attach '%s': give rigid, smooth, skin_weights or closest\n", project.c_str(), mode.c_str());
    return false;
  }
  const Skeleton& sk = d.character->skeleton;
  for (const std::string& p : points) {
    const size_t colon = p.find(':');
    const std::string number = p.substr(0, colon);  // kept: strtoul's `end` points into it
    char* end = nullptr;
    const unsigned long i = std::strtoul(number.c_str(), &end, 10);
    if (colon == std::string::npos || *end || colon == 0) {
      std::fprintf(stderr, "error: %s: --attach-point '%s': give CONTROL_POINT:JOINT (14:chest) or CONTROL_POINT:auto\n", project.c_str(),
                   p.c_str());
      return false;
    }
    if (i >= num_control_points) {
      std::fprintf(stderr, "error: %s: --attach-point '%s': the driver has control points 0 to %zu\n", project.c_str(), p.c_str(),
                   num_control_points - 1);
      return false;
    }
    const std::string joint = p.substr(colon + 1);
    std::optional<uint32_t> node;
    if (joint != "auto") {
      for (uint32_t n = 0; n < sk.size() && !node; ++n)
        if (sk.node(n).name == joint) node = n;
      if (!node) {
        std::fprintf(stderr, "error: %s: --attach-point '%s': the skeleton has no node '%s'\n", project.c_str(), p.c_str(), joint.c_str());
        return false;
      }
    }
    const uint32_t v = static_cast<uint32_t>(i);
    a = assign_vertices(a, std::span<const uint32_t>(&v, 1), node);
  }
  // checked as the rig will attach it (a node that is no joint of the skin is named there)
  std::vector<glm::vec3> probe(num_control_points, glm::vec3(0.0f));
  if (auto att = attach_cage(*d.character, probe, a); !att) {
    std::fprintf(stderr, "error: %s: the driver's attachment: %s\n", project.c_str(), att.error().message.c_str());
    return false;
  }
  place.attachment = std::move(a);
  return true;
}

// `--after` parsed into `place` (last, or 0 to the number of layers); false (printed) when it is neither.
bool parse_after(const Document& d, const std::string& after, DriverPlacement& place, const std::string& project) {
  if (after.empty()) return true;
  if (after == "last") {
    place.after = -1;
    return true;
  }
  char* end = nullptr;
  const long v = std::strtol(after.c_str(), &end, 10);
  if (*end || v < 0 || static_cast<size_t>(v) > d.layers.size()) {
    std::fprintf(stderr, "error: %s: --after '%s': give 0 to %zu layers, or last\n", project.c_str(), after.c_str(), d.layers.size());
    return false;
  }
  place.after = static_cast<int32_t>(v);
  return true;
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
    std::string project, out, cage, name, rename, stack, patch, posed_patch;
    uint32_t patch_density = 2;
    long index = -1, to = -1;
    double exponent = -1.0;
    bool mute = false, unmute = false, hide = false, show = false, driver = false;
    std::string solo, after, attach, driver_edits;
    std::vector<std::string> attach_points;
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

  auto* add = cmd->add_subcommand("add", "add a cage as a new layer at the end of the stack, or a parametric driver");
  common(add);
  auto* add_cage = add->add_option("--cage", args->cage, "the layer's cage at rest (.obj .ply .off .stl)");
  auto* add_patch = add->add_option("--patch", args->patch, "or a parametric driver (.cwpatch .gltf .glb): the first, or one more");
  add_cage->excludes(add_patch);
  add->add_option("--posed-patch", args->posed_patch, "with --patch: the driver sculpted (the same grids moved; default: no sculpt)")
      ->needs(add_patch);
  add->add_option("--patch-density", args->patch_density, "with --patch: its samples per knot span (1..1024)")
      ->capture_default_str()->needs(add_patch);
  add->add_option("--after", args->after, "with --patch: the number of layers before it (0 = right after the project's cage; last)")
      ->needs(add_patch);
  add->add_option("--attach", args->attach, "with --patch: how its control points follow the skeleton: rigid, smooth, skin_weights "
                                            "or closest (default: each rigidly to its closest limb)")->needs(add_patch);
  add->add_option("--attach-point", args->attach_points, "with --patch: a control point to a joint (14:chest; 14:auto undoes it)")
      ->needs(add_patch);
  add->add_option("--name", args->name, "its name (default: the file's name)");
  add_mask_options(*add, args->mask, false);
  add_bind_options(*add, args->bind);
  add->callback([args, load, &exit_code] {
    exit_code = 1;
    if (!finish_bind_options(args->bind)) return;
    if (args->cage.empty() && args->patch.empty()) {
      std::fprintf(stderr, "error: deformer add: give --cage (a layer) or --patch (a parametric driver)\n");
      return;
    }
    auto doc = load();
    if (!doc) return;
    const std::string& file = args->cage.empty() ? args->patch : args->cage;
    const std::string name = args->name.empty() ? std::filesystem::path(file).stem().string() : args->name;
    if (!name_free(*doc, name, args->project)) return;
    if (!args->patch.empty()) {  // a parametric driver
      auto driver = load_driver_or_report(args->patch, args->posed_patch, args->patch_density);
      if (!driver) return;
      DriverPlacement place;
      place.name = name;
      if (!parse_after(*doc, args->after, place, args->project)) return;
      if (!parse_driver_attachment(*doc, args->attach, args->attach_points, driver->rest.num_control_points(), place, args->project)) return;
      if (!apply_mask(*doc, args->mask, name, place.mask, place.mask_source, args->project)) return;
      if (any_bind_option(args->bind)) place.params = args->bind.params;
      Document d = *doc;
      if (!d.patch_driver) {
        d = with_driver_place(with_patch_driver(d, std::move(driver)), std::move(place));
      } else {
        std::vector<DriverDeformer> more = d.more_drivers;
        more.push_back({std::move(driver), std::move(place)});
        d = with_more_drivers(d, std::move(more));
      }
      exit_code = save_and_print(d, args->project, args->out);
      return;
    }
    auto cage = load_cage_or_report(args->cage);
    if (!cage) return;
    DeformerLayer l;
    l.name = name;
    l.cage = std::make_shared<const Cage>(std::move(*cage));
    l.params = args->bind.params;
    l.attachment = doc->attachment;
    l.attachment.overrides.clear();  // they named the project cage's vertices
    if (!apply_mask(*doc, args->mask, l, args->project)) return;
    std::vector<DeformerLayer> layers = doc->layers;
    layers.push_back(std::move(l));
    exit_code = save_and_print(with_layers(*doc, std::move(layers)), args->project, args->out);
  });

  auto* remove = cmd->add_subcommand("remove", "remove a layer or a parametric driver");
  common(remove);
  remove->add_option("--name", args->name, "the layer's (or with --driver, the driver's) name");
  remove->add_option("--index", args->index, "or its place: 1 = the first layer");
  remove->add_flag("--driver", args->driver, "remove a parametric driver (--name says which; default: the first)");
  remove->callback([args, load, &exit_code] {
    exit_code = 1;
    auto doc = load();
    if (!doc) return;
    if (args->driver) {
      const long i = find_driver(*doc, args->name, args->project);
      if (i < 0) return;
      std::printf("removed    %s\n", driver_name(*doc, size_t(i)).c_str());
      Document next = without_first_driver(with_first_driver(*doc, size_t(i)));
      if (soloed_driver(*doc) == size_t(i)) next = with_driver_solo(next, std::nullopt);
      exit_code = save_and_print(next, args->project, args->out);
      return;
    }
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
  set->add_option("--solo", args->solo, "only this deformer moves the skin (0 = the project's cage, 1 = the first layer; D, D2: a "
                                        "parametric driver, as the list labels it; none = off)");
  set->add_option("--to", args->to, "move it to this place among the layers (1 = first)");
  set->add_flag("--driver", args->driver, "change a parametric driver (--name says which; default: the first): its name, mute, mask, place, binding");
  set->add_option("--after", args->after, "with --driver: the number of layers before it (0 = right after the project's cage; last = after them all)");
  set->add_option("--attach", args->attach, "with --driver: how its control points follow the skeleton: rigid, smooth, skin_weights or "
                                            "closest (each rigidly to its closest limb)");
  set->add_option("--attach-point", args->attach_points, "with --driver: a control point to a joint (14:chest; 14:auto undoes it)");
  set->add_option("--set-edits", args->driver_edits,
                  "with --driver: its contributing-set edits from a set edits file (docs/edits-format.md; per-point edits "
                  "whose element ids are the driver's samples), or none");
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
    if (!args->solo.empty() && args->solo[0] == 'D') {  // a parametric driver, by its label in the list (D, D2, ...)
      char* end = nullptr;
      const long k = args->solo.size() == 1 ? 1 : std::strtol(args->solo.c_str() + 1, &end, 10);
      if ((args->solo.size() > 1 && *end) || k < 1 || static_cast<size_t>(k) > driver_count(d)) {
        std::fprintf(stderr, "error: %s: --solo '%s': the project's drivers are %s\n", args->project.c_str(), args->solo.c_str(),
                     driver_count(d) == 0 ? "none" : driver_count(d) == 1 ? "D" : ("D to D" + std::to_string(driver_count(d))).c_str());
        return;
      }
      d = with_driver_solo(d, static_cast<size_t>(k - 1));
    } else if (!args->solo.empty()) {
      DeformerStack stack = d.stack;
      stack.solo_driver.clear();
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
                              !args->mask.primitives.empty() || !args->mask.weights.empty() || !args->mask.meshes.empty() || args->mask.none || params;
    if (args->driver) {  // a parametric driver: its name, switch, place, mask and binding parameters
      const long i = find_driver(d, args->name, args->project);
      if (i < 0) return;
      if (args->index >= 0 || args->to >= 0) {
        std::fprintf(stderr, "error: %s: --driver takes --name, --rename, --mute, --unmute, --hide, --show, --after, --attach, "
                             "--attach-point, the mask options and binding parameters only\n", args->project.c_str());
        return;
      }
      if (!args->rename.empty() && args->rename != driver_name(d, size_t(i)) && !name_free(d, args->rename, args->project)) return;
      const DriverRef r = driver_at(d, size_t(i));
      std::shared_ptr<const PatchDriver> surface = i == 0 ? d.patch_driver : d.more_drivers[size_t(i) - 1].driver;
      if (args->mute || args->unmute) {
        PatchDriver p = *r.driver;
        p.drive_skin = args->unmute;
        surface = std::make_shared<const PatchDriver>(std::move(p));
      }
      DriverPlacement place = *r.place;
      const bool was_soloed = soloed_driver(d) == size_t(i);
      if (!args->rename.empty()) place.name = args->rename;
      if (args->hide) place.hidden = true;
      if (args->show) place.hidden = false;
      if (!parse_after(d, args->after, place, args->project)) return;
      if (!parse_driver_attachment(d, args->attach, args->attach_points, r.driver->rest.num_control_points(), place, args->project)) return;
      if (args->driver_edits == "none") {
        place.set_edits.clear();
      } else if (!args->driver_edits.empty()) {
        auto file = load_set_edits(args->driver_edits);
        if (!file) {
          report_error(file.error());
          return;
        }
        auto edits = resolve_sample_edits(*file, args->driver_edits, d.character->num_vertices(),
                                          patch_sample_count(r.driver->rest, r.driver->density));
        if (!edits) {
          report_error(edits.error());
          return;
        }
        place.set_edits = std::move(edits).value();
      }
      if (!apply_mask(d, args->mask, driver_name(d, size_t(i)), place.mask, place.mask_source, args->project)) return;
      if (params) {  // its own binding parameters, starting from those it binds with now
        auto p = bind_options_over(args->bind, driver_params(d, *r.place));
        if (!p) return;
        place.params = *p;
      }
      d = with_driver(d, size_t(i), std::move(surface), std::move(place));
      if (was_soloed) d = with_driver_solo(d, size_t(i));  // the solo follows a renamed driver
    } else if (!args->after.empty() || !args->attach.empty() || !args->attach_points.empty()) {
      std::fprintf(stderr, "error: %s: --after, --attach and --attach-point are the parametric driver's: give --driver too\n",
                   args->project.c_str());
      return;
    } else if (args->index == 0 && args->name.empty()) {  // the project's own cage: only its switches
      if (!args->rename.empty() || args->to >= 0 || !args->mask.joints.empty() || !args->mask.primitives.empty() ||
          !args->mask.weights.empty() || !args->mask.meshes.empty() || args->mask.none) {
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
