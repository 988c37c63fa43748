#if CAGEWRAP_GUI  // the editor's; nothing here without it
#include "app/project_dialogs.h"

#include <imgui/imgui.h>

#include <filesystem>
#include <utility>


namespace cagewrap::app {

namespace fs = std::filesystem;

namespace {

constexpr const char* kMissingTitle = "Character not found";
constexpr const char* kRecoveryTitle = "Recover unsaved work?";


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
        request.directory = Workspace::browse_folder_near(missing_character_, missing_project_);
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

ProjectDialogs::Request ProjectDialogs::menu_items(Workspace& ws) {
  Request request;
  const Document& doc = ws.scene()->doc();
  const bool embedded = doc.embedded_character != nullptr;
  if (ImGui::MenuItem("Embed the character in the project", nullptr, embedded)) {
    if (!embedded) {
      ws.embed_character();
    } else if (auto ask = ws.where_to_unembed()) {  // the file it came from no longer holds it: ask where
      request.kind = Request::Kind::kSaveCharacter;
      request.character = ask->name;
      request.directory = ask->directory;
    } else {
      ws.unembed_character();
    }
  }
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip(embedded ? "The project holds the character file (%s): it opens with no other file.\nUntick to write it back out."
                               : "The project names the character file %s.\nTick to keep the file inside the project.",
                      embedded ? (std::to_string(doc.embedded_character->size()) + " bytes").c_str() : doc.character_path.c_str());
  const bool cached = doc.cache_binding;
  if (ImGui::MenuItem("Cache the binding beside the project", nullptr, cached)) ws.set_cache_binding(!cached);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("Saves the binding as <project>.cwb beside the project, so opening it needs no bind.\n"
                      "Used only while the character, cage, parameters, set edits and attachment are unchanged.");
  return request;
}

}  // namespace cagewrap::app

#endif  // CAGEWRAP_GUI
