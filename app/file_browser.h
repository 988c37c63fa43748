// The editor's file dialog: a Dear ImGui modal over app/workspace/file_listing.h's FileBrowserModel. The
// folder path (editable), a parent button, folders then the files the purpose accepts with sizes
// and times, double-click to enter or choose, a file name field and an overwrite question when
// saving, a hidden-files toggle, and errors that name the folder or file.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "app/workspace/file_listing.h"

namespace cagewrap::app {

enum class FilePurpose {
  kOpen,
  kSaveProject,
  kImportCage,
  kAddDeformer,  // a cage added as a layer of the deformer stack
  kAddDriver,    // a parametric driver added to the deformer stack
  kScreenshot,
  kNewFromCharacter,
  kExportGlb,
  kExportObj,
  kExportJson,
  kLocateCharacter,  // a project's character file that moved (app/project_dialogs.h)
  kSaveCharacter,    // where to write an embedded character taken out of the project
};

struct FilePurposeInfo {
  const char* title;                    // window title ("Open")
  const char* action;                   // the confirm button ("Open", "Save")
  std::vector<std::string> extensions;  // files listed (lower case, with the dot)
  const char* default_extension;        // appended to a typed save name without one
  bool save;                            // a file name field, and the overwrite question
};
const FilePurposeInfo& purpose_info(FilePurpose purpose);

class FileBrowser {
 public:
  // Shows the dialog from the next draw(), in `directory` (or its nearest existing ancestor), with
  // `file_name` in the name field when saving.
  void open(FilePurpose purpose, const std::string& directory, const std::string& file_name = {});
  bool is_open() const { return open_ || opening_; }
  FilePurpose purpose() const { return purpose_; }
  // The folder shown (remembered as the last folder browsed).
  const std::string& directory() const { return model_.directory(); }

  // Draws the dialog while it is open. Returns the chosen path (absolute) on the frame the user
  // confirms it (after the overwrite question, when saving over a file); the dialog is then closed.
  std::optional<std::string> draw();

  // What a click would do, for scripted tests (--script): select an entry by name, type the file
  // name, press the confirm button (or Replace when the overwrite question is up), or Cancel.
  bool select(const std::string& name);
  void set_file_name(const std::string& name);
  void confirm() { confirm_requested_ = true; }
  // The open dialog's "Keep the file's units and up axis" (CharacterLoadOptions::keep_units) for the character
  // chosen.
  bool keep_units() const { return keep_units_; }
  void set_keep_units(bool keep) { keep_units_ = keep; }
  void cancel() { cancel_requested_ = true; }

 private:
  // The confirm button: open the selected file or folder, or resolve the typed save name.
  std::optional<std::string> accept();
  // Double-click (or Enter on the list): enters a folder, chooses a file. By value: entering a
  // folder replaces the listing it came from.
  std::optional<std::string> activate(FileEntry entry);
  std::optional<std::string> choose(const std::string& path);  // asks before replacing a file
  void set_path_field();
  void draw_toolbar();
  // Returns the entry double-clicked (-1: none).
  int draw_entries();
  std::optional<std::string> draw_overwrite_question();

  FileBrowserModel model_;
  FilePurpose purpose_ = FilePurpose::kOpen;
  bool opening_ = false, open_ = false, close_ = false;
  bool confirm_requested_ = false, cancel_requested_ = false;
  bool keep_units_ = false;
  int selected_ = -1;           // index into model_.entries()
  std::string error_;           // from the last confirm (a bad save name); the model has its own
  std::string overwrite_;       // asks before replacing this file
  bool ask_overwrite_ = false;  // opens the question on the next draw
  bool keys_free_ = false;      // this frame: no field was being typed in, no question up
  char path_field_[4096] = {};
  char name_field_[1024] = {};
  int name_generation_ = 0, path_generation_ = 0;  // bumped when a field is set from outside it
};

}  // namespace cagewrap::app
