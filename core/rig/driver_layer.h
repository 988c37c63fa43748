// The parametric driver as a deformer of the posed skin (issue 21, docs/parametric-drivers.md): its
// control points follow the skeleton like cage vertices (rigidly, each to its closest limb:
// attach_to_closest_limb), and its sculpt -- the posed control points minus the rest ones, both in the
// bind pose -- is added to the skin the cages make:
//   s += D(M (rest + sculpt)) - D(M rest)
// with D the driver's deformer (core/deform/patch_binding.h) and M each control point's joint at the
// pose, each skin point taking it in full within 1.5 h of the driver's nearest sample and none beyond
// 3 h (h: the control net's scale), so that the sculpt stays where the driver is. At the bind pose M is the identity and D(rest) is the rest skin, so this is the driven skin
// the editor always showed there; posed, the sculpt travels with the limbs. A driver with no sculpt
// adds nothing. Keyposes (Document::driver_place.keyposes) add their offsets to the sculpt at each pose.
// The displacement takes its place in the deformer stack (Document::driver_place, core/rig/deformer_stack.h
// combine_document_stack), so `pose`, `check`, the exports and the editor's frame carry it alike.
#pragma once

#include <memory>
#include <span>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "core/base/result.h"
#include "core/cage/keyposes.h"
#include "core/character/character.h"
#include "core/deform/binding.h"
#include "core/deform/patch_surface.h"
#include "core/deform/registration.h"

namespace cagewrap {

class DriverLayer {
 public:
  // Binds `skin_rest` (#P, skin_character order) to the driver's rest surface at its density
  // (bind_skin_to_patches with `params`) and attaches its control points to the skeleton. Fails when the
  // character has no skin, or the bind fails (the message says which).
  static Result<DriverLayer> create(const Character& character, std::span<const glm::vec3> skin_rest,
                                    const PatchDriver& driver, const BindParams& params, const BindProgress& progress = {},
                                    std::span<const SetEdit> edits = {});
  // The same from a binding made earlier for this driver and skin (the editor's), with `edits`.
  static Result<DriverLayer> create(const Character& character, std::span<const glm::vec3> skin_rest,
                                    const PatchDriver& driver, Binding binding, std::span<const SetEdit> edits = {});

  // Whether `driver` has the rest surface and density this layer was bound for (its sculpt may differ), and
  // `params` are what it was bound with (core/deform/patch_binding.h patch_bind_params).
  bool fits(const PatchDriver& driver) const;
  bool fits(const PatchDriver& driver, const BindParams& params) const;
  // ... and its set edits are `edits` (canonical, as DriverPlacement keeps them).
  bool fits(const PatchDriver& driver, const BindParams& params, std::span<const SetEdit> edits) const;
  // The sculpt's displacement of the skin alone, written into `delta` (#P): the sculpt is the posed control
  // points minus the rest ones plus `offsets` (#C, the driver's keyposes at the pose in bind space, or
  // empty). Returns whether there is any (false: `delta` is all zero).
  Result<bool> displacement(const PatchDriver& driver, std::span<const glm::vec3> offsets, std::span<const glm::mat4> globals,
                            std::span<glm::vec3> delta);
  // The same at `pose` (node world transforms `globals`), the offsets being `keyposes` evaluated there
  // (Document::driver_place.keyposes; core/cage/keyposes.h): what Rig and the editor add to the stack.
  Result<bool> displacement(const PatchDriver& driver, std::span<const KeyposeSet> keyposes, const Skeleton& skeleton,
                            const Pose& pose, std::span<const glm::mat4> globals, std::span<glm::vec3> delta);
  size_t num_control_points() const;
  // The skin's binding to the driver's samples (what a project caches for it).
  const Binding& binding() const;
  // Attaches the control points by `settings` (rigid, smooth or skin_weights; its overrides name control
  // points) instead of each rigidly to its closest limb (null: back to that), without binding again.
  // Errors: fitted (it fits a cage's attachment to its binding), an override past the control points or on
  // a node that is not a joint of the skin (named).
  Status attach(const Character& character, const AttachmentSettings* settings);
  // Whether the control points are attached by `settings` (null: to their closest limbs).
  bool attached_by(const AttachmentSettings* settings) const;

  DriverLayer(DriverLayer&&) noexcept;
  DriverLayer& operator=(DriverLayer&&) noexcept;
  ~DriverLayer();

 private:
  DriverLayer();
  struct State;
  std::unique_ptr<State> s_;
};

}  // namespace cagewrap
