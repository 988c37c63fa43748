// cagewrap project P.cagewrap [--embed | --unembed FILE [--replace]] [--cache-binding | --no-cache-binding]
//                             [--character FILE] [--out Q.cagewrap]
// How a project stores its character and its binding: prints it, and changes it. --embed puts the
// character file into the project (it then opens with no other file), --unembed writes it back out
// to FILE and names that; --cache-binding keeps the binding beside the project (P.cagewrap.cwb) so
// that opening it needs no bind, --no-cache-binding stops that and removes the file. --character
// locates a character file that moved. Writes P again (or Q) when anything changed.
#include <cstdio>
#include <filesystem>

#include "app/cli_common.h"
#include "app/commands.h"
#include "core/document/binding_cache.h"
#include "core/document/character_embedding.h"
#include "core/base/file_hash.h"
#include "core/document/project_io.h"

namespace cagewrap::app {

namespace {

void print_storage(const Document& doc) {
  if (doc.embedded_character)
    std::printf("character  embedded (%zu bytes, %s), from %s\n", doc.embedded_character->size(),
                doc.character_hash.c_str(), doc.character_path.c_str());
  else
    std::printf("character  file %s (%s)\n", doc.character_path.c_str(), doc.character_hash.c_str());
  if (!doc.cache_binding) {
    std::printf("binding    not cached (bound when opened)\n");
    return;
  }
  for (size_t d = 0; d < deformer_count(doc); ++d) {
    const Document view = deformer_document(doc, d);
    const std::string what = d == 0 ? "binding   " : "deformer " + std::to_string(d) + " '" + deformer_name(doc, d) + "':";
    if (deformer_muted(doc, d)) {
      std::printf("%s muted: not bound, not cached\n", what.c_str());
      continue;
    }
    if (view.binding_cache.file.empty()) {
      std::printf("%s cached on save; nothing cached yet\n", what.c_str());
      continue;
    }
    auto cached = load_binding_cache(view);
    if (cached)
      std::printf("%s cached in %s (up to date)\n", what.c_str(), view.binding_cache.file.c_str());
    else
      std::printf("%s cache not usable: %s\n", what.c_str(), cached.error().message.c_str());
  }
  for (size_t i = 0; i < driver_count(doc); ++i) {
    const std::string what = "driver D" + std::string(i ? std::to_string(i + 1) : "") + " '" + driver_name(doc, i) + "':";
    const BindingCacheRecord& r = driver_at(doc, i).place->binding_cache;
    if (!driver_moves_skin(doc, i))
      std::printf("%s does not move the skin: not bound, not cached\n", what.c_str());
    else if (r.file.empty())
      std::printf("%s cached on save; nothing cached yet\n", what.c_str());
    else if (auto cached = load_driver_binding_cache(doc, i))
      std::printf("%s cached in %s (up to date)\n", what.c_str(), r.file.c_str());
    else
      std::printf("%s cache not usable: %s\n", what.c_str(), cached.error().message.c_str());
  }
}

}  // namespace

void add_project_command(CLI::App& app, int& exit_code) {
  struct Args {
    std::string project, unembed, character, out;
    bool embed = false, replace = false, cache = false, no_cache = false;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "project", "show or change how a project stores its character (embedded or a file) and its binding (cached or not)");
  cmd->add_option("project", args->project, "project file (.cagewrap)")->required();
  auto* embed = cmd->add_flag("--embed", args->embed, "put the character file into the project (it then opens with no other file)");
  auto* unembed =
      cmd->add_option("--unembed", args->unembed, "write the embedded character to this file and have the project name it");
  embed->excludes(unembed);
  cmd->add_flag("--replace", args->replace, "with --unembed: replace an existing other file");
  auto* cache = cmd->add_flag("--cache-binding", args->cache,
                              "keep the binding beside the project (P.cagewrap.cwb): opening needs no bind");
  auto* no_cache = cmd->add_flag("--no-cache-binding", args->no_cache, "stop caching the binding and remove the cache file");
  cache->excludes(no_cache);
  cmd->add_option("--character", args->character, "the character file, when it moved (the project remembers the new place)");
  cmd->add_option("--out", args->out, "write the result here instead of over the project");
  cmd->callback([args, &exit_code] {
    exit_code = 1;
    const std::string& P = args->project;
    auto loaded = load_project(P, args->character);
    if (!loaded) {
      report_error(loaded.error());
      if (loaded.error().code == ErrorCode::kFileNotFound && args->character.empty())
        std::fprintf(stderr, "hint: give the character's new place with --character FILE\n");
      return;
    }
    for (const std::string& w : loaded->warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    Document doc = loaded->document;
    bool changed = loaded->character_relocated;
    if (args->embed && !doc.embedded_character) {
      auto e = embed_character(doc);
      if (!e) {
        report_error(e.error());
        return;
      }
      doc = std::move(e).value();
      changed = true;
    }
    if (!args->unembed.empty()) {
      auto u = unembed_character(doc, args->unembed, args->replace);
      if (!u) {
        report_error(u.error());
        return;
      }
      doc = std::move(u).value();
      std::printf("wrote      %s (the character, taken out of the project)\n", doc.character_path.c_str());
      changed = true;
    }
    const std::string out = args->out.empty() ? P : args->out;
    changed = changed || out != P;
    if (args->cache && !doc.cache_binding) doc = with_cache_binding(doc, true), changed = true;
    if (args->no_cache && doc.cache_binding) {
      doc = with_cache_binding(doc, false);
      changed = true;
    }
    // caching on: the project's binding, from a cache still valid or bound now
    std::optional<Rig> rig;
    if (doc.cache_binding && doc.cage) {
      // asked to cache: bind and write it when there is none yet or it is out of date; showing
      // the project (no option) never writes
      if (args->cache) {
        // each deformer that moves the skin needs its cache
        const StackBindingCache cached = load_stack_binding_caches(doc);
        if (cached.used < moving_deformers(doc) || cached.drivers_used < moving_drivers(doc)) changed = true;
      }
      if (changed) {
        rig = rig_of_project(doc, P);
        if (!rig) return;
      }
    } else if (doc.cache_binding) {
      std::fprintf(stderr, "warning: %s: the project has no cage yet; there is no binding to cache\n", P.c_str());
    }
    if (changed) {
      const SaveOptions options = rig ? save_options_caching(*rig, doc) : SaveOptions{};
      if (auto s = save_project(out, doc, options); !s) {
        report_error(s.error());
        return;
      }
      doc.project_path = out;
      for (size_t d = 0; rig && d < deformer_count(doc); ++d) {  // what the file now records
        if (!(d == 0 ? options.binding : options.layer_bindings[d - 1])) continue;
        BindingCacheRecord& r = d == 0 ? doc.binding_cache : doc.layers[d - 1].binding_cache;
        r.file = std::filesystem::absolute(binding_cache_path(out, d)).lexically_normal().string();
        auto h = hash_file(r.file);
        r.file_hash = h ? *h : std::string();
        r.inputs = binding_inputs(deformer_document(doc, d));
      }
      for (size_t i = 0; rig && i < driver_count(doc); ++i) {
        if (!options.driver_bindings[i]) continue;
        DriverPlacement place = *driver_at(doc, i).place;
        BindingCacheRecord& r = place.binding_cache;
        r.file = std::filesystem::absolute(driver_binding_cache_path(out, i)).lexically_normal().string();
        auto h = hash_file(r.file);
        r.file_hash = h ? *h : std::string();
        r.inputs = driver_binding_inputs(doc, i);
        doc = with_driver_place(doc, i, std::move(place));
      }
      std::printf("wrote      %s\n", out.c_str());
    }
    if (args->no_cache)
      for (size_t d = 0; d < deformer_count(doc) + driver_count(doc); ++d) {
        const std::string old_cache = d < deformer_count(doc) ? binding_cache_path(out, d)
                                                              : driver_binding_cache_path(out, d - deformer_count(doc));
        std::error_code ec;
        if (std::filesystem::remove(old_cache, ec)) std::printf("removed    %s\n", old_cache.c_str());
      }
    std::printf("project    %s\n", (changed ? out : P).c_str());
    print_storage(doc);
    exit_code = 0;
  });
}

}  // namespace cagewrap::app
