// The action table: every named thing the editor can do. Menus, shortcuts, panels and `--script`
// run the same entries, so a script line is an action's name and its arguments ("select grow",
// "move 0 0.1 0", "undo"), and docs/editor-actions.md is generated from this table
// (`cagewrap actions`).
//
// An action reads its arguments from a stream and reports through the workspace's log; it never
// throws. The workspace registers the document and selection actions (app/workspace/workspace.cpp);
// the window adds the ones that need it (screenshots, panels, the file browser: app/editor.cpp).
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

namespace cagewrap::app {

struct Action {
  std::string name;   // the script word, lower_case: "select", "undo", "gizmo_drag"
  std::string usage;  // its arguments: "all|none|invert|grow|shrink|mirror" ("" for none)
  std::string help;   // one line: what it does
  bool needs_document = true;  // refused, with a message, while no document is open
  // Frames a script waits after it before the next line (a dialog to open, a frame to draw).
  int script_frames = 0;
  std::function<void(std::istringstream& args)> run;
};

class ActionTable {
 public:
  // Adds an action; a second one of the same name replaces the first (the window overrides a
  // headless default).
  void add(Action action);
  const Action* find(std::string_view name) const;

  enum class Outcome : uint8_t { kRan, kBlank, kUnknown, kNeedsDocument };
  struct Result {
    Outcome outcome = Outcome::kBlank;
    std::string name;        // the action's name as written
    const Action* action = nullptr;
  };
  // Runs one line: "name args...". Blank lines and lines starting with '#' are kBlank.
  Result run(const std::string& line, bool have_document) const;
  // Runs an action by name with arguments; false when there is no such action.
  bool run(std::string_view name, const std::string& args = {}) const;

  // Every action, by name.
  std::vector<const Action*> list() const;
  // The reference: one Markdown table row per action (name, arguments, what it does).
  std::string reference() const;

 private:
  std::map<std::string, Action, std::less<>> actions_;
};

}  // namespace cagewrap::app
