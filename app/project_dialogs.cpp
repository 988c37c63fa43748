#if CAGEWRAP_GUI  // the editor's; nothing here without it
#include "app/project_dialogs.h"

#include <imgui/imgui.h>

#include <filesystem>
#include <utility>

#include "core/rig/character_embedding.h"
#include "core/base/file_hash.h"

namespace cagewrap::app {

namespace fs = std::filesystem;

namespace {

constexpr const char* kMissingTitle = "Character not found";
constexpr const char* kRecoveryTitle = "Recover unsaved work?";

// The folder to start browsing in: the nearest existing folder above `path`, else `fallback`'s.
std::string nearest_folder(const std::string& path, const std::string& fallback) {
  std::error_code ec;
  for (fs::path p = fs::path(path).parent_path(); !p.empty(); p = p.parent_path()) {
    if (fs::is_directory(p, ec)) return p.string();
    if (p == p.root_path()) break;
  }
  return fs::path(fallback).parent_path().string();
}

}  // namespace

void ProjectDialogs::character_missing(const std::string& project, const std::string& character) {
  missing_project_ = project;
  missing_character_ = character;
  open_missing_ = true;
}

void ProjectDialogs::offer_recovery(std::vector<RecoveryFile> files) {
  recoveries_ = std::move(files);
  open_recovery_ = !recoveries_.empty();
}

ProjectDialogs::Request ProjectDialogs::draw() {
  Request request;
  if (!missing_character_.empty()) {
    if (std::exchange(open_missing_, false)) ImGui::OpenPopup(kMissingTitle);
    if (ImGui::BeginPopupModal(kMissingTitle, nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
      ImGui::Text("The character %s was not found.", missing_character_.c_str());
      ImGui::TextDisabled("The project %s names it.", missing_project_.c_str());
      ImGui::TextDisabled("Locate the file (the project remembers the new place when it is saved), or cancel.");
      const std::string answer = std::exchange(answer_missing_, std::string());
      if (ImGui::Button("Locate...", ImVec2(120, 0)) || answer == "locate") {
        request.kind = Request::Kind::kLocate;
        request.project = locating_ = missing_project_;
        request.character = missing_character_;
        request.directory = nearest_folder(missing_character_, missing_project_);
        missing_character_.clear();
        ImGui::CloseCurrentPopup();
      }
      ImGui::SameLine();
      if (ImGui::Button("Cancel", ImVec2(120, 0)) || answer == "cancel") {
        missing_character_.clear();
        ImGui::CloseCurrentPopup();
      }
      ImGui::EndPopup();
    }
    return request;
  }
  if (recoveries_.empty()) return request;
  if (std::exchange(open_recovery_, false)) ImGui::OpenPopup(kRecoveryTitle);
  if (ImGui::BeginPopupModal(kRecoveryTitle, nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    const RecoveryFile f = recoveries_.front();
    ImGui::Text("Recover unsaved work from %s?", format_local_time(f.modified).c_str());
    ImGui::Text("Project: %s", f.info.project.empty() ? "untitled (never saved)" : f.info.project.c_str());
    ImGui::TextDisabled("Autosaved in %s", f.path.c_str());
    if (recoveries_.size() > 1)
      ImGui::TextDisabled("%zu more recovery file%s after this one", recoveries_.size() - 1, recoveries_.size() > 2 ? "s" : "");
    ImGui::TextDisabled("Recover opens it (unsaved); Discard deletes it; Later asks again at the next start.");
    const std::string answer = std::exchange(answer_recovery_, std::string());
    bool answered = false;
    if (ImGui::Button("Recover", ImVec2(100, 0)) || answer == "recover") {
      request.kind = Request::Kind::kRecover;
      request.recovery = f;
      answered = true;
    }
    ImGui::SameLine();
    if (ImGui::Button("Discard", ImVec2(100, 0)) || answer == "discard") {
      std::error_code ec;
      fs::remove(f.path, ec);
      request.kind = Request::Kind::kDiscardRecovery;
      request.recovery = f;
      answered = true;
    }
    ImGui::SameLine();
    if (ImGui::Button("Later", ImVec2(100, 0)) || answer == "later") answered = true;
    if (answered) {
      recoveries_.erase(recoveries_.begin());
      open_recovery_ = !recoveries_.empty();
      ImGui::CloseCurrentPopup();
    }
    ImGui::EndPopup();
  }
  return request;
}

void ProjectDialogs::set_embedded(Scene& scene, bool embed, const EditorHooks& hooks, Request& request) {
  const Document& doc = scene.doc();
  if (embed) {
    auto e = embed_character(doc);
    if (!e) {
      hooks.show_error(e.error().message);
      return;
    }
    scene.apply("Embed the character", std::move(e).value());
    hooks.log("embedded the character " + doc.character_path + " in the project (" +
                  std::to_string(scene.doc().embedded_character->size()) + " bytes); save to keep it",
              false);
  } else {
    // back to the file it came from when that still holds these bytes; else ask where
    auto hash = hash_file(doc.character_path);
    if (!hash || *hash != doc.character_hash) {
      request.kind = Request::Kind::kSaveCharacter;
      request.character = fs::path(doc.character_path).filename().string();
      request.directory = doc.project_path.empty() ? nearest_folder(doc.character_path, ".")
                                                   : fs::path(doc.project_path).parent_path().string();
      return;
    }
    unembed_to(scene, doc.character_path, hooks);
  }
}

void ProjectDialogs::unembed_to(Scene& scene, const std::string& path, const EditorHooks& hooks) {
  auto u = unembed_character(scene.doc(), path, /*replace=*/true);
  if (!u) {
    hooks.show_error(u.error().message);
    return;
  }
  scene.apply("Take the character out of the project", std::move(u).value());
  hooks.log("the project names the character file " + scene.doc().character_path + " again; save to keep it", false);
}

void ProjectDialogs::set_cache_binding(Scene& scene, bool cache, const EditorHooks& hooks) {
  scene.apply(cache ? "Cache the binding" : "Stop caching the binding", with_cache_binding(scene.doc(), cache));
  hooks.log(cache ? "the binding will be saved beside the project (opening it then needs no bind)"
                  : "the binding will no longer be saved beside the project",
            false);
}

ProjectDialogs::Request ProjectDialogs::menu_items(Scene& scene, const EditorHooks& hooks) {
  Request request;
  const Document& doc = scene.doc();
  const bool embedded = doc.embedded_character != nullptr;
  if (ImGui::MenuItem("Embed the character in the project", nullptr, embedded)) set_embedded(scene, !embedded, hooks, request);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip(embedded ? "The project holds the character file (%s): it opens with no other file.\nUntick to write it back out."
                               : "The project names the character file %s.\nTick to keep the file inside the project.",
                      embedded ? (std::to_string(doc.embedded_character->size()) + " bytes").c_str() : doc.character_path.c_str());
  const bool cached = doc.cache_binding;
  if (ImGui::MenuItem("Cache the binding beside the project", nullptr, cached)) set_cache_binding(scene, !cached, hooks);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("Saves the binding as <project>.cwb beside the project, so opening it needs no bind.\n"
                      "Used only while the character, cage, parameters, set edits and attachment are unchanged.");
  return request;
}

bool ProjectDialogs::script_command(const std::string& cmd, std::istringstream& in, Scene* scene, const EditorHooks& hooks,
                                    Request& request) {
  std::string arg;
  if (cmd == "answer_missing") in >> answer_missing_;
  else if (cmd == "answer_recovery") in >> answer_recovery_;
  else if (cmd == "embed" || cmd == "cache_binding") {
    in >> arg;
    if (!scene) return true;
    const bool on = arg == "on";
    if (cmd == "embed" && on != (scene->doc().embedded_character != nullptr)) set_embedded(*scene, on, hooks, request);
    if (cmd == "cache_binding" && on != scene->doc().cache_binding) set_cache_binding(*scene, on, hooks);
  } else {
    return false;
  }
  return true;
}

}  // namespace cagewrap::app

#endif  // CAGEWRAP_GUI
