// The workspace's project storage (app/workspace/workspace.h "project storage"): the character
// embedded in the project or named by it (core/document/character_embedding.h), and the binding
// cached beside the project (core/document/binding_cache.h). The File menu and the actions embed and
// cache_binding run these; each change is one undo step.
#include <filesystem>

#include "app/workspace/workspace.h"
#include "core/base/file_hash.h"
#include "core/document/character_embedding.h"

namespace cagewrap::app {

namespace fs = std::filesystem;

std::string Workspace::browse_folder_near(const std::string& path, const std::string& fallback) {
  std::error_code ec;
  for (fs::path p = fs::path(path).parent_path(); !p.empty(); p = p.parent_path()) {
    if (fs::is_directory(p, ec)) return p.string();
    if (p == p.root_path()) break;
  }
  return fs::path(fallback).parent_path().string();
}

bool Workspace::embed_character() {
  if (!scene_) return false;
  const Document& doc = scene_->doc();
  if (doc.embedded_character) return true;
  auto e = cagewrap::embed_character(doc);
  if (!e) {
    report_error(e.error().message);
    return false;
  }
  const std::string from = doc.character_path;
  scene_->apply("Embed the character", std::move(e).value());
  log("embedded the character " + from + " in the project (" + std::to_string(scene_->doc().embedded_character->size()) +
      " bytes); save to keep it");
  return true;
}

std::optional<Workspace::CharacterFileAsk> Workspace::where_to_unembed() const {
  if (!scene_ || !scene_->doc().embedded_character) return std::nullopt;
  const Document& doc = scene_->doc();
  auto hash = hash_file(doc.character_path);
  if (hash && *hash == doc.character_hash) return std::nullopt;  // the file it came from still holds these bytes
  CharacterFileAsk ask;
  ask.name = fs::path(doc.character_path).filename().string();
  ask.directory = doc.project_path.empty() ? browse_folder_near(doc.character_path, ".")
                                           : fs::path(doc.project_path).parent_path().string();
  return ask;
}

bool Workspace::unembed_character(const std::string& path) {
  if (!scene_) return false;
  const Document& doc = scene_->doc();
  if (!doc.embedded_character) return true;
  std::string to = path;
  if (to.empty()) {
    if (where_to_unembed()) {
      fail("the character file " + doc.character_path +
           " is gone or holds other bytes: say where to write the embedded character (embed off PATH)");
      return false;
    }
    to = doc.character_path;
  }
  auto u = cagewrap::unembed_character(doc, to, /*replace=*/true);
  if (!u) {
    report_error(u.error().message);
    return false;
  }
  scene_->apply("Take the character out of the project", std::move(u).value());
  log("the project names the character file " + scene_->doc().character_path + " again; save to keep it");
  return true;
}

bool Workspace::set_cache_binding(bool cache) {
  if (!scene_) return false;
  if (scene_->doc().cache_binding == cache) return true;
  scene_->apply(cache ? "Cache the binding" : "Stop caching the binding", with_cache_binding(scene_->doc(), cache));
  log(cache ? "the binding will be saved beside the project (opening it then needs no bind)"
            : "the binding will no longer be saved beside the project");
  return true;
}

}  // namespace cagewrap::app
