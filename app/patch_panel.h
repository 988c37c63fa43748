// The editor's Parametric driver window (issue #11; docs/parametric-drivers.md): a patch driver
// imported from a .cwpatch or glTF file or fitted to the selected cage quads, its control net drawn
// over the view, a sampling density, and control points picked by index and moved, the skin
// following. The driver acts on the rest skin, instead of the cage, while "Drive the skin" is on;
// it is view state of this window (not saved with the project, not undone). ImGui only; the
// geometry is core's (core/patch_binding.h, core/patch_fit.h).
#pragma once

#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "app/cage_tools.h"
#include "app/editor_scene.h"
#include "core/patch_binding.h"
#include "core/selection.h"
#include "render/viewport_renderer.h"

namespace cagewrap::app {

class PatchPanel {
 public:
  bool& visible() { return visible_; }
  void draw(Scene& scene, const Selection& selection, const EditorHooks& hooks);
  // After the frame's skin is drawn into the renderer: the skin the driver deforms (when it drives
  // the skin) and the control net.
  void update_display(Scene& scene, render::ViewportRenderer& renderer);

  // Operations (also for scripts); each returns false and logs (or shows) why on failure, keeping
  // the driver it had.
  bool import(Scene& scene, const std::string& path, const EditorHooks& hooks);
  bool export_to(const std::string& path, const EditorHooks& hooks) const;
  bool fit(Scene& scene, const Selection& selection, const EditorHooks& hooks);
  bool set_density(Scene& scene, uint32_t density, const EditorHooks& hooks);
  bool select(int control_point, const EditorHooks& hooks);
  bool move(const glm::dvec3& delta, const EditorHooks& hooks);  // the selected control point
  // `patch_*` script commands (patch_import P, patch_export P, patch_fit, patch_density N,
  // patch_select I, patch_move DX DY DZ, patch_reset, patch_drive on|off, patch_panel); false when
  // `cmd` is not one of them.
  bool script_command(const std::string& cmd, std::istringstream& in, Scene& scene, const Selection& selection,
                      const EditorHooks& hooks);

 private:
  bool set_driver(Scene& scene, PatchSurface rest, const std::string& what, const EditorHooks& hooks);
  bool bind(Scene& scene, uint32_t density, const EditorHooks& hooks);

  bool visible_ = false;
  bool drive_skin_ = true;
  std::optional<PatchSurface> rest_;
  PatchSurface posed_;
  uint32_t density_ = 2;
  int selected_ = -1;
  std::unique_ptr<Binding> binding_;
  std::unique_ptr<PatchDeformer> deformer_;
  const std::vector<glm::vec3>* bound_skin_ = nullptr;  // the scene's skin_rest the binding is for
  std::vector<glm::vec3> skin_;  // #V deformed by posed_
  bool skin_dirty_ = true;
  double bind_ms_ = 0;
  char path_field_[512] = "";
};

}  // namespace cagewrap::app
