#include "app/editor_window.h"

#include <algorithm>

#if CAGEWRAP_GUI

namespace cagewrap::app {

void Editor::set_scene(std::unique_ptr<Scene> scene) {
  ws_.set_scene(std::move(scene));
  outliner_for_ = nullptr;
  if (autosave_) autosave_->discard();  // the work it held was saved or discarded (guard_unsaved)
  recovered_ = false;
  skin_display_.scene_changed();
  topology_dirty_ = true;
  skin_bvh_built_ = false;
  display_key_.reset();
  if (options_.play && ws_.view.playback.clip >= 0) ws_.run("play");
  frame_all();
}

void Editor::load_initial() {
  std::string path = options_.file;
  std::string cage = options_.cage;
  if (path.empty()) {
    path = demo_character_path();
    if (cage.empty() && !path.empty()) cage = demo_cage_path(path);  // the demo's own generated cage
    if (path.empty()) {  // not found beside the binary: make it (deterministic, about a second)
      path = "/tmp/cagewrap_demo_character.glb";
      auto st = write_glb(path, make_demo_character());
      if (!st.ok()) log("error: " + st.error().message, true);
    }
  }
  if (has_extension(path, ".cagewrap")) {  // the project's own messages, prompts and recent files
    open_project(path);
    return;
  }
  auto s = load_scene(path, cage, {options_.keep_units});
  if (!s.ok()) {
    error_modal_ = s.error().message;
    log("error: " + s.error().message, true);
    return;
  }
  log("opened " + path + (cage.empty() ? "" : " with cage " + cage));
  if (!options_.file.empty())
    if (auto e = files_.add_recent(path); !e.empty()) log("warning: " + e);
  for (const auto& w : s.value()->doc().character->warnings) log("warning: " + w);
  set_scene(std::move(s).value());
}

void Editor::request_save() {
  if (!ws_.scene()) return;
  if (ws_.scene()->doc().project_path.empty()) open_save_popup_ = true;
  else save_project_to(ws_.scene()->doc().project_path);
}

bool Editor::save_project_to(const std::string& path) {
  SaveOptions options;  // each deformer's binding goes beside the project when it is cached and up to date
  size_t cached = 0;
  if (ws_.scene()->work().cache_binding) {
    const std::vector<const Binding*> bindings = ws_.scene()->deformer_bindings();
    options.binding = bindings[0];
    options.layer_bindings.assign(bindings.begin() + 1, bindings.end());
    options.driver_bindings = ws_.scene()->driver_bindings();
    cached = static_cast<size_t>(std::count_if(bindings.begin(), bindings.end(), [](const Binding* b) { return b != nullptr; }) +
                                 std::count_if(options.driver_bindings.begin(), options.driver_bindings.end(),
                                               [](const Binding* b) { return b != nullptr; }));
  }
  auto st = save_project(path, ws_.scene()->work(), options);
  if (!st.ok()) {
    error_modal_ = st.error().message;
    log("error: " + st.error().message, true);
    return false;
  }
  ws_.scene()->mark_saved(path);
  if (autosave_) autosave_->discard();
  recovered_ = false;
  log("saved " + path + (cached == 1 && options.binding ? " (and its binding, " + binding_cache_path(path) + ")"
                         : cached > 0 ? " (and " + std::to_string(cached) + " bindings beside it)" : ""));
  if (auto e = files_.add_recent(path); !e.empty()) log("warning: " + e);
  return true;
}

// Opens a project (or a recovery file); a missing character asks to be located, a recovery file
// becomes the unsaved work of the project it names. The current document stays on any error.
bool Editor::open_project(const std::string& path, const std::string& character_override) {
  ProjectOpen opened;
  auto s = load_project_scene(path, opened, character_override);
  for (const auto& w : opened.warnings) log("warning: " + w);
  if (!s.ok()) {
    log("error: " + s.error().message, true);
    if (!opened.missing_character.empty()) dialogs_.character_missing(path, opened.missing_character);
    else error_modal_ = s.error().message;
    return false;
  }
  for (const auto& n : opened.notes) log(n);
  set_scene(std::move(s).value());
  if (opened.recovery) {  // the work belongs to its project, not to the recovery file; not saved
    std::error_code ec;
    const int64_t when = modified_seconds(path).value_or(0);
    ws_.scene()->mark_saved(opened.recovery->project);
    ws_.scene()->mark_unsaved();
    recovered_ = true;
    if (autosave_ && autosave_->enabled()) {  // protected again at once, under this editor's name
      if (auto w = autosave_->write(ws_.scene()->doc()); !w) log("error: autosave failed: " + w.error().message, true);
    }
    std::filesystem::remove(path, ec);
    log("recovered the unsaved work" + (opened.recovery->project.empty() ? std::string(" (untitled)") : " of " + opened.recovery->project) +
        (when ? " from " + format_local_time(when) : std::string()) + "; save to keep it");
    return true;
  }
  if (!character_override.empty()) {
    ws_.scene()->mark_unsaved();
    log("located the character at " + character_override + "; save the project to remember the new place");
  }
  log("opened " + path);
  if (auto e = files_.add_recent(path); !e.empty()) log("warning: " + e);
  return true;
}

bool Editor::open_path(const std::string& path) {
  if (has_extension(path, ".cagewrap")) return open_project(path);
  auto s = load_scene(path, "", {files_.browser().keep_units()});
  if (!s.ok()) {  // the current document stays as it is
    error_modal_ = s.error().message;
    log("error: " + s.error().message, true);
    return false;
  }
  log("opened " + path);
  for (const auto& w : s.value()->doc().character->warnings) log("warning: " + w);
  set_scene(std::move(s).value());
  if (auto e = files_.add_recent(path); !e.empty()) log("warning: " + e);
  return true;
}

// Opens the file browser in `dir`, else near the project, else in the last folder browsed.
void Editor::browse(FilePurpose purpose, const std::string& dir) {
  std::string near, name;
  if (purpose == FilePurpose::kSaveProject && ws_.scene()) {
    near = ws_.scene()->doc().project_path;
    name = near.empty() ? std::filesystem::path(ws_.scene()->doc().character_path).stem().string() + ".cagewrap"
                        : std::filesystem::path(near).filename().string();
  } else if (purpose == FilePurpose::kScreenshot) {
    name = "cagewrap_screenshot.png";
  }
  screenshot_view_only_ = false;
  if (!dir.empty()) files_.browser().open(purpose, dir, name);
  else files_.browse(purpose, near, name);
}

void Editor::act_on(const EditorFiles::Choice& choice) {
  switch (choice.purpose) {
    case FilePurpose::kOpen:
    case FilePurpose::kNewFromCharacter: {
      const std::string path = choice.path;
      guard_unsaved([this, path] { open_path(path); });
      break;
    }
    case FilePurpose::kImportCage: ws_.run("import_cage " + choice.path); break;
    case FilePurpose::kAddDeformer: ws_.run("deformer_add " + choice.path); break;
    case FilePurpose::kAddDriver: ws_.run("driver_add " + choice.path); break;
    case FilePurpose::kSaveProject:
      if (ws_.scene() && save_project_to(choice.path) && after_save_) after_save_();
      after_save_ = nullptr;
      break;
    case FilePurpose::kScreenshot:
      pending_screenshot_ = choice.path;
      pending_screenshot_frames_ = 2;  // the dialog leaves the picture first
      break;
    case FilePurpose::kExportGlb:
    case FilePurpose::kExportObj:
    case FilePurpose::kExportJson: export_panel_.set_output(choice.path); break;
    case FilePurpose::kLocateCharacter: {
      const std::string project = dialogs_.locating_project();
      dialogs_.located();
      if (!project.empty()) open_project(project, choice.path);
      break;
    }
    case FilePurpose::kSaveCharacter:
      if (ws_.scene()) ws_.unembed_character(choice.path);
      break;
  }
}

void Editor::act_on(const ProjectDialogs::Request& request) {
  using Kind = ProjectDialogs::Request::Kind;
  switch (request.kind) {
    case Kind::kNone: break;
    case Kind::kLocate: files_.browser().open(FilePurpose::kLocateCharacter, request.directory); break;
    case Kind::kSaveCharacter: files_.browser().open(FilePurpose::kSaveCharacter, request.directory, request.character); break;
    case Kind::kRecover: {
      const std::string path = request.recovery.path;
      guard_unsaved([this, path] { open_project(path); });
      break;
    }
    case Kind::kDiscardRecovery: log("discarded the recovery file " + request.recovery.path); break;
  }
}

void Editor::draw_file_popups() {
  if (!ImGui::GetIO().WantCaptureKeyboard && ImGui::IsKeyPressed(GLFW_KEY_F12)) browse(FilePurpose::kScreenshot);
  if (open_save_popup_ && ws_.scene()) browse(FilePurpose::kSaveProject);
  if (open_open_popup_) browse(FilePurpose::kOpen);
  if (cage_tools_.take_import_request()) browse(FilePurpose::kImportCage);
  if (auto b = export_panel_.take_browse_request()) files_.browse(b->purpose, b->near_path, b->file_name);
  open_save_popup_ = open_open_popup_ = false;
  if (auto choice = files_.draw_browser()) act_on(*choice);
  else if (!files_.browsing()) after_save_ = nullptr;  // the Save as was cancelled
  if (quit_requested_) {
    quit_requested_ = false;
    guard_unsaved([this] { close_ = true; });
  }
  if (open_prompt_) ImGui::OpenPopup("Save changes?");
  open_prompt_ = false;
  if (ImGui::BeginPopupModal("Save changes?", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    ImGui::TextUnformatted("The project has unsaved changes.");
    const std::string answer = std::exchange(script_answer_, std::string());
    if (ImGui::Button("Save", ImVec2(100, 0)) || answer == "save") {
      auto action = std::move(pending_action_);
      pending_action_ = nullptr;
      if (ws_.scene()->doc().project_path.empty()) {
        open_save_popup_ = true;
        after_save_ = std::move(action);
      } else if (save_project_to(ws_.scene()->doc().project_path) && action) {
        action();
      }
      ImGui::CloseCurrentPopup();
    }
    ImGui::SameLine();
    if (ImGui::Button("Discard", ImVec2(100, 0)) || answer == "discard") {
      auto action = std::move(pending_action_);
      pending_action_ = nullptr;
      ImGui::CloseCurrentPopup();
      if (action) action();
    }
    ImGui::SameLine();
    if (ImGui::Button("Cancel", ImVec2(100, 0)) || answer == "cancel") {
      pending_action_ = nullptr;
      ImGui::CloseCurrentPopup();
    }
    ImGui::EndPopup();
  }
}

// Runs `action` now, or after the artist saved or discarded the unsaved changes (Cancel drops it).
void Editor::guard_unsaved(std::function<void()> action) {
  if (ws_.scene() && ws_.scene()->dirty()) {
    pending_action_ = std::move(action);
    open_prompt_ = true;
  } else {
    action();
  }
}

}  // namespace cagewrap::app

#endif
