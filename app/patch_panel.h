// The editor's Parametric driver window (issue #11; docs/parametric-drivers.md): a patch driver
// imported from a .cwpatch or glTF file or fitted to the selected cage quads, its control net drawn
// over the view, a sampling density, and control points picked (by index, or by a click in the
// view) and moved (position fields, or the editor's move gizmo), the skin following. The driver acts on the rest skin, instead of the cage, while "Drive the skin" is on.
// The driver is the document's (Document::patch_driver): saved with the project, and every change
// (import, fit, density, a move, reset, drive on/off) is one undo step. Binding runs in the
// background with progress and Cancel; a change that needs a new binding (import, fit, density)
// enters the document once its bind succeeds. ImGui only; the geometry is core's
// (core/deform/patch_binding.h, core/deform/patch_fit.h).
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "app/workspace/background_task.h"
#include "app/cage_tools.h"
#include "app/workspace/scene.h"
#include "core/deform/patch_binding.h"
#include "app/workspace/picking.h"
#include "core/geometry/selection.h"
#include "render/viewport_renderer.h"

namespace cagewrap::app {

class PatchPanel {
 public:
  bool& visible() { return visible_; }
  void draw(Scene& scene, const Selection& selection, const EditorHooks& hooks);
  // Before the frame's pose: while the driver drives the skin, hands the skin it deforms to the
  // scene (Scene::driven_skin; deformed again only when the driver changes), else takes it back.
  void drive_skin(Scene& scene);
  // The control net, into the renderer.
  void update_display(Scene& scene, render::ViewportRenderer& renderer);
  // Every frame: finishes a background bind (the change it was for becomes an undo step) and starts
  // one when the document's driver is not bound (undo, redo, a project opened).
  void poll(Scene& scene, const EditorHooks& hooks);
  // Whether a script waits: a bind runs (unless the script started it with `nowait`).
  bool busy() const { return job_ != nullptr && !script_nowait_; }

  // Operations (also for scripts); each returns false and logs (or shows) why on failure, keeping
  // the driver it had.
  bool import(Scene& scene, const std::string& path, const EditorHooks& hooks);
  bool export_to(const std::string& path, const Scene& scene, const EditorHooks& hooks) const;
  bool fit(Scene& scene, const Selection& selection, const EditorHooks& hooks);
  bool set_density(Scene& scene, uint32_t density, const EditorHooks& hooks);
  bool select(const Scene& scene, int control_point, const EditorHooks& hooks);
  bool move(Scene& scene, const glm::dvec3& delta, const EditorHooks& hooks);  // the selected control point
  bool set_drive(Scene& scene, bool drive, const EditorHooks& hooks);  // "Drive the skin" on or off
  bool reset(Scene& scene, const EditorHooks& hooks);                  // the control points back to rest
  // The view's picking and move gizmo (app/editor.cpp), while the window is open: the selected
  // control point's posed position (none: no selection or the window is closed); a click within 8
  // pixels of a control point selects it (app/workspace/picking.h pick_vertex; false when none is near);
  // and `from` with the selected control point moved by `total` (a drag rebuilds from its start).
  std::optional<glm::dvec3> selected_position(const Scene& scene) const;
  bool pick(const Scene& scene, const Camera& camera, Viewport viewport, glm::dvec2 pixel);
  void deselect() { selected_ = -1; }
  int selected() const { return selected_; }
  Document moved(const Document& from, const glm::dvec3& total) const;
  // `patch_*` script commands (patch_import P, patch_export P, patch_fit, patch_density N,
  // patch_select I, patch_move DX DY DZ, patch_reset, patch_drive on|off, patch_cancel, patch_panel; patch_density N nowait lets the script go on
  // while it binds); false when
  // `cmd` is not one of them.
  bool script_command(const std::string& cmd, std::istringstream& in, Scene& scene, const Selection& selection,
                      const EditorHooks& hooks);

 private:
  // Binds `driver` in the background; when it succeeds and `label` is not empty, the document gets
  // the driver as the undo step `label` (else the driver is the document's already).
  void start_bind(Scene& scene, std::shared_ptr<const PatchDriver> driver, std::string label);
  void new_driver(Scene& scene, PatchSurface rest, const std::string& label);
  // The document with its driver replaced, as the undo step `label`.
  void commit(Scene& scene, std::shared_ptr<const PatchDriver> driver, const std::string& label);
  // The document's driver changed by `change`, as the undo step `label`; false (logged) without one.
  bool change_driver(Scene& scene, const std::function<void(PatchDriver&)>& change, const std::string& label,
                     const EditorHooks& hooks);
  // Whether the binding is for the document's driver (rest grids and density) and this skin.
  bool bound_to(const Scene& scene) const;

  bool visible_ = false;
  int selected_ = -1;  // view state
  std::unique_ptr<BackgroundTask<Binding>> job_;
  std::shared_ptr<const PatchDriver> job_driver_;  // what the running job binds
  std::shared_ptr<const Character> job_character_;  // whose rest skin it binds
  std::string job_label_;
  bool script_nowait_ = false;  // the running bind was started by `patch_density N nowait`
  std::shared_ptr<const PatchDriver> failed_;  // the document's driver whose bind failed (not retried)
  std::unique_ptr<Binding> binding_;
  std::unique_ptr<PatchDeformer> deformer_;
  std::shared_ptr<const PatchDriver> bound_driver_;  // the driver the binding was made for
  std::shared_ptr<const Character> bound_character_;  // and the character whose rest skin it binds
  std::shared_ptr<const PatchDriver> shown_;  // the driver skin_ was deformed by
  std::shared_ptr<const std::vector<glm::vec3>> skin_;  // #V deformed by shown_->posed (null: it failed)
  char path_field_[512] = "";
};

}  // namespace cagewrap::app
