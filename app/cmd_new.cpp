// cagewrap new --character F [--cage C [--cage C2 ...] | --auto-cage FACES [auto-cage options]] [params]
//              [--stack in_order|sum|blend] [--embed] [--cache-binding] --out P.cagewrap
// A second and later --cage become deformer layers over the first (docs/deformer-stack.md), named
// by their files, with the same binding parameters and no mask (`cagewrap deformer set` adds one).
#include <cstdio>
#include <filesystem>

#include "app/auto_cage_options.h"
#include "app/cli_common.h"
#include "app/commands.h"
#include "core/io/patch_io.h"
#include "core/document/binding_cache.h"
#include "core/document/character_embedding.h"
#include "core/document/document.h"
#include "core/document/project_io.h"

namespace cagewrap::app {

void add_new_command(CLI::App& app, int& exit_code) {
  struct Args {
    std::string character, cage, out, stack;
    std::vector<std::string> patches, posed_patches;
    uint32_t patch_density = 2;
    std::vector<std::string> cages;
    BindOptions bind;
    AutoCageOptions auto_cage;
    CLI::Option* auto_cage_option = nullptr;
    bool embed = false, cache = false, keep_units = false;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("new", "make a project (.cagewrap) from a character and a cage");
  cmd->add_option("--character", args->character, "character (.glb .gltf .fbx .dae .x .b3d .ms3d .smd .md5mesh)")->required();
  add_keep_units_flag(*cmd, args->keep_units);
  cmd->add_option("--cage", args->cages,
                  "cage at rest (.obj .ply .off .stl); without it the project has no cage yet. Given again: more cages, "
                  "each a deformer layer over the first (docs/deformer-stack.md)");
  cmd->add_option("--stack", args->stack, "with several cages: how their skins combine (in_order, sum or blend)");
  cmd->add_option("--patch", args->patches,
                  "a parametric driver (.cwpatch .gltf .glb) that drives the skin: its sculpt (posed minus rest control "
                  "points) follows the skeleton after the cages (docs/parametric-drivers.md). Given again: more drivers "
                  "(each named after its file)");
  cmd->add_option("--posed-patch", args->posed_patches,
                  "the driver sculpted (its control points moved at the bind pose), one per --patch in the same order; "
                  "default: as --patch (no sculpt)");
  cmd->add_option("--patch-density", args->patch_density, "the driver's samples per knot span (1..1024)")->capture_default_str();
  cmd->add_option("--out", args->out, "project file to write (.cagewrap)")->required();
  cmd->add_flag("--embed", args->embed, "put the character file into the project: it opens with no other file");
  cmd->add_flag("--cache-binding", args->cache,
                "bind now and keep the binding beside the project (P.cagewrap.cwb): opening needs no bind");
  add_bind_options(*cmd, args->bind);
  args->auto_cage_option = add_auto_cage_options(*cmd, args->auto_cage, "--auto-cage");
  args->auto_cage_option->description("build the cage automatically with about this many triangles (see `cagewrap cage`)");
  cmd->callback([args, &exit_code] {
    exit_code = 1;
    if (!finish_bind_options(args->bind)) return;
    args->cage = args->cages.empty() ? std::string() : args->cages.front();
    DeformerStack stack;
    if (!args->stack.empty() && !parse_stack_mode(args->stack, stack.mode)) {
      std::fprintf(stderr, "error: --stack '%s': use in_order, sum or blend\n", args->stack.c_str());
      return;
    }
    const bool automatic = args->auto_cage_option->count() > 0;
    if (automatic && !args->cage.empty()) {
      std::fprintf(stderr, "error: give either --cage or --auto-cage, not both\n");
      return;
    }
    if (automatic && !finish_auto_cage_options(args->auto_cage, args->bind.params)) return;
    auto doc = document_from_files(args->character, args->cage, {args->keep_units});
    if (!doc) {
      report_error(doc.error());
      return;
    }
    *doc = with_params(*doc, args->bind.params);
    if (args->cages.size() > 1) {
      std::vector<DeformerLayer> layers;
      for (size_t i = 1; i < args->cages.size(); ++i) {
        auto cage = load_cage_or_report(args->cages[i]);
        if (!cage) return;
        DeformerLayer l;
        l.name = std::filesystem::path(args->cages[i]).stem().string();
        for (const DeformerLayer& other : layers)
          if (other.name == l.name) l.name += " " + std::to_string(i + 1);
        l.cage = std::make_shared<const Cage>(std::move(*cage));
        l.params = doc->params;
        l.attachment = doc->attachment;
        layers.push_back(std::move(l));
      }
      *doc = with_stack(with_layers(*doc, std::move(layers)), stack);
    }
    if (!args->posed_patches.empty() && args->posed_patches.size() != args->patches.size()) {
      std::fprintf(stderr, "error: %zu --posed-patch for %zu --patch: give one per driver, in the same order, or none\n",
                   args->posed_patches.size(), args->patches.size());
      return;
    }
    std::vector<DriverDeformer> more;
    for (size_t i = 0; i < args->patches.size(); ++i) {
      auto driver = load_driver_or_report(args->patches[i], args->posed_patches.empty() ? std::string() : args->posed_patches[i],
                                          args->patch_density);
      if (!driver) return;
      if (i == 0) *doc = with_patch_driver(*doc, std::move(driver));
      else {
        DriverPlacement place;
        place.name = std::filesystem::path(args->patches[i]).stem().string();
        more.push_back({std::move(driver), std::move(place)});
      }
    }
    if (!more.empty()) *doc = with_more_drivers(*doc, std::move(more));
    if (automatic && !add_automatic_cage(*doc, args->auto_cage.params, args->character, false)) return;
    if (args->embed) {
      auto e = embed_character(*doc);
      if (!e) {
        report_error(e.error());
        return;
      }
      *doc = std::move(e).value();
    }
    std::optional<Rig> rig;
    if (args->cache) {
      if (!doc->cage) {
        std::fprintf(stderr, "error: --cache-binding needs a cage (--cage or --auto-cage)\n");
        return;
      }
      *doc = with_cache_binding(*doc, true);
      rig = rig_of_project(*doc, args->out);
      if (!rig) return;
    }
    const SaveOptions options = rig ? save_options_caching(*rig, *doc) : SaveOptions{};
    if (auto s = save_project(args->out, *doc, options); !s) {
      report_error(s.error());
      return;
    }
    const Character& c = *doc->character;
    std::printf("character  %s: %zu vertices, %zu joints, %zu clips\n", args->character.c_str(), c.num_vertices(),
                c.num_joints(), c.clips.size());
    if (doc->cage)
      std::printf("cage       %s: %zu vertices, %zu faces\n", automatic ? "automatic" : args->cage.c_str(), doc->cage->num_vertices(),
                  doc->cage->polygons.num_faces());
    else
      std::printf("cage       none\n");
    for (const DeformerLayer& l : doc->layers)
      std::printf("deformer   %s: %zu vertices, %zu faces (a layer, %s)\n", l.name.c_str(), l.cage->num_vertices(),
                  l.cage->polygons.num_faces(), stack_mode_name(doc->stack.mode));
    for (size_t i = 0; i < driver_count(*doc); ++i)
      std::printf("driver     %s: %zu control points, density %u (drives the skin)\n", args->patches[i].c_str(),
                  driver_at(*doc, i).driver->rest.num_control_points(), driver_at(*doc, i).driver->density);
    if (doc->embedded_character)
      std::printf("embedded   the character (%zu bytes)\n", doc->embedded_character->size());
    if (rig)
      for (size_t d = 0; d < deformer_count(*doc); ++d) {
        const Binding* b = d == 0 ? &rig->binding() : rig->layer_binding(d - 1);
        if (b)
          std::printf("cached     %s in %s (%u points, %zu entries)\n", d == 0 ? "the binding" : ("deformer " + std::to_string(d) + "'s binding").c_str(),
                      binding_cache_path(args->out, d).c_str(), b->num_points, b->num_entries());
      }
    for (size_t i = 0; rig && i < driver_count(*doc); ++i)
      if (const Binding* b = rig->driver_binding(i))
        std::printf("cached     driver '%s''s binding in %s (%u points, %zu entries)\n", driver_name(*doc, i).c_str(),
                    driver_binding_cache_path(args->out, i).c_str(), b->num_points, b->num_entries());
    std::printf("wrote      %s\n", args->out.c_str());
    exit_code = 0;
  });
}

}  // namespace cagewrap::app
