// The editor without a window: the open document (Scene: the document, its undo steps and what is
// derived from it), the view state, the log and the action table. Everything the editor does to the
// document or the selection is a method here or an action in the table, so that tests drive the
// editor in-process (tests/workspace_test.cpp) and the window only draws and routes input.
//
//   Workspace ws;
//   ws.set_scene(load_scene(path, "").value());
//   ws.run("mode cage_vertices"); ws.run("select all"); ws.run("move 0 0.1 0"); ws.run("undo");
//
// A drag (the move gizmo) is begin_move / update_move per mouse event / end_move: one undo step.
#pragma once

#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/workspace/actions.h"
#include "app/workspace/background_task.h"
#include "app/workspace/scene.h"
#include "app/workspace/view_state.h"
#include "core/rig/cage_attachment.h"
#include "core/rig/keyposes.h"
#include "core/cage/auto_cage.h"
#include "core/document/set_editing.h"
#include "core/document/skin_brush.h"
#include "core/export/rig_exporter.h"

namespace cagewrap::app {

struct LogLine {
  std::string text;
  int repeats = 1;
  bool error = false;
};

class Workspace {
 public:
  Workspace();
  Workspace(const Workspace&) = delete;
  Workspace& operator=(const Workspace&) = delete;

  // ---- the document
  Scene* scene() { return scene_.get(); }
  const Scene* scene() const { return scene_.get(); }
  // Replaces the open document (the selection is cleared, the view kept).
  void set_scene(std::unique_ptr<Scene> scene);

  ViewState view;
  ActionTable actions;

  // ---- the log: every message for the artist (stdout/stderr as well, so a crash keeps it)
  void log(std::string text, bool error = false);
  const std::deque<LogLine>& log_lines() const { return log_; }
  // Runs one line of the action table ("select all"); unknown actions and actions that need a
  // document are logged as errors naming `where` ("script line 4"). False when it did not run.
  bool run(const std::string& line, const std::string& where = "action");
  // Called after each action that ran (the window uses it to wait frames in scripts).
  std::function<void(const Action&)> after_action;
  // Shows an error the artist must acknowledge (the window's modal); without it the error is logged.
  std::function<void(const std::string& message)> show_error;
  void report_error(const std::string& message);

  // ---- selection
  IndexSet& active_set();
  uint32_t active_count() const;  // elements of the active mode
  void edit_selection(SelectOp op);
  // The cage faces' centroids at `positions` (cage vertex positions).
  std::vector<glm::vec3> face_centroids(std::span<const glm::vec3> positions) const;
  double scene_size() const { return scene_ ? scene_->skin_diagonal : 1.0; }
  double mirror_tolerance() const { return view.mirror_tolerance_share * scene_size(); }
  // Keys and assignments go to the vertex nearest each mirror image: about an edge length.
  double rig_mirror_tolerance() const;
  double grid_spacing() const;  // the ground grid's step (a power of ten; Ctrl-snapping uses it)

  // ---- moving cage vertices (the move gizmo, `move`)
  // The cage vertices a move acts on: the selected vertices, or the corners of the selected faces.
  IndexSet move_set() const;
  Result<MoveWeights> move_weights_now() const;  // soft-selection and mirror shares of move_set
  std::vector<std::pair<uint32_t, float>> sim_paint_weights() const;
  std::optional<glm::dvec3> cage_selection_centre() const;  // of move_set, posed
  // A different thing to move (the parametric driver's control point): the document from the drag's
  // start moved by a displacement, and the undo step's label.
  struct Mover {
    std::function<Document(const Document& start, const glm::dvec3& total)> moved;
    std::string label;
  };
  // Starts a move of move_set (or of `mover`'s thing): false (logged) when there is nothing to move.
  bool begin_move(std::optional<Mover> mover = std::nullopt);
  // The drag's total displacement so far, snapped to the grid when `snap`; the document is rebuilt
  // from the drag's start each time, so nothing accumulates and undo restores the start exactly.
  void update_move(const glm::dvec3& total, bool snap = false);
  void end_move();     // one undo step (none when nothing moved)
  void cancel_move();  // back to the start
  bool moving() const { return move_.has_value(); }
  const glm::dvec3& move_total() const;  // zero when not moving

  // ---- undo
  void undo();
  void redo();

  // ---- the rig: how the cage follows the skeleton, and keyposes (workspace_rig.cpp; the Rig window
  // and the actions attach, keyset, key, remove_key, mirror_keyset run these). Each change is one undo
  // step; false (said why) when it cannot be made, the document kept.
  bool set_attachment_mode(AttachmentMode mode, double smooth_width);
  // The selected cage vertices follow the one selected joint (or, `automatic`, what the mode gives
  // them again); X-mirror editing assigns the mirror vertices to the mirror joint too.
  bool assign_cage_vertices(bool automatic);
  // A keypose set driven by the selected joint's rotation about its local axis (0 X, 1 Y, 2 Z); it
  // becomes the active set (view.keypose_set).
  bool add_keypose_set(int axis);
  // Keys what was sculpted since the last key (the cage's pose offsets) in the active set at the
  // drivers' current angles, and takes it out of the offsets.
  bool key_sculpt();
  bool remove_key(size_t key);  // of the active set
  bool mirror_keypose_set();    // the active set onto the joints and cage vertices across X
  // The active set replaced by `set` (mute, solo, rest key, interpolation, key values), checked first.
  bool replace_keypose_set(KeyposeSet set, const std::string& label);
  // The active set, clamped to the document's (null when there is none).
  const KeyposeSet* active_keypose_set();

  // ---- the cage (workspace_cage.cpp; the Cage menu and the actions cage_op and import_cage run these)
  // A new cage in the document, one undo step: the old one's sculpted offsets, set edits, vertex
  // assignments and keyed vertices go (they named its vertices and elements); its selection is cleared.
  void replace_cage(std::shared_ptr<const Cage> cage, const std::string& label);
  // Reads a cage file (OBJ, PLY, OFF, STL, glTF), logs its problems by element, replace_cage. False
  // (shown, the document kept) when it cannot be read.
  bool import_cage(const std::string& path);
  // A topology edit of the Cage menu on the selection, one undo step that carries offsets, set edits
  // and keys (core/document/topology_change.h): merge (selected vertices), weld D (distance), flip
  // (selected faces), flip_all, linear [N], loop [N] (levels), refine (selected faces), triangulate.
  // False (shown, the document kept) when it cannot be made.
  bool cage_operation(const std::string& op, double arg);
  // The automatic cage (core/cage/auto_cage.h) of the character at its bind pose, built in the
  // background with the scene's binding parameters; when it ends (poll_jobs) it becomes the document's
  // cage (replace_cage, one undo step) and its report is kept. False (said why) when one is being built
  // or the parameters are refused.
  struct AutoCageState {
    std::unique_ptr<BackgroundTask<AutoCageReport>> job;  // the build under way (null: none)
    std::optional<AutoCageReport> report;                 // the last finished build's figures (its mesh is the cage)
    std::shared_ptr<const Cage> cage;                     // the cage it made
    size_t builds = 0;                                    // builds finished so far (a new report)
  };
  bool start_auto_cage(AutoCageParams params);
  void cancel_auto_cage();
  const AutoCageState& auto_cage_state() const { return auto_cage_; }
  bool building_cage() const { return auto_cage_.job != nullptr; }

  // ---- contributing sets (workspace_sets.cpp; the Sets window and set_edit, select_limb_faces and
  // paint_at_skin_vertex run these): view.sets.mode with the selected cage faces on `points` (and their
  // mirror images with view.sets.mirror). One undo step, or part of the brush stroke under way.
  bool apply_set_edit(const IndexSet& points);
  // A brush stroke: each dab applies the edit to the skin points within view.sets.brush_radius of
  // `hit` (on skin triangle `triangle`) along the skin, at once; the stroke is one undo step.
  void begin_set_stroke();
  bool set_stroke_dab(uint32_t triangle, const glm::dvec3& hit);
  void end_set_stroke();
  bool set_stroking() const { return stroke_.has_value(); }
  // The cage faces whose corners all follow the given joints (by the attachment).
  IndexSet limb_faces(const IndexSet& joints) const;

  // ---- the cage simulation (workspace_sim.cpp; the Simulation window and the actions sim, sim_param,
  // sim_weights, sim_collider, sim_remove_collider run these): one undo step each, checked first; false
  // (said why, the document kept) when refused.
  bool set_simulation(bool on);
  bool set_sim_params(const SimParams& params);
  // Pins the selected cage vertices, or frees them with this mass and stiffness, each blended with what
  // it had by its soft-selection share (sim_paint_weights; pinning needs a share of 1/2).
  bool set_sim_weights(bool pinned, float mass, float stiffness);
  bool add_collider(Collider collider);
  bool remove_collider(size_t index);

  // ---- export (workspace_export.cpp; the Export window and the actions export, export_nowait and
  // export_cancel run these). The document is never changed.
  struct ExportState {
    std::unique_ptr<BackgroundTask<ExportReport>> job;  // the export under way (null: none)
    ExportRequest request;                              // the last one asked for
    std::optional<ExportReport> report;                 // the last finished one's
    std::string outcome;  // "cancelled; nothing was written", or the last refusal or failure
    int failures = 0;     // refused or failed (not cancelled) so far: a scripted editor run exits non-zero
    double started = 0.0, seconds = 0.0;
  };
  // Starts exporting the document as `request` asks, in the background (a bind of its own, then
  // run_export). False (shown as an error, counted in failures) when it cannot start: one is running,
  // no cage, no clip to bake, a bad path.
  bool start_export(const ExportRequest& request);
  void cancel_export();
  const ExportState& export_state() const { return export_; }
  bool exporting() const { return export_.job != nullptr; }
  // A script's export line, "FORMAT MODE|- FPS all|CLIP[,CLIP] PATH", for this document.
  Result<ExportRequest> parse_export(std::istringstream& in) const;
  // An export line that could not be read: logged as an error and counted in failures.
  void refuse_export(const std::string& message);
  // Finishes background work that is done (the frame loop calls it every frame; tests too): an
  // automatic cage into the document, an export's report into the log; their errors shown.
  void poll_jobs();

  // ---- playing and posing (view.playback: never undone)
  void set_pose_override(uint32_t node, const glm::quat& q);
  // Shows the clip `name` from its start, paused ("rest": the bind pose); false
  // when the character has no clip of that name.
  bool select_clip(const std::string& name);
  // The scene posed as view.playback says (Scene::update_pose), and the pose it shows.
  void update_pose();
  Pose current_pose() const;

 private:
  void add_actions();  // workspace_actions.cpp
  // Logs "error: <where the running action came from>: text".
  void fail(const std::string& text);
  std::string where_ = "action";
  std::unique_ptr<Scene> scene_;
  std::deque<LogLine> log_;
  struct MoveDrag {
    MoveWeights weights;
    std::optional<Mover> mover;  // (the drag's start is the history's: Scene::drag_start)
    glm::dvec3 total{0.0};
    bool rest = false;
  };
  std::optional<MoveDrag> move_;
  std::optional<SkinBrush> stroke_;  // a set-edit brush stroke under way
  // X-mirror maps of the skin points and the cage faces, for the cage they were made for
  struct SetMirrorMaps {
    std::shared_ptr<const Cage> cage;
    size_t skin_points = 0;
    MirrorMap points, faces;
    SetEditMirror maps;  // points at the two above
  };
  std::optional<SetMirrorMaps> set_mirror_;
  const SetEditMirror& set_edit_mirror();
  void clip_cage_selection();  // drops selected cage vertex and face ids past the cage's counts
  bool commit_sim(SimSettings sim, const std::string& label);
  ExportState export_;
  AutoCageState auto_cage_;
  void poll_auto_cage();
  void poll_export();
};

}  // namespace cagewrap::app
