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

#include "app/workspace/background_task.h"
#include "app/workspace/scene.h"
#include "app/workspace/workspace.h"
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
  // Items of the Cage menu (call between BeginMenu/EndMenu); they run the workspace's actions.
  void menu_items(Workspace& ws);
  // The automatic-cage dialog and the report window.
  void draw_windows(Scene& scene, const EditorHooks& hooks);
  // Finishes a background build: the new cage enters the document as one undo step (Workspace::replace_cage).
  void poll(Workspace& ws, const EditorHooks& hooks);

  // Opens the automatic-cage dialog / starts a build with the dialog's parameters (scripts use it).
  void open_auto_cage_dialog() { show_dialog_ = true; }
  void start_auto_cage(Scene& scene);
  AutoCageParams& auto_params() { return params_; }
  bool busy() const { return job_ != nullptr; }
  // The menu asked for a cage file: the editor opens its file browser and calls import_cage.
  bool take_import_request() { return std::exchange(import_requested_, false); }

  // Skin points that failed the cage-quality test of the last automatic cage, while that cage is the
  // document's and they are to be shown (empty otherwise).
  std::span<const uint32_t> failing_points(const Scene& scene) const;
  bool has_failing_points(const Scene& scene) const;  // shown or not

 private:
  float weld_distance_share_ = 0.01f;  // of the cage's size, for "weld by distance"

  AutoCageParams params_;
  bool show_dialog_ = false, show_report_ = false, show_failing_ = true, import_requested_ = false;
  std::unique_ptr<BackgroundTask<AutoCageReport>> job_;
  std::optional<AutoCageReport> report_;  // the last build's figures (cage moved into the document)
  std::vector<uint32_t> failing_;
  std::shared_ptr<const Cage> failing_cage_;  // the cage failing_ was found for
};

}  // namespace cagewrap::app
