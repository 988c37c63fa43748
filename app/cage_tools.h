// The editor's Cage menu: build an automatic cage in the background (parameters, progress, cancel,
// a report with the points that fail the cage-quality test shown in the viewport), import a cage
// made elsewhere (checked, its problems listed by element), and the topology edits. Every change of
// the document is one undo step. No GL here; ImGui only.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "app/workspace/background_task.h"
#include "app/workspace/scene.h"
#include "core/cage/auto_cage.h"
#include "core/document/topology_change.h"
#include "core/geometry/selection.h"

namespace cagewrap::app {

// What the tools need from the editor window.
struct EditorHooks {
  std::function<void(const std::string& text, bool error)> log;
  std::function<void(const std::string& message)> show_error;  // a modal; the document is kept
};

class CageTools {
 public:
  // Items of the Cage menu (call between BeginMenu/EndMenu).
  void menu_items(Scene& scene, const Selection& selection, const EditorHooks& hooks);
  // The automatic-cage dialog and the report window.
  void draw_windows(Scene& scene, const EditorHooks& hooks);
  // Finishes a background build: commits the new cage as one undo step.
  void poll(Scene& scene, const EditorHooks& hooks);

  // Opens the automatic-cage dialog / starts a build with the dialog's parameters (scripts use it).
  void open_auto_cage_dialog() { show_dialog_ = true; }
  void start_auto_cage(Scene& scene);
  AutoCageParams& auto_params() { return params_; }
  bool busy() const { return job_ != nullptr; }
  // The menu asked for a cage file: the editor opens its file browser and calls import_cage.
  bool take_import_request() { return std::exchange(import_requested_, false); }

  // Imports a cage file (OBJ, PLY, OFF, STL, glTF): checked, problems logged by element, one undo
  // step. False (and the document unchanged) when it cannot be read.
  bool import_cage(Scene& scene, const std::string& path, const EditorHooks& hooks);

  // Skin points that failed the cage-quality test in the last report (empty: none or no report).
  const std::vector<uint32_t>& failing_points() const { return failing_; }
  bool show_failing() const { return show_failing_ && !failing_.empty(); }

 private:
  void commit_cage(Scene& scene, std::shared_ptr<const Cage> cage, const std::string& label);
 public:
  // Applies a topology edit (core/cage/cage_edit.h, core/cage/cage_subdivide.h) to the document as one undo
  // step, carrying offsets and set edits (core/document/topology_change.h). False on error (shown, document
  // unchanged).
  bool apply_edit(Scene& scene, Result<CageEdit> edit, const std::string& label, const EditorHooks& hooks);
  // The menu's operations by name, for scripts: merge, weld D, flip, flip_all, linear [N], loop [N],
  // refine. `selection` supplies the vertices (merge) and faces (flip, refine).
  bool run_operation(Scene& scene, const Selection& selection, const std::string& op, double arg, const EditorHooks& hooks);

 private:
  float weld_distance_share_ = 0.01f;  // of the cage's size, for "weld by distance"

  AutoCageParams params_;
  bool show_dialog_ = false, show_report_ = false, show_failing_ = true, import_requested_ = false;
  std::unique_ptr<BackgroundTask<AutoCageReport>> job_;
  std::optional<AutoCageReport> report_;  // the last build's figures (cage moved into the document)
  std::vector<uint32_t> failing_;
};

}  // namespace cagewrap::app
