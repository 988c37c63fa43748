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
#include "core/cage/cage_attachment.h"
#include "core/cage/keyposes.h"
#include "core/rig/auto_cage.h"
#include "core/deform/set_editing.h"
#include "core/document/skin_brush.h"
#include "core/export/rig_exporter.h"
#include "core/rig/fidelity.h"

namespace cagewrap::app {

struct LogLine {
  std::string text;
  int repeats = 1;
  bool error = false;
};

// The heat-map colour of a distance to the file's skinning (share of the diagonal): grey within
// 0.5%, through yellow at 1%, orange at 2.5%, red from 5%.
glm::vec4 fidelity_color(float share);

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
  // Starts a move of move_set (or of `mover`'s thing; without one, of the parametric driver's selected
  // control point while view.patch.editing): false (logged) when there is nothing to move.
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
  // The automatic cage (core/rig/auto_cage.h) of the character at its bind pose, built in the
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

  // ---- the mask brush (workspace_mask.cpp; view.mask, the Deformers list, actions mask_*): paints the skin
  // mask of a deformer layer or a parametric driver, the stroke one undo step; the frame shows the stroke as
  // it goes (Scene::mask_preview), pose and the exports use the mask once the stroke ends.
  struct MaskTarget {
    size_t layer = 0;  // >= 1: deformer `layer` (the layer layer - 1)
    int driver = -1;   // >= 0: that parametric driver
    std::string name;
  };
  // What view.mask paints: its driver, else the active deformer when it is a layer; none (said why when
  // `say`) otherwise.
  std::optional<MaskTarget> mask_target(bool say);
  void begin_mask_stroke();
  bool mask_stroke_dab(uint32_t triangle, const glm::dvec3& hit);
  void end_mask_stroke();
  bool mask_stroking() const { return mask_stroke_.has_value(); }
  bool fill_mask(float value);  // every weight of the target's mask to `value` (one undo step)
  // The target's weights as colours (#P; 0 blue to 1 orange) while view.mask.painting; empty otherwise.
  const std::vector<glm::vec4>& mask_colors();

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
  // The corrective targets script exports ask for (the action export_correctives; the Export window has its
  // own fields): ExportOptions::max_targets (-1: the mode's default) and max_error.
  struct ExportCorrectives {
    int max_targets = -1;
    double max_error = 0.0;
    int max_influences = 4;  // baked-skin's fitted joints per vertex (the action export_influences)
    bool optimize = false;   // glb: reordered for the GPU (the action export_optimize)
    bool quantize = false;   // glb: KHR_mesh_quantization (the action export_quantize)
    bool pose_driven = false;  // baked-skin: pose-driven correctives (the action export_pose_driven)
    std::string hold_out;      // with pose_driven: a clip left out of the fits ("" none)
  } export_correctives;
  void cancel_export();
  const ExportState& export_state() const { return export_; }
  bool exporting() const { return export_.job != nullptr; }
  // A script's export line, "FORMAT MODE|- FPS all|CLIP[,CLIP] PATH", for this document.
  Result<ExportRequest> parse_export(std::istringstream& in) const;
  // An export line that could not be read: logged as an error and counted in failures.
  void refuse_export(const std::string& message);
  // Finishes background work that is done (the frame loop calls it every frame; tests too): an
  // automatic cage into the document, an export's report into the log, a parametric driver's binding
  // (and the change it was for); their errors shown. Starts the driver's bind when it is not bound.
  void poll_jobs();

  // ---- the parametric driver (workspace_patch.cpp; docs/parametric-drivers.md): a surface of
  // bicubic patches that drives the rest skin instead of the cage while "drive the skin" is on. The
  // Parametric driver window and the actions patch_* run these. Every change is one undo step; a
  // change that needs a new binding (import, fit, density) enters the document once its background
  // bind succeeds. The binding is the scene's (Scene::driver_binding). False (said why, the document
  // kept) when refused.
  struct PatchState {
    std::unique_ptr<BackgroundTask<Binding>> job;      // the bind under way (null: none)
    std::shared_ptr<const PatchDriver> job_driver;     // what it binds
    std::shared_ptr<const Character> job_character;    // whose rest skin
    std::string job_label;                             // the undo step it makes ("": the document's driver)
    std::vector<SetEdit> job_edits;                    // the driver's set edits it binds with
    std::shared_ptr<std::string> cache_note;           // the job's word on the project's cache ("" = none tried)
    bool nowait = false;                               // a script goes on while it binds
    std::shared_ptr<const PatchDriver> failed;         // the document's driver whose bind failed (not retried)
  };
  bool import_patch_driver(const std::string& path);   // .cwpatch or glTF
  bool export_patch_driver(const std::string& path);   // its posed control points
  bool fit_patch_driver();                             // to the selected cage faces (a rectangle of quads)
  bool set_patch_density(uint32_t density, bool nowait = false);
  bool select_patch_point(int point);                  // view.patch.point (-1: none)
  bool move_patch_point(const glm::dvec3& delta);      // the selected control point
  bool set_patch_drive(bool drive);
  bool reset_patch_driver();                           // the control points back to rest
  // The driver as a deformer of the stack (Document::driver_place, docs/deformer-stack.md), each one undo step:
  bool set_driver_after(int after, size_t i = 0);      // after that many layers (-1: after them all); driver i
  bool set_driver_mask(const std::string& source);     // "joints a,b,-c" or "primitives 0,2"; "" = no mask
  // Keys the driver's sculpt (posed minus rest control points) against the selected joint's rotation about
  // its local axis (0 X, 1 Y, 2 Z) at the current pose, in the driver's keypose set for it (made when
  // missing), and puts the control points back at rest: posed, the keyposes bring the sculpt back.
  bool key_driver_sculpt(int axis);
  bool remove_driver_keyset(size_t i);
  bool set_driver_params(std::optional<BindParams> params);  // its own binding parameters; null = the cage's
  // How the first driver's control points follow the skeleton (DriverPlacement::attachment): a mode (rigid,
  // smooth, skin_weights; null: each rigidly to its closest limb), and control points assigned to a joint
  // (node; nullopt: back to automatic). One undo step each, checked as the rig attaches it.
  bool set_driver_attachment(std::optional<AttachmentMode> mode);
  bool assign_driver_points(std::span<const uint32_t> points, std::optional<uint32_t> node);
  // More parametric drivers (Document::more_drivers; numbered as driver_at numbers them), each one undo step:
  bool add_driver(const std::string& path);            // a .cwpatch or glTF driver (the first, or one more)
  bool make_driver_first(size_t i);                    // the one the driver window and the patch_* actions edit
  bool set_driver_muted(size_t i, bool muted);
  bool set_driver_hidden(size_t i, bool hidden);  // its control net not drawn (saved with the project)
  bool set_driver_solo(std::optional<size_t> i);   // only driver i moves the skin (nullopt: no solo)
  // The first driver's contributing-set edits from a set edits file (per-point edits of its samples;
  // docs/edits-format.md), or none (""): one undo step; it binds again.
  bool set_driver_set_edits(const std::string& path);
  // The same picked in the view (app/workspace/workspace_driver_sets.cpp): `mode` (remove, add, only, reset)
  // with the picked samples (view.patch.picked) on the selected skin vertices; one undo step; it binds again.
  bool driver_set_edit(SetEditMode mode);
  // Picks the samples that drive the selected skin vertices (their contributing sets in the driver's binding).
  bool select_driver_set_samples();
  // The first driver's samples on its posed surface (#S, what the view draws and picks), cached per driver.
  const std::vector<glm::vec3>& driver_sample_points();
  // Per sample: 0 plain, 1 in the set of a selected skin vertex, 2 picked (what the view colours them by).
  std::vector<uint8_t> driver_sample_states() const;
  bool remove_driver(size_t i);
  void bind_patch_driver();                            // binds the document's driver again (after a failure)
  void cancel_patch_bind();
  // `from` with the selected control point moved by `total` (a drag rebuilds from its start).
  Document patch_point_moved(const Document& from, const glm::dvec3& total) const;
  // The selected control point while view.patch.editing (the move gizmo moves it instead of the cage).
  std::optional<glm::dvec3> patch_point_position() const;
  const PatchState& patch_state() const { return patch_; }
  bool binding_patch_driver() const { return patch_.job != nullptr; }

  // ---- fidelity to the file's skinning (workspace_fidelity.cpp; core/rig/fidelity.h): the current
  // frame's figures and heat map (view.fidelity.heat_map), and the check of every clip in the
  // background (the Properties window's Fidelity section, the view's warning, and the actions heatmap,
  // fidelity_check, fidelity_cancel, fidelity_frame).
  struct FidelityState {
    std::optional<FrameFidelity> frame;  // the current frame's figures (measure_fidelity), when measured
    std::vector<float> distance;         // #V its distance to the file's skinning / the diagonal
    std::vector<glm::vec4> colors;       // #V the heat map's colours (empty when it is off)
    std::unique_ptr<BackgroundTask<FidelityReport>> job;  // the check under way (null: none)
    bool nowait = false;                  // a script goes on while it runs
    std::optional<FidelityReport> report;  // the last finished check's
    std::string report_key;               // the rig it is of (rig_key(); stale when that changed)
    std::string outcome;                  // of the last check that gave no report: "cancelled" or why
    // what frame was measured for, and the skin's edges and heaviest joints (of `character`)
    std::string key;
    double measured_at = -1e9;
    std::vector<std::pair<uint32_t, uint32_t>> edges;
    std::vector<int32_t> joints;
    const Character* character = nullptr;
  };
  // Measures the current frame when it changed (pose, binding, attachment, document; while a clip
  // plays, at most 4 times a second); cheap when not. The frame loop calls it after update_pose.
  void measure_fidelity();
  // Checks every clip (`cagewrap check`) in the background, with the scene's binding when it is the
  // document's. False (said why) when one runs, or there is no cage or no skin.
  bool start_fidelity_check(bool nowait = false);
  void cancel_fidelity_check();
  const FidelityState& fidelity() const { return fidelity_; }
  bool checking_fidelity() const { return fidelity_.job != nullptr; }
  // Names the rig the figures are of: the document's revision, the binding's and the attachment's.
  std::string rig_key() const;
  std::string joint_name(int32_t joint) const;  // "-" for none

  // ---- project storage (workspace_project.cpp; the File menu and the actions embed, cache_binding):
  // one undo step each, saved with the project; false (said why, the document kept) when refused.
  // The character file kept inside the project (it then opens with no other file).
  bool embed_character();
  // The embedded character written out to `path` and named by the project again; "" = back to the
  // file it came from, which must still hold the same bytes (else where_to_unembed says where to ask).
  bool unembed_character(const std::string& path = "");
  struct CharacterFileAsk {
    std::string name, directory;  // a file name and folder to propose
  };
  // Where to ask for the embedded character's new file, or none: the file it came from still holds it.
  std::optional<CharacterFileAsk> where_to_unembed() const;
  // The binding saved beside the project (<project>.cwb), so that opening it needs no bind.
  bool set_cache_binding(bool cache);
  // The nearest existing folder above `path`, else `fallback`'s (where a file browser starts).
  static std::string browse_folder_near(const std::string& path, const std::string& fallback);

  // ---- the deformer stack (workspace_stack.cpp, issue 21; the outliner's Deformers and the deformer_*
  // actions): deformer 0 is the document's own cage, k the layer k - 1. Every change but the active
  // deformer is one undo step; false (said why, the document kept) when refused.
  bool set_active_deformer(size_t d);  // what the tools, sets, keyposes and Rebind act on
  // Layer d's skin mask from its description (core/character/skin_mask.h skin_mask_from_source: "joints a,b,-c",
  // "primitives 0,2"; "" = none): one undo step; false (said why) when it cannot be made.
  bool set_deformer_mask(size_t d, const std::string& source);
  bool add_deformer(const std::string& cage_path, std::string name = "");  // a layer at the end
  bool remove_deformer(size_t d);                                          // a layer (d >= 1)
  bool set_deformer_muted(size_t d, bool muted);
  bool set_deformer_hidden(size_t d, bool hidden);
  bool set_deformer_solo(long d);  // -1: none
  bool move_deformer(size_t d, size_t to);  // layers only: 1 .. layers
  bool set_stack_mode(StackMode mode, double exponent);
  bool rename_deformer(size_t d, const std::string& name);
  // Whether a bind runs: the active deformer's or another's (a script waits for both).
  bool binding_any() const;

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
  void add_stack_actions();  // workspace_stack.cpp
  bool change_stack(const std::string& label, Document next);
  bool set_deformer_switch(size_t d, bool on, bool DeformerStack::*base, bool DeformerLayer::*layer, const std::string& label);
  // A cage file loaded, checked and made into a cage; none (said why) when it cannot be.
  std::optional<Cage> read_cage(const std::string& path);
  bool check_deformer(size_t d, bool layer_only);
  bool check_driver(size_t i);  // a parametric driver of the document (else said)
  // Driver i's placement replaced as one undo step labelled `label` (logged); false when nothing changed.
  bool apply_driver_place(size_t i, const std::string& label, DriverPlacement place);
  // Logs "error: <where the running action came from>: text".
  void fail(const std::string& text);
  // An action's on|off argument into `flag`; anything else fails naming `action` ("ACTION on|off").
  void read_on_off(std::istringstream& in, const char* action, bool& flag);
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
  struct MaskStroke {
    SkinBrush brush;
    MaskTarget target;
    std::vector<float> weights;  // #P, the stroke's mask so far
    bool changed = false;
  };
  std::optional<MaskStroke> mask_stroke_;
  std::vector<glm::vec4> mask_colors_;
  // `w` with the target's mask replaced (mask_source "": painted).
  static Document with_target_mask(const Document& w, const MaskTarget& t, std::shared_ptr<const std::vector<float>> mask);
  const std::shared_ptr<const std::vector<float>>& target_mask(const Document& w, const MaskTarget& t) const;
  // X-mirror maps of the skin points and the cage faces, for the cage they were made for
  struct SetMirrorMaps {
    std::shared_ptr<const Cage> cage;
    size_t skin_points = 0;
    MirrorMap points, faces;
    SetEditMirror maps;  // points at the two above
  };
  std::optional<SetMirrorMaps> set_mirror_;
  struct SamplePoints {
    std::shared_ptr<const PatchDriver> driver;  // what `points` were made for
    std::vector<glm::vec3> points;
  } sample_points_;
  const SetEditMirror& set_edit_mirror();
  void clip_cage_selection();  // drops selected cage vertex and face ids past the cage's counts
  bool commit_sim(SimSettings sim, const std::string& label);
  ExportState export_;
  AutoCageState auto_cage_;
  PatchState patch_;
  FidelityState fidelity_;
  void poll_fidelity();
  void reset_fidelity();  // another document: a running check is cancelled, what was measured dropped
  void poll_patch();
  // A mask made from `source` into `mask` and `mask_source` ("" = none); false (failed, naming `what`) when it cannot be made.
  bool make_mask(const Document& w, const std::string& source, std::shared_ptr<const std::vector<float>>& mask, std::string& mask_source,
                 const std::string& what);
  void start_patch_bind(std::shared_ptr<const PatchDriver> driver, std::string label);
  void new_patch_driver(PatchSurface rest, const std::string& label);
  bool change_patch_driver(const std::function<void(PatchDriver&)>& change, const std::string& label);
  void poll_auto_cage();
  void poll_export();
};

}  // namespace cagewrap::app
