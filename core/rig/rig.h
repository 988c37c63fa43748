// Posing a document: the one path from a skeleton pose to a posed cage and a deformed skin,
// shared by the editor (app/workspace/scene.cpp) and `cagewrap pose`.
//
//   keypose_v = evaluate_keyposes(doc.keyposes, skeleton, pose)            (bind space)
//   driver_rest_v = rest_v + doc.cage_offsets[v] + keypose_v                (bind space)
//   M_v = sum_i w_i * skinning[joint_i]    (core/cage/cage_attachment.h; one joint when rigid)
//   D_v = M_v * driver_rest_v, linear_v = 3x3 of M_v
//   skin = Deformer::deform(D, linear for the extended variant)
// Without an attachment (a character with no skin) the driver stays at driver_rest.
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "core/cage/cage_attachment.h"
#include "core/deform/deformer.h"
#include "core/document/document.h"
#include "core/deform/registration.h"
#include "core/deform/rest_edit.h"

namespace cagewrap {

// The pose of clip `clip` (-1: the rest pose) at time t (clamped, or wrapped when `loop`) with
// per-node rotation overrides on top: local rotation = clip rotation * overrides[node] (#N or
// fewer; missing entries are the identity).
Pose compose_pose(const Character& character, int32_t clip, double t, bool loop,
                  std::span<const glm::quat> overrides = {});

// A rotation from angles in degrees about the joint's local X, then Y, then Z (q = Rz * Ry * Rx),
// as `cagewrap pose --pose node=rx,ry,rz` takes them.
glm::quat rotation_xyz_degrees(double rx, double ry, double rz);

struct PosedCage {
  std::vector<glm::mat4> globals;          // #N world transform of every skeleton node
  std::vector<glm::vec3> keypose_offsets;  // #Vc the keyposes' offsets at this pose (bind space)
  std::vector<glm::vec3> driver_rest;      // #Vc rest + cage offsets + keypose offsets
  std::vector<glm::vec3> positions;        // #Vc the posed driver cage D
  std::vector<glm::dmat3> linear;          // #Vc linear part of each vertex's manipulation
  std::vector<glm::mat4> skinning;         // #Vc each vertex's (blended) skinning matrix
  bool attached = false;                   // false: no attachment, positions = driver_rest
};

// Poses the document's cage (it must have one: checked). `attachment` may be null (no skin). The
// vectors of `out` are resized, so a PosedCage reused frame to frame does not allocate.
void pose_document_cage(const Document& doc, const CageAttachment* attachment, const Pose& pose,
                        PosedCage& out);

// Deforms the skin through a posed cage: the extended variant takes the vertices' linear parts when
// the cage was posed by an attachment (otherwise it fits them from the one-rings).
Status deform_through_cage(Deformer& deformer, const PosedCage& cage, std::span<glm::vec3> skin_out);
// The vertex frames deform_through_cage hands the deformer: the cage's linear parts for the
// extended variant of an attached cage, else none (fitted from the one-rings).
std::span<const glm::dmat3> cage_vertex_frames(const Binding& binding, const PosedCage& cage);

// Binds a document's skin (every primitive concatenated) to its cage with its parameters and set
// edits; with automatic separation on and an attachment, the skeleton-part labels of
// core/deform/part_labels.h keep unrelated parts apart. The one bind the editor, the CLI and export share.
Result<Binding> bind_document(const Document& doc, std::span<const glm::vec3> skin_rest, const CageAttachment* attachment,
                              const BindProgress& progress = {});

// A candidate cache (core/deform/registration.h CandidateCache) kept between binds of one document
// whose binding parameters are being dragged, and what the last bind through it did.
struct CandidateCacheSlot {
  std::shared_ptr<const CandidateCache> cache;
  bool last_from_cache = false;  // the last bind re-weighted from the cache
  double made_seconds = -1;      // the last bind made the cache (its time), else -1
};
// bind_document through `slot`'s candidate cache: the same result bit for bit. When the cache does
// not fit the document's skin, cage and part labels, `make` makes it first (a parameter drag: the
// next binds re-weight from it), else it is dropped and the bind is bind_document's.
Result<Binding> bind_document_cached(const Document& doc, std::span<const glm::vec3> skin_rest, const CageAttachment* attachment,
                                     CandidateCacheSlot& slot, bool make, const BindProgress& progress = {});

// bind_document for a document whose rest cage moved (same cage elements, parameters and set edits)
// since `previous` was bound with `previous_attachment`: only the skin points the moved vertices can
// reach are registered again (core/deform/rest_edit.h), with the same result bit for bit. The same for a
// cage whose topology changed (core/document/topology_change.h edits; rest_edit.h rebind_new_topology:
// the points out of reach of every removed and added element keep their rows; `previous_edits`, the
// set edits `previous` was made with, null: the document's). Anything else (other parameters, a
// binding read from a file, a scale of 0, other skin labels, reordered elements) binds in full.
// `report` (may be null): moved vertices and points registered (every point after a full bind).
// Whether a binding made with `bound` (its distance scale came out as `h`) can follow a rest edit to
// parameters `now`: the same parameters, `now` giving a scale, and a bound scale of 0 counting as h.
bool rest_edit_params_fit(const BindParams& bound, double h, const BindParams& now);
Result<Binding> rebind_document(const Document& doc, std::span<const glm::vec3> skin_rest, const CageAttachment* attachment,
                                Binding previous, const CageAttachment* previous_attachment,
                                const BindProgress& progress = {}, RestRebindReport* report = nullptr,
                                const std::vector<SetEdit>* previous_edits = nullptr);

// Everything a document needs to be posed again and again: the attachment of its cage, the binding
// of its skin (every primitive concatenated, as skin_character orders them) and the deformer.
// Bind once, pose many. Made for one cage, binding parameters and attachment settings; `pose`
// takes any document that has the same (its cage offsets and keyposes may differ: a document
// being edited).
class Rig {
 public:
  // Fails when the document has no cage, the attachment fails (an override naming a non-joint) or
  // the bind fails; the message says which. A character without a skin gets no attachment.
  static Result<Rig> create(const Document& doc, const BindProgress& progress = {});
  // The same with a binding made earlier for this document (a project's cache, core/document/binding_cache.h:
  // the caller has checked that it fits): no bind.
  static Result<Rig> create(const Document& doc, Binding binding);
  // The same with bindings made earlier for some of the stack's deformers (index = deformer: 0 the
  // document's cage, k layer k - 1; core/document/binding_cache.h load_stack_binding_caches, which checks
  // that they fit): those are not bound again, the others are.
  // `driver_bindings`: the same for the parametric drivers (index = driver_at's number; load_stack_binding_caches'
  // drivers, checked there): those are not bound again.
  static Result<Rig> create(const Document& doc, std::vector<std::optional<Binding>> bindings,
                            const BindProgress& progress = {}, std::vector<std::optional<Binding>> driver_bindings = {});

  // Whether `doc` has this rig's cage (same object or same content), parameters and attachment.
  bool fits(const Document& doc) const;
  // Poses `doc` (fits(doc) must hold: checked): the posed cage into `cage`, the skin into
  // skin_out (#P, num_skin_points()).
  Status pose(const Document& doc, const Pose& pose, PosedCage& cage, std::span<glm::vec3> skin_out);
  // The same at time t of clip `clip` (-1: the rest pose; t clamped to the clip) with per-node
  // rotation overrides (compose_pose), and, when doc.sim is enabled and a clip plays, the cage's
  // simulation applied (core/rig/clip_sim.h: the rig caches each clip's simulated frames). Fails with
  // the simulation's message when its settings are invalid.
  Status pose_clip(const Document& doc, int32_t clip, double t, std::span<const glm::quat> overrides, PosedCage& cage,
                   std::span<glm::vec3> skin_out);

  // For a caller that deforms the skin itself (the editor's GPU path, app/skin_display.h): poses only this
  // rig's own cage as pose_clip does (the simulation applied when doc.sim is on and a clip plays), with
  // neither the skin nor the layers' rigs; deformer().update_maps then makes the maps of that cage.
  Status pose_clip_cage(const Document& doc, int32_t clip, double t, std::span<const glm::quat> overrides,
                        PosedCage& cage);
  // The deformer of this rig's own cage (not its layers'): what pose and pose_clip deform the skin with.
  Deformer& deformer();

  size_t num_skin_points() const;
  std::span<const glm::vec3> skin_rest() const;
  // The registration: the sets, what a project's cache holds (bind_document's result).
  const Binding& binding() const;
  // The registration of layer `layer` of the stack (its rig's binding()); null when it is muted or there
  // is no such layer. What the project caches for it.
  const Binding* layer_binding(size_t layer) const;
  // The binding of parametric driver `driver` (driver_at's number); null when it does not move the skin.
  // What the project caches for it.
  const Binding* driver_binding(size_t driver) const;
  // What the deformer reads: the registration, or with a fitted attachment its stencil smoothed
  // where the rig would stretch the skin (core/deform/attachment_fit.h fit_rig).
  const Binding& deformer_binding() const;
  const CageAttachment* attachment() const;

  Rig(Rig&&) noexcept;
  Rig& operator=(Rig&&) noexcept;
  ~Rig();

 private:
  Rig();
  static Result<Rig> make(const Document& doc, std::vector<std::optional<Binding>> bindings, const BindProgress& progress,
                          std::vector<std::optional<Binding>> driver_bindings = {});
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace cagewrap
