#if CAGEWRAP_GUI  // the editor's; nothing here without it
#include "app/file_browser.h"

#include "core/io/gltf_loader.h"

#include <imgui/imgui.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>

namespace cagewrap::app {

namespace {

constexpr const char* kPopupId = "###file_browser";
const ImVec4 kFolderColour(0.55f, 0.78f, 1.0f, 1.0f);
const ImVec4 kErrorColour(1.0f, 0.45f, 0.4f, 1.0f);

bool key_pressed(ImGuiKey key) {
  return ImGui::IsKeyPressed(ImGui::GetKeyIndex(key));
}

std::string joined(const std::vector<std::string>& extensions) {
  std::string out;
  for (const auto& e : extensions) out += (out.empty() ? "" : " ") + e;
  return out;
}

// The character files the editor opens (glTF, and FBX, Collada, ... through assimp), after `first`.
std::vector<std::string> with_characters(std::vector<std::string> first) {
  for (const std::string& e : character_extensions())
    if (std::find(first.begin(), first.end(), e) == first.end()) first.push_back(e);
  return first;
}

// Opening a character from a file shows the "keep units" choice (a moved project's character has the project's).
bool shows_keep_units(FilePurpose purpose) { return purpose == FilePurpose::kOpen || purpose == FilePurpose::kNewFromCharacter; }

}  // namespace

const FilePurposeInfo& purpose_info(FilePurpose purpose) {
  static const FilePurposeInfo kOpen{"Open project or character", "Open", with_characters({".cagewrap"}), "", false};
  static const FilePurposeInfo kSave{"Save project as", "Save", {".cagewrap"}, ".cagewrap", true};
  static const FilePurposeInfo kCage{"Import cage", "Import", with_characters({".obj", ".ply", ".off", ".stl"}), "", false};
  static const FilePurposeInfo kLayer{"Add a cage as a deformer layer", "Add", {".obj", ".ply", ".off", ".stl", ".glb", ".gltf"}, "", false};
  static const FilePurposeInfo kDriver{"Add a parametric driver", "Add", {".cwpatch", ".glb", ".gltf"}, "", false};
  static const FilePurposeInfo kShot{"Save screenshot", "Save", {".png"}, ".png", true};
  static const FilePurposeInfo kNew{"New project from a character", "Create", character_extensions(), "", false};
  static const FilePurposeInfo kGlb{"Export to glTF binary", "Choose", {".glb"}, ".glb", true};
  static const FilePurposeInfo kObj{"Export OBJ frames (F.obj gives F_<clip>_<frame>.obj)", "Choose", {".obj"}, ".obj", true};
  static const FilePurposeInfo kJson{"Export the rig as JSON", "Choose", {".json"}, ".json", true};
  static const FilePurposeInfo kLocate{"Locate the character", "Use", character_extensions(), "", false};
  static const FilePurposeInfo kSaveCharacter{"Save the embedded character as", "Save", {".glb", ".gltf"}, ".glb", true};
  switch (purpose) {
    case FilePurpose::kOpen:
      return kOpen;
    case FilePurpose::kSaveProject:
      return kSave;
    case FilePurpose::kImportCage:
      return kCage;
    case FilePurpose::kAddDeformer:
      return kLayer;
    case FilePurpose::kAddDriver:
      return kDriver;
    case FilePurpose::kScreenshot:
      return kShot;
    case FilePurpose::kNewFromCharacter:
      return kNew;
    case FilePurpose::kExportGlb:
      return kGlb;
    case FilePurpose::kExportObj:
      return kObj;
    case FilePurpose::kExportJson:
      return kJson;
    case FilePurpose::kLocateCharacter:
      return kLocate;
    case FilePurpose::kSaveCharacter:
      return kSaveCharacter;
  }
  return kOpen;
}

void FileBrowser::open(FilePurpose purpose, const std::string& directory, const std::string& file_name) {
  purpose_ = purpose;
  const bool hidden = model_.show_hidden();
  model_ = FileBrowserModel(FileFilter{purpose_info(purpose).extensions, hidden});
  model_.open(directory);
  std::snprintf(name_field_, sizeof name_field_, "%s", file_name.c_str());
  set_path_field();
  selected_ = -1;
  error_.clear();
  overwrite_.clear();
  ask_overwrite_ = confirm_requested_ = cancel_requested_ = close_ = false;
  opening_ = true;
}

void FileBrowser::set_path_field() {
  std::snprintf(path_field_, sizeof path_field_, "%s", model_.directory().c_str());
  ++path_generation_;
}

bool FileBrowser::select(const std::string& name) {
  const auto& entries = model_.entries();
  for (size_t i = 0; i < entries.size(); ++i)
    if (entries[i].name == name) {
      selected_ = static_cast<int>(i);
      if (purpose_info(purpose_).save && !entries[i].is_directory) set_file_name(name);
      return true;
    }
  return false;
}

void FileBrowser::set_file_name(const std::string& name) {
  std::snprintf(name_field_, sizeof name_field_, "%s", name.c_str());
  ++name_generation_;  // a field being typed in keeps its own text: this makes it a new field
}

std::optional<std::string> FileBrowser::choose(const std::string& path) {
  std::error_code ec;
  if (purpose_info(purpose_).save && std::filesystem::exists(path, ec)) {
    overwrite_ = path;
    ask_overwrite_ = true;
    return std::nullopt;
  }
  return path;
}

std::optional<std::string> FileBrowser::activate(FileEntry entry) {
  if (!entry.is_directory) return choose(model_.path_of(entry));
  if (model_.navigate(model_.path_of(entry))) selected_ = -1;
  set_path_field();
  return std::nullopt;
}

std::optional<std::string> FileBrowser::accept() {
  error_.clear();
  const FilePurposeInfo& info = purpose_info(purpose_);
  const auto& entries = model_.entries();
  const FileEntry* sel = selected_ >= 0 && selected_ < static_cast<int>(entries.size())
                             ? &entries[static_cast<size_t>(selected_)]
                             : nullptr;
  if (!info.save) {
    if (sel) return activate(*sel);
    error_ = "select a file first (or double-click it)";
    return std::nullopt;
  }
  // saving: the typed name is the file; with no name, a selected folder is entered
  if (sel && sel->is_directory && name_field_[0] == '\0') return activate(*sel);
  auto target = resolve_save_name(model_.directory(), name_field_, info.extensions, info.default_extension);
  if (!target) {
    error_ = target.error().message;
    return std::nullopt;
  }
  return choose(target->path);
}

void FileBrowser::draw_toolbar() {
  if (ImGui::Button("Up")) {
    if (model_.go_up()) selected_ = -1;
    set_path_field();
  }
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Parent folder (Backspace)");
  ImGui::SameLine();
  const float right = ImGui::CalcTextSize("Hidden files").x + ImGui::GetFrameHeight() +
                      ImGui::CalcTextSize("Refresh").x + 4 * ImGui::GetStyle().ItemSpacing.x +
                      2 * ImGui::GetStyle().FramePadding.x;
  ImGui::SetNextItemWidth(-right);
  ImGui::PushID(path_generation_);
  const bool entered =
      ImGui::InputText("##folder", path_field_, sizeof path_field_, ImGuiInputTextFlags_EnterReturnsTrue);
  ImGui::PopID();
  if (entered) {
    const std::string typed = path_field_;
    selected_ = -1;
    if (auto file = model_.enter_typed_path(typed)) {  // a file typed in the folder field
      if (purpose_info(purpose_).save)
        set_file_name(std::filesystem::path(*file).filename().string());
      else if (select(std::filesystem::path(*file).filename().string()))
        confirm_requested_ = true;
    }
    if (model_.error().empty()) set_path_field();  // on an error the typed text stays to be corrected
  }
  if (ImGui::IsItemHovered() && !ImGui::IsItemActive())
    ImGui::SetTooltip("Type a folder (or a file) and press Enter; ~ is your home");
  ImGui::SameLine();
  if (ImGui::Button("Refresh")) model_.refresh();
  ImGui::SameLine();
  bool hidden = model_.show_hidden();
  if (ImGui::Checkbox("Hidden files", &hidden)) {
    selected_ = -1;
    model_.set_show_hidden(hidden);
  }
}

int FileBrowser::draw_entries() {
  const FilePurposeInfo& info = purpose_info(purpose_);
  const auto& entries = model_.entries();
  int activated = -1;
  const float footer =
      ImGui::GetFrameHeightWithSpacing() * (info.save || shows_keep_units(purpose_) ? 3.0f : 2.0f) + ImGui::GetStyle().ItemSpacing.y;
  const ImGuiTableFlags flags = ImGuiTableFlags_ScrollY | ImGuiTableFlags_RowBg |
                                ImGuiTableFlags_BordersOuter | ImGuiTableFlags_BordersV |
                                ImGuiTableFlags_Resizable;
  if (!ImGui::BeginTable("entries", 3, flags, ImVec2(0, -footer))) return -1;
  ImGui::TableSetupScrollFreeze(0, 1);
  ImGui::TableSetupColumn("Name", ImGuiTableColumnFlags_WidthStretch);
  ImGui::TableSetupColumn("Size", ImGuiTableColumnFlags_WidthFixed, ImGui::CalcTextSize("1023.0 MB").x);
  ImGui::TableSetupColumn("Modified", ImGuiTableColumnFlags_WidthFixed,
                          ImGui::CalcTextSize("2000-00-00 00:00").x);
  ImGui::TableHeadersRow();
  if (ImGui::IsWindowAppearing()) ImGui::SetScrollY(0.0f);
  // keyboard: arrows move the selection, Enter confirms, Backspace goes up (not while typing)
  bool scroll_to_selection = false;
  if (keys_free_ && !entries.empty()) {
    const int n = static_cast<int>(entries.size());
    if (key_pressed(ImGuiKey_DownArrow))
      selected_ = std::min(n - 1, selected_ + 1), scroll_to_selection = true;
    if (key_pressed(ImGuiKey_UpArrow)) selected_ = std::max(0, selected_ - 1), scroll_to_selection = true;
    if (scroll_to_selection && info.save && !entries[static_cast<size_t>(selected_)].is_directory)
      set_file_name(entries[static_cast<size_t>(selected_)].name);
  }
  ImGuiListClipper clipper;
  clipper.Begin(static_cast<int>(entries.size()));
  if (scroll_to_selection && selected_ >= 0) clipper.ForceDisplayRangeByIndices(selected_, selected_ + 1);
  while (clipper.Step()) {
    for (int i = clipper.DisplayStart; i < clipper.DisplayEnd; ++i) {
      const FileEntry& e = entries[static_cast<size_t>(i)];
      ImGui::TableNextRow();
      ImGui::TableSetColumnIndex(0);
      ImGui::PushID(i);
      if (e.is_directory)
        ImGui::PushStyleColor(ImGuiCol_Text, kFolderColour);
      else if (e.is_hidden)
        ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
      const std::string label = e.is_directory ? e.name + "/" : e.name;
      if (ImGui::Selectable(label.c_str(), selected_ == i,
                            ImGuiSelectableFlags_SpanAllColumns | ImGuiSelectableFlags_AllowDoubleClick)) {
        selected_ = i;
        if (info.save && !e.is_directory) set_file_name(e.name);
        if (ImGui::IsMouseDoubleClicked(0)) activated = i;
      }
      if (scroll_to_selection && selected_ == i) ImGui::SetScrollHereY();
      if (e.is_directory || e.is_hidden) ImGui::PopStyleColor();
      ImGui::TableNextColumn();
      if (!e.is_directory) {
        const std::string size = e.size ? format_size(*e.size) : "?";
        ImGui::SetCursorPosX(ImGui::GetCursorPosX() + ImGui::GetColumnWidth() -
                             ImGui::CalcTextSize(size.c_str()).x);
        ImGui::TextUnformatted(size.c_str());
      }
      ImGui::TableNextColumn();
      ImGui::TextDisabled("%s", e.modified ? format_time(*e.modified).c_str() : "?");
      ImGui::PopID();
    }
  }
  if (entries.empty()) {
    ImGui::TableNextRow();
    ImGui::TableSetColumnIndex(0);
    ImGui::TextDisabled("(no folders or %s files here)", joined(info.extensions).c_str());
  }
  ImGui::EndTable();
  return activated;
}

std::optional<std::string> FileBrowser::draw_overwrite_question() {
  const bool just_asked = ask_overwrite_;  // the key that asked must not also answer
  if (ask_overwrite_) {
    ImGui::OpenPopup("Replace file?");
    ask_overwrite_ = false;
  }
  std::optional<std::string> chosen;
  if (ImGui::BeginPopupModal("Replace file?", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    ImGui::Text("%s already exists.", overwrite_.c_str());
    ImGui::TextUnformatted("Replace it?");
    ImGui::Spacing();
    if (ImGui::Button("Replace", ImVec2(120, 0)) || confirm_requested_ ||
        (!just_asked && key_pressed(ImGuiKey_Enter))) {
      chosen = overwrite_;
      overwrite_.clear();
      ImGui::CloseCurrentPopup();
    }
    ImGui::SameLine();
    if (ImGui::Button("Cancel", ImVec2(120, 0)) || cancel_requested_ ||
        (!just_asked && key_pressed(ImGuiKey_Escape))) {
      overwrite_.clear();
      ImGui::CloseCurrentPopup();
    }
    confirm_requested_ = cancel_requested_ = false;
    ImGui::EndPopup();
  }
  return chosen;
}

std::optional<std::string> FileBrowser::draw() {
  if (!is_open()) return std::nullopt;
  const FilePurposeInfo& info = purpose_info(purpose_);
  const std::string title = std::string(info.title) + kPopupId;
  if (opening_) {
    ImGui::OpenPopup(title.c_str());
    opening_ = false;
    open_ = true;
  }
  const ImVec2 display = ImGui::GetIO().DisplaySize;
  ImGui::SetNextWindowPos(ImVec2(display.x * 0.5f, display.y * 0.5f), ImGuiCond_Appearing,
                          ImVec2(0.5f, 0.5f));
  ImGui::SetNextWindowSize(ImVec2(std::min(860.0f, display.x - 40), std::min(540.0f, display.y - 40)),
                           ImGuiCond_Appearing);
  bool keep = true;
  if (!ImGui::BeginPopupModal(title.c_str(), &keep, ImGuiWindowFlags_NoSavedSettings)) {
    open_ = false;  // closed with its title bar's X
    return std::nullopt;
  }
  // keys act on the dialog only when no field was being typed in (and no question is up)
  const bool question_up = !overwrite_.empty();
  keys_free_ = !ImGui::IsAnyItemActive() && !question_up;
  draw_toolbar();
  const std::string& error = !error_.empty() ? error_ : model_.error();
  if (!error.empty()) ImGui::TextColored(kErrorColour, "%s", error.c_str());
  int activated = draw_entries();  // double-clicked; Enter on the list acts on the selection
  if (activated < 0 && keys_free_ && key_pressed(ImGuiKey_Enter) && selected_ >= 0 &&
      selected_ < static_cast<int>(model_.entries().size()))
    activated = selected_;

  // footer: what is listed, the name field when saving, the buttons
  const DirectoryListing& l = model_.listing();
  std::string listed = joined(info.extensions) + " files";
  if (l.filtered_count)
    listed += ", " + std::to_string(l.filtered_count) +
              (l.filtered_count == 1 ? " other file" : " other files") + " not shown";
  if (l.hidden_count) listed += ", " + std::to_string(l.hidden_count) + " hidden";
  ImGui::TextDisabled("%s", listed.c_str());
  if (shows_keep_units(purpose_)) {
    ImGui::Checkbox("Keep the file's units and up axis", &keep_units_);
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("FBX, Collada, .x, ...: read the scene as the file has it. Off: brought to metres, Y up, as glTF is\n"
                        "(the file's unit and up axis are in the log). A project remembers the choice.");
  }
  bool enter = false;
  if (info.save) {
    ImGui::AlignTextToFramePadding();
    ImGui::TextUnformatted("File name");
    ImGui::SameLine();
    ImGui::SetNextItemWidth(-1);
    if (ImGui::IsWindowAppearing()) ImGui::SetKeyboardFocusHere();
    ImGui::PushID(name_generation_);
    enter = ImGui::InputText("##name", name_field_, sizeof name_field_, ImGuiInputTextFlags_EnterReturnsTrue);
    ImGui::PopID();
  }
  const float button = 110.0f;
  ImGui::SetCursorPosX(ImGui::GetWindowContentRegionMax().x - 2 * button - ImGui::GetStyle().ItemSpacing.x);
  const bool confirm = ImGui::Button(info.action, ImVec2(button, 0));
  ImGui::SameLine();
  const bool cancel = ImGui::Button("Cancel", ImVec2(button, 0));

  std::optional<std::string> chosen;
  if (question_up) {
    // the question answers confirm and cancel requests
  } else if (activated >= 0) {
    chosen = activate(model_.entries()[static_cast<size_t>(activated)]);
  } else if (confirm || enter || confirm_requested_ || (keys_free_ && key_pressed(ImGuiKey_Enter))) {
    confirm_requested_ = false;
    chosen = accept();
  } else if (keys_free_ && key_pressed(ImGuiKey_Backspace)) {
    if (model_.go_up()) selected_ = -1;
    set_path_field();
  }
  if (!overwrite_.empty())
    if (auto replaced = draw_overwrite_question()) chosen = replaced;
  if (chosen || cancel || (!question_up && cancel_requested_) ||
      (keys_free_ && key_pressed(ImGuiKey_Escape))) {
    cancel_requested_ = false;
    ImGui::CloseCurrentPopup();
    open_ = false;
  }
  ImGui::EndPopup();
  return chosen;
}

}  // namespace cagewrap::app

#endif  // CAGEWRAP_GUI
