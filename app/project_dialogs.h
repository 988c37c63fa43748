// The editor's prompts around opening and keeping a project, so app/editor.cpp only acts on the
// answers: a character file that moved ("The character X was not found. Locate..."), the unsaved
// work an earlier run left in recovery files (app/workspace/autosave.h: "Recover unsaved work from <time>?"
// Recover / Discard / Later), and the File menu's storage toggles (embed the character in the
// project, cache the binding beside it; core/document/character_embedding.h, core/document/binding_cache.h).
#pragma once

#include <sstream>
#include <string>
#include <vector>

#include "app/cage_tools.h"
#include "app/workspace/scene.h"
#include "app/workspace/autosave.h"
#include "app/workspace/workspace.h"

namespace cagewrap::app {

class ProjectDialogs {
 public:
  // What the user asked for this frame.
  struct Request {
    enum class Kind {
      kNone,
      kLocate,           // browse for `character` (in `directory`), then open `project` with it
      kRecover,          // open `recovery` as the current document
      kDiscardRecovery,  // `recovery` was dropped (its file is already removed)
      kSaveCharacter,    // browse for where to write the embedded character (in `directory`, named `character`)
    };
    Kind kind = Kind::kNone;
    std::string project, character, directory;
    RecoveryFile recovery;
  };

  // The project (or recovery file) `project` names the character file `character`, which was not
  // found: asks whether to locate it.
  void character_missing(const std::string& project, const std::string& character);
  // The project waiting for the located character (after Locate..., until the browser answers).
  const std::string& locating_project() const { return locating_; }
  void located() { locating_.clear(); }

  // Recovery files to offer, newest first (app/workspace/autosave.h list_recovery_files).
  void offer_recovery(std::vector<RecoveryFile> files);
  bool offering_recovery() const { return !recoveries_.empty(); }

  // Draws the prompt that is up (the missing character first, then the recoveries one by one).
  Request draw();

  // Items of the File menu: "Embed the character in the project", "Cache the binding beside the
  // project" (the workspace's embed_character, unembed_character, set_cache_binding: one undo step
  // each). Turning embedding off writes the character back out: to the file it came from when that
  // still holds the same bytes, else where the returned kSaveCharacter request's browser says.
  Request menu_items(Workspace& ws);

  // Scripted button presses of the prompts (the next draw answers): locate|cancel, and
  // recover|discard|later.
  void answer_missing(std::istringstream& in) { in >> answer_missing_; }
  void answer_recovery(std::istringstream& in) { in >> answer_recovery_; }

 private:

  std::string missing_project_, missing_character_;  // the open question; "" = none
  bool open_missing_ = false;
  std::string locating_;
  std::vector<RecoveryFile> recoveries_;
  bool open_recovery_ = false;
  std::string answer_missing_, answer_recovery_;  // scripted button presses
};

}  // namespace cagewrap::app
