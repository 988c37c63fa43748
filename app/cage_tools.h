// The editor's Cage menu: build an automatic cage in the background (parameters, progress, cancel,
// a report with the points that fail the cage-quality test shown in the viewport), and the items that
// run the workspace's cage actions (import, the topology edits: app/workspace/workspace_cage.cpp).
// Every change of the document is one undo step. No GL here; ImGui only.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "app/workspace/scene.h"
#include "app/workspace/workspace.h"
#include "core/rig/auto_cage.h"
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
  // Items of the Cage menu (call between BeginMenu/EndMenu); they run the workspace's actions.
  void menu_items(Workspace& ws);
  // The automatic-cage dialog (its parameters, Build, the build's progress and Cancel) and the report
  // window of the last build (it opens when a build ends).
  void draw_windows(Workspace& ws);

  // Opens the automatic-cage dialog (scripts use it); its parameters are what Build starts with.
  void open_auto_cage_dialog() { show_dialog_ = true; }
  AutoCageParams& auto_params() { return params_; }
  // The menu asked for a cage file: the editor opens its file browser and runs import_cage.
  bool take_import_request() { return std::exchange(import_requested_, false); }

  // Skin points that failed the cage-quality test of the last automatic cage, while that cage is the
  // document's and they are to be shown (empty otherwise).
  std::span<const uint32_t> failing_points(const Workspace& ws) const;
  bool has_failing_points(const Workspace& ws) const;  // shown or not

 private:
  float weld_distance_share_ = 0.01f;  // of the cage's size, for "weld by distance"
  AutoCageParams params_;
  bool show_dialog_ = false, show_report_ = false, show_failing_ = true, import_requested_ = false;
  size_t shown_builds_ = 0;  // the workspace's finished builds when the report window was last opened
};

}  // namespace cagewrap::app
