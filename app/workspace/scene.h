// What the editor shows and animates: the character, its cage, the binding, and the pose of the
// current frame. No GL or ImGui here: the viewport draws from it, panels edit it.
#pragma once

#include <atomic>
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <glm/gtc/quaternion.hpp>

#include "app/workspace/background_task.h"
#include "core/character/animation.h"
#include "core/cage/cage.h"
#include "core/cage/cage_attachment.h"
#include "core/character/character.h"
#include "core/rig/clip_sim.h"
#include "core/deform/deformer.h"
#include "core/deform/patch_binding.h"
#include "core/document/binding_cache.h"
#include "core/document/document.h"
#include "core/document/project_io.h"
#include "app/workspace/history.h"
#include "core/deform/registration.h"
#include "core/rig/deformer_stack.h"
#include "core/rig/driver_layer.h"
#include "core/rig/rig.h"
#include "core/character/skeleton.h"
#include "app/workspace/soft_selection.h"
#include "app/workspace/view_state.h"

namespace cagewrap::app {

// A bind running on a worker thread, with progress and cancel; the UI polls it every frame.
using BindJob = BackgroundTask<Binding>;
// A background bind's progress and Cancel, as the core binds take them.
BindProgress job_progress(const BindJob::Progress& progress, const std::atomic<bool>& cancel);
// The default rig's fit of a bind (core/deform/attachment_fit.h fit_rig: the fitted attachment and the
// smoothed stencil), made on the bind's worker thread so that the UI does not wait for it.
struct RigFit {
  CageAttachment attachment;        // `transferred` fitted
  std::optional<Binding> smoothed;  // the stencil the deformer reads, or none: the registration
  CageAttachment transferred;       // what it was fitted from (it applies to this attachment only)
};
// What a bind job fits after binding: the transferred attachment, when the document's attachment is
// fitted; the result goes to `out`.
struct FitRequest {
  std::optional<CageAttachment> transferred;
  std::shared_ptr<std::optional<RigFit>> out;
};
// Binds the document's skin to its cage (parameters, set edits, automatic separation by the
// attachment's skeleton parts: core/rig/rig.h bind_document), then fits the rig (`fit`).
// With `cache`: the bind goes through its candidate cache (core/rig/rig.h bind_document_cached; the
// same result), made first when `make_cache` (a parameter drag). The job owns `cache` while it runs.
std::unique_ptr<BindJob> start_bind_job(std::vector<glm::vec3> skin, Document doc, std::optional<CageAttachment> attachment,
                                        FitRequest fit = {}, std::shared_ptr<CandidateCacheSlot> cache = nullptr,
                                        bool make_cache = false);
// The document's rest cage moved, or its topology changed, since `previous` was bound (core/rig/rig.h
// rebind_document; `previous_edits`: the set edits it was bound with): only the skin points within
// reach of the moved vertices or changed elements are registered again; `report` is filled when it
// ends; then the rig is fitted (`fit`).
std::unique_ptr<BindJob> start_rest_edit_job(std::vector<glm::vec3> skin, Document doc,
                                             std::optional<CageAttachment> attachment, Binding previous,
                                             std::optional<CageAttachment> previous_attachment,
                                             std::shared_ptr<RestRebindReport> report, FitRequest fit = {},
                                             std::vector<SetEdit> previous_edits = {});

// A deformer of the stack other than the active one (issue 21): a rig of its own, bound in the
// background, posed every frame and combined with the active deformer's skin.
using StackRigJob = BackgroundTask<Rig>;
struct StackRig {
  size_t deformer = 0;            // its number in the stack (0 = the document's cage, k = layer k - 1)
  Document doc;                   // deformer_document of the whole document as it is now
  BindingInputs inputs;           // what its rig was (or is being) made from
  std::unique_ptr<Rig> rig;       // null while binding or after a failure
  uint64_t revision = 0;          // changes (to a value never used before) whenever `rig` is made: the GPU follows
  std::unique_ptr<StackRigJob> job;
  // What the job did with the deformer's binding cache, written by the job before it ends: "" (none
  // recorded), "used: FILE" or "not used: why"
  std::shared_ptr<std::string> cache_note = std::make_shared<std::string>();
  std::string error;              // why it has no rig ("" = none)
  std::vector<glm::vec3> skin;    // its posed skin of the current frame (with skin_on_gpu: made only when asked)
  PosedCage cage;                 // its posed cage of the current frame
};

// A parametric driver beyond the first (Document::more_drivers; issue 21): bound in the background like
// the stack's rigs, its displacement added where it sits in the stack (on the CPU, like the first's).
using DriverRigJob = BackgroundTask<DriverLayer>;
struct DriverRig {
  size_t index = 0;                           // which of the document's drivers (driver_at; >= 1)
  std::shared_ptr<const PatchDriver> driver;  // what it was (or is being) bound for
  BindParams params;                          // and with
  std::vector<SetEdit> edits;                 // and its set edits
  std::shared_ptr<const Character> character; // and for
  std::string name;                           // for messages
  std::unique_ptr<DriverLayer> layer;         // null while binding or after a failure
  std::shared_ptr<std::string> cache_note;  // the job's word on the project's cache ("used: F", "not used: why")
  std::unique_ptr<DriverRigJob> job;
  std::string error;                          // why it has no layer ("" = none)
  std::vector<glm::vec3> delta;               // its displacement of the current frame (#P)
};

// The deformers that make a frame's skin on the GPU (Scene::gpu_frame; app/skin_display.h deforms and
// combines them there, render/gpu_deformer.h GpuStack).
struct GpuFrame {
  struct Deformed {
    size_t index = 0;                    // its number in the stack (0 = the document's cage)
    const Deformer* deformer = nullptr;  // with the maps of this frame's posed cage (Deformer::update_maps)
    uint64_t revision = 0;               // changes whenever the deformer is made again or its table changes
    std::shared_ptr<const std::vector<float>> mask;  // #P, or null: 1 everywhere
    // Non-empty (#P): a parametric driver's displacement of this frame, made on the CPU (no deformer).
    std::span<const glm::vec3> displacement;
  };
  // The skin the others combine over: deformer 0's, or none (muted, or it has no cage): the rest skin.
  // While the other deformers bind, the active deformer's alone (whichever it is), with no layers.
  std::optional<Deformed> base;
  std::vector<Deformed> layers;  // the other deformers that move the skin, and the drivers' displacements, in stack order
  DeformerStack stack;           // how they combine (the whole document's)
  bool built = false;            // update_pose built the maps: the GPU makes this frame's skin
};

struct Scene {
  explicit Scene(Document doc) : history_(std::move(doc)) {}
  // During a drag: the document being edited (history holds its start), as the active deformer sees it.
  std::optional<Document> live;
  // The document as the active deformer sees it (deformer_document, with the document-wide fields:
  // the character, the parametric driver, the project's storage): what the tools, panels and the
  // binding below act on. With one deformer (or the document's own cage active) it is the document.
  const Document& doc() const { return live ? *live : view(); }
  // The whole document (every deformer): what is saved, exported, checked and autosaved.
  const Document& work() const;

  // ---- Several deformers (issue 21, docs/deformer-stack.md)
  size_t active_deformer() const { return active_; }
  // Makes deformer `d` the one edited (not an undo step): its binding is taken from its stack rig when
  // that is ready, else bound in the background. False when there is no such deformer or a drag is open.
  bool set_active_deformer(size_t d);
  // The other deformers that move the skin (not muted), each with its rig or its bind.
  std::vector<StackRig> stack_rigs;
  // Whether the skin shown is a stack's (another deformer moves it, or the active one is muted) or has the
  // parametric driver's sculpt. A stack of cages is deformed and combined on the GPU with skin_on_gpu
  // (gpu_frame); the driver's sculpt is added on the CPU, so a driven skin is made there.
  bool stacked() const { return cage_stack() || any_driving(); }
  bool cage_stack() const;  // more than the active cage moves the skin
  // Whether every other deformer's rig is ready (else the active deformer's skin is shown alone).
  bool stack_ready() const { return stack_ready_; }
  // Each deformer's binding when it is ready and is that of the document as it is (index = deformer; null
  // = none: binding, failed or muted): what a save caches beside the project.
  std::vector<const Binding*> deformer_bindings() const;
  // The same for each parametric driver (index = driver_at's number): the first's driver_binding, the others'
  // rigs, each when it is the binding of that driver as the document has it.
  std::vector<const Binding*> driver_bindings() const;
  // While a mask brush stroke is under way (app/workspace/workspace_mask.cpp): the whole document with the
  // stroke's mask, which the frame's stack combines with (the stroke becomes one undo step when it ends);
  // null otherwise. stack_document() is the one the frame combines with.
  std::optional<Document> mask_preview;
  const Document& stack_document() const { return mask_preview ? *mask_preview : history_.current(); }
  // The parametric drivers beyond the first that move the skin, each with its layer or its bind.
  std::vector<DriverRig> driver_rigs;
  // Polls the stack rigs' and the drivers' binds; a message per bind that ended.
  std::vector<std::string> poll_stack();
  void cancel_stack_binds();
  // Binds again the other deformers whose bind failed or was cancelled.
  void retry_stack_binds();

  // ---- Changing the document: the only place that records undo steps and refreshes what derives
  // from the document (attachment, binding, deformer). Panels and tools change it only through these.
  // One edit, one undo step ("Move cage vertices"); then everything derived is brought up to date
  // (document_changed). False when `next` is the current document (nothing recorded).
  bool apply(std::string label, Document next);
  // The same for a change of the whole document (work(): the deformer stack's settings, a layer added).
  bool apply_work(std::string label, Document next);
  // The same for a set edit of `points`: re-registers only those points when it can
  // (update_set_edits_live), else rebinds.
  bool apply_set_edits(std::string label, Document next, std::span<const uint32_t> points);
  // A drag (gizmo, brush stroke, slider): begin_drag remembers the document before it; `live` holds
  // the document while it changes (drag); commit_drag makes the whole drag one undo step (false when
  // it changed nothing) and cancel_drag restores the start. `refresh`: call document_changed after.
  void begin_drag();
  void drag(Document next) { live = std::move(next); }
  bool dragging() const { return history_.dragging(); }
  // The document the open drag started from, as the active deformer sees it; null when not dragging.
  const Document* drag_start() const { return history_.dragging() && drag_view_ ? &*drag_view_ : nullptr; }
  bool commit_drag(std::string label, bool refresh = true);
  void cancel_drag();
  // Undo and redo one step; return the step's label ("" when there was none).
  std::string undo();
  std::string redo();
  // The undo steps (read-only: labels, dirty state, memory).
  const History& history() const { return history_; }
  // The document was written to `path` (the save point) / came from a recovery file (dirty until saved).
  void mark_saved(const std::string& path) { history_.mark_saved(path); }
  void mark_unsaved() { history_.mark_unsaved(); }
  bool dirty() const { return history_.dirty(work()); }

  std::vector<glm::vec3> skin_rest;  // #V bind pose, every primitive in file order
  double skin_diagonal = 1.0;        // of skin_rest's bounding box (grid, tolerances; never 0)
  PolyMesh skin_topology;            // combined triangles
  std::optional<CageAttachment> attachment;
  BindParams params;                 // as edited in the panel (committed to the document on release)
  std::unique_ptr<Binding> binding;  // the registration in use
  std::shared_ptr<const Cage> bound_cage;  // the rest cage it was made from
  std::optional<Deformer> deformer;
  std::unique_ptr<BindJob> job;

  // the current frame (update_pose: the workspace's Playback, app/workspace/view_state.h)
  std::vector<glm::vec3> cage_posed, joint_heads;
  std::vector<glm::mat4> joint_globals;  // #nodes world transforms of the current pose
  std::vector<glm::dmat3> cage_linear;
  std::vector<glm::mat4> cage_skinning;  // skinning matrix of each cage vertex (blended when smooth)
  PosedCage posed;  // the whole posing result (core/rig/rig.h): keypose offsets, driver at rest, ...
  std::vector<std::array<uint32_t, 2>> bones;
  double deform_ms = 0.0;
  bool skin_from_cage = false;  // false: the file's own linear blend skinning is shown
  // Set by the editor when the skin is deformed on the GPU (app/skin_display.h): update_pose then
  // only builds each deformer's per-change maps (Deformer::update_maps; with a stack, every deformer
  // that moves the skin, its cage posed) for the GPU kernels (gpu_frame), and the CPU copy of the skin
  // is made only when something asks for it (skin_posed()). Not while the parametric driver drives
  // the skin (driving()): its sculpt is added on the CPU.
  bool skin_on_gpu = false;
  // The deformers whose maps update_pose built for the GPU this frame (skin_on_gpu and the skin from
  // the cage; otherwise no base and no layers). While the other deformers bind, the active one alone,
  // as the CPU path shows it.
  const GpuFrame& gpu_frame() const { return gpu_frame_; }
  // Changes (to a value never used before, by any scene) whenever `deformer` is replaced or its
  // table changes in place, so a GPU copy of the table knows to follow.
  uint64_t binding_revision = 0;
  // The parametric driver's binding (derived from the document like `binding` is for the cage): made
  // by the workspace's background bind (app/workspace/workspace_patch.cpp) for `driver`'s rest grids
  // and density and `character`'s rest skin; `layer` adds the driver's sculpt, carried by the skeleton,
  // to the frame's skin (core/rig/driver_layer.h, as Rig does for pose and the exports).
  struct DriverBinding {
    std::unique_ptr<Binding> binding;
    std::unique_ptr<PatchDeformer> deformer;
    std::unique_ptr<DriverLayer> layer;  // null when the driver cannot follow the skeleton (no skin)
    std::shared_ptr<const PatchDriver> driver;
    std::shared_ptr<const Character> character;
    std::vector<SetEdit> edits;  // the driver's set edits it was bound with
  } driver_binding;
  // Whether driver_binding serves the document's driver (same rest grids and density) and skin.
  bool driver_bound() const;
  // Whether the document's driver drives the skin and is bound: update_pose adds its sculpt.
  bool driving() const;
  // The same for any of the document's drivers (the first, or one of driver_rigs): the skin is made on the CPU.
  bool any_driving() const;
  // Whether this frame's skin has the driver's sculpt (set by update_pose).
  bool skin_driven() const { return skin_driven_; }
  // The deformed skin of the current frame (#V, the order of skin_rest), for picking, brushes and
  // the skin points; with skin_on_gpu it is deformed on the CPU here, at the first call per frame.
  const std::vector<glm::vec3>& skin_posed();
  // The skin's triangles (skin_topology, whose faces are all triangles).
  std::span<const Tri> skin_triangles() const;

  // The cage simulation (core/rig/clip_sim.h) of the current clip, when the document has it on: its
  // frames are filled a little each UI frame (fill_simulation) and update_pose shows them once the
  // frames around the player's time are there (the plain skinned cage until then).
  SimCache sim_cache;
  bool sim_shown = false;  // this frame's cage has the simulation applied
  std::string sim_error;   // why the simulation cannot run ("" = it can, or it is off)
  // The simulation of `clip` (made when needed), or null when it is off, `clip` is -1 (the bind pose) or
  // the settings are invalid (sim_error says why).
  ClipSimulation* simulation(int32_t clip);
  // Simulates more frames of `clip` for up to budget_ms of wall time (0: all of them).
  void fill_simulation(int32_t clip, double budget_ms);

  bool needs_rebind() const;
  // The registration for the document as it is, for a background job's rig of its own (an export, a
  // fidelity check: core/rig/rig.h Rig::create with a binding), or null when there is none: the jobs
  // then bind themselves.
  std::shared_ptr<const Binding> binding_for_jobs() const;
  // The deformer made again from the current binding, whenever it changes (a bind ends, a cached one
  // is adopted, a live set edit): with a fitted attachment, the rig's fit (core/deform/attachment_fit.h
  // fit_rig, as Rig and `cagewrap pose` make it: the attachment fitted from the transferred weights
  // and the stencil smoothed where the rig would stretch the skin) goes into `rig_binding`, which
  // the deformer reads when the fit smoothed the stencil; `binding` stays the registration (sets,
  // live edits, rest edits, the cache).
  // `fit` (optional): the fit a bind job made for the current binding, taken instead of fitting
  // here when it was made from the current transferred attachment.
  Status make_deformer(RigFit* fit = nullptr);
  bool fits_attachment() const;  // a fitted attachment for the current binding (make_deformer fits it)
  std::unique_ptr<Binding> rig_binding;  // the smoothed stencil `deformer` reads, or null: `binding`
  uint64_t attachment_revision = 0;  // changes whenever `attachment` is made or fitted again
  // Takes a binding made earlier for the document as it is (a project's cache: the caller checked
  // binding_fits), as a finished bind would; call before document_changed so that none starts.
  void adopt_binding(Binding binding);
  // Call after the document changed (undo, redo, load): re-attaches and rebinds what it must.
  void document_changed();
  // The pose `playback` shows: its clip at the player's time (the rest pose without a clip) and the overrides.
  Pose current_pose(const Playback& playback) const;
  // Poses skeleton and cage as `playback` says and deforms the skin (the file's own skinning when
  // playback.show_file_skinning).
  void update_pose(const Playback& playback);
  const Pose& shown_pose() const { return pose_; }  // the pose of the last update_pose
  void start_bind();
  // The panel's Rebind: its parameters become the document's (one undo step, saved with the
  // project) when they differ, then the skin binds again.
  void rebind();
  // Live binding parameters (issue 24): while a binding slider is dragged on a skin of at most
  // kLiveBindPoints points, drag_params() (each frame of the drag) binds the skin with the panel's
  // parameters as they are, in the background, again as soon as the previous bind ends, so the skin
  // follows the slider; commit_params() (on release) makes them the document's: one undo step per drag.
  // The first bind of a drag makes a candidate cache (core/deform/registration.h CandidateCache), the
  // next ones re-weight from it: the same result as a fresh bind, several times faster.
  static constexpr size_t kLiveBindPoints = 200000;
  bool live_params_possible() const { return doc().cage && skin_rest.size() <= kLiveBindPoints; }
  void drag_params();
  void commit_params();
  bool live_params = false;  // a drag is on
  // The drags' candidate cache and what the last bind did with it (read it while no job runs).
  const CandidateCacheSlot& candidate_cache() const { return *candidate_cache_; }
  // Set edits changed for `points` only (a brush dab, an applied edit): re-registers just those points
  // in the current binding (core/deform/registration.h Rebinder) so the skin updates at once; the caller
  // has put `edits` into the document (live or committed). False (nothing done) when there is no
  // current binding for this cage; a full rebind then follows as usual.
  bool update_set_edits_live(const std::vector<SetEdit>& edits, std::span<const uint32_t> points);
  // Polls the running job; returns a message when it finished (bound, failed or cancelled).
  std::optional<std::string> poll_bind();
  // Moves cage vertices of the driver by a world-space displacement at the current pose, each by its
  // share (soft selection, X-mirror: app/workspace/soft_selection.h), stored as offsets in each vertex's joint
  // bind space, and returns the new document (not yet in history).
  Document moved(const Document& from, const MoveWeights& weights, const glm::dvec3& world_delta) const;
  // The same move applied to the reference (rest) cage instead: the skin stays where it is and, once
  // committed (document_changed), only the skin points the moved vertices can reach are registered
  // again. A distance scale of 0 (h from the mean edge length, which any move changes) is fixed to
  // the bound h in the same document, so the edit stays local.
  Document moved_rest(const Document& from, const MoveWeights& weights, const glm::dvec3& world_delta) const;
  // `d` with a distance scale of 0 fixed to the bound h, when it is bound with these parameters (rest
  // and local topology edits: the mean edge length they change would change every weight).
  Document keep_bound_scale(Document d) const;

 private:
  History history_;  // the document and its undo steps
  size_t active_ = 0;  // the active deformer
  mutable std::optional<Document> view_;       // doc() for a layer: made when the document or active_ changes
  mutable uint64_t view_of_ = 0;               // the revision of the document view_ was made from
  mutable std::optional<Document> work_live_;  // work() during a drag
  std::optional<Document> drag_view_;          // doc() when the drag began
  const Document& view() const;
  // `next` (a document as the active deformer sees it, made from doc()) back into the whole document `base`.
  Document to_work(const Document& next, const Document& base) const;
  void update_attachment();
  void switch_active(size_t d);
  struct HandedOver {  // the registration of the deformer that stopped being active, for its stack rig
    size_t deformer;
    Binding binding;
  };
  std::optional<HandedOver> handed_over_;
  void update_stack_rigs();
  void update_driver_rigs();
  // Poses every other deformer's cage; on the CPU (maps_only false) deforms its skin and combines the
  // stack, with `drivers` (the parametric drivers' displacements) at their places, into skin_posed_
  // (core/rig/deformer_stack.h combine_document_stack); on the GPU (maps_only) builds its maps and fills
  // gpu_frame_ (no driver there: a driven skin is made on the CPU).
  void pose_stack(const Playback& pb, bool maps_only, std::span<const DriverTerm> drivers);
  // The other deformers' skins (stack_rigs' `skin`) combined with the active one's (skin_posed_) and the
  // drivers' displacements into skin_posed_; false (skin_posed_ unchanged) when the stack cannot combine them.
  bool combine_skins(std::span<const DriverTerm> drivers);
  // The CPU copy of a stack the GPU made: each other deformer's skin deformed from its cage posed this
  // frame, then combined with the active one's (in skin_posed_) and `drivers`. False when one fails.
  bool combine_stack_on_cpu(std::span<const DriverTerm> drivers);
  GpuFrame gpu_frame_;
  bool stack_combined_ = false;  // this frame's skin is the stack's (not the active deformer's alone)
  // The parametric drivers' displacements at this frame (their sculpts and keyposes, carried by the
  // skeleton): the first's into driver_delta_, the others' into their rigs' `delta`; those that add
  // something (a sculpt, and no failure) as terms.
  std::vector<DriverTerm> driver_displacements();
  // skin_posed_ += each driver's mask * its displacement (the stack's other deformers not ready, or no binding yet).
  void add_drivers_alone(std::span<const DriverTerm> drivers);
  std::vector<glm::vec3> driver_delta_;  // #P
  bool stack_ready_ = true;
  std::shared_ptr<const Cage> pending_cage_;   // the cage the running job binds
  std::vector<SetEdit> pending_edits_, bound_edits_;  // the set edits of the running job / the binding
  std::optional<CageAttachment> pending_attachment_data_, bound_attachment_data_;  // the attachment they used
  std::shared_ptr<RestRebindReport> pending_rest_report_;  // set when the running job is a rest edit
  std::shared_ptr<std::optional<RigFit>> pending_fit_;     // the running job's fit, when it makes one
  // whether the running job may re-register only some points (same elements, parameters, edits)
  bool rest_edit_possible() const;
  void add_move(std::vector<glm::vec3>& values, const MoveWeights& weights, const glm::dvec3& world_delta) const;
  std::unique_ptr<Rebinder> rebinder_;  // for live set edits, made for the current binding
  // the candidate cache of parameter drags (made by the first bind of a drag, kept for the next drags
  // while skin, cage and labels stay; only bind jobs touch it, one at a time)
  std::shared_ptr<CandidateCacheSlot> candidate_cache_ = std::make_shared<CandidateCacheSlot>();
  const Binding* rebinder_for_ = nullptr;
  Pose pose_;                          // the pose of the current frame (update_pose)
  std::vector<glm::vec3> skin_posed_;  // see skin_posed()
  bool skin_stale_ = false;            // the GPU has this frame's skin; skin_posed_ is older
  bool skin_driven_ = false;           // this frame has the driver's sculpt
  AttachmentSettings pending_attachment_, bound_attachment_;
  std::shared_ptr<const Cage> attached_cage_;  // the cage `attachment` was made for
  AttachmentSettings attached_settings_;       // and the settings it was made with
  std::optional<CageAttachment> transferred_;  // `attachment` as attach_cage made it (before any fit)
};

// Loads a character file (glTF, FBX, Collada, ...: core/io/gltf_loader.h) and optionally a cage; errors name the file.
Result<std::unique_ptr<Scene>> load_scene(const std::string& character_path, const std::string& cage_path,
                                          const CharacterLoadOptions& load = {});
// What opening a project reports beside its scene.
struct ProjectOpen {
  std::vector<std::string> warnings;  // each to log as a warning
  std::vector<std::string> notes;     // to log as they are (the cached binding used)
  std::string missing_character;      // the character file looked for, when it was not found
  std::optional<RecoveryInfo> recovery;  // the file was an editor recovery file (app/workspace/autosave.h)
};
// Opens a saved project (.cagewrap), with `character_override` for a character that moved
// (core/document/project_io.h load_project). Uses the project's cached binding when it is still valid
// (core/document/binding_cache.h), else binds in the background and says why in the warnings.
Result<std::unique_ptr<Scene>> load_project_scene(const std::string& project_path, ProjectOpen& out,
                                                  const std::string& character_override = {});
// The demo character shipped in assets/ (found beside the executable or the source tree), or
// generated in-process when the file cannot be found.
std::string demo_character_path();
// The cage made for it by `cagewrap cage` (assets/demo_cage.obj beside the character), or "".
std::string demo_cage_path(const std::string& character_path);

}  // namespace cagewrap::app
