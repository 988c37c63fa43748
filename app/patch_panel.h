// The editor's Parametric driver window (issue #11; docs/parametric-drivers.md): a patch driver
// imported from a .cwpatch or glTF file or fitted to the selected cage quads, its control net drawn
// over the view, a sampling density, and control points picked (by index, or by a click in the view)
// and moved (position fields, or the editor's move gizmo), the skin following. The driver acts on
// the rest skin, instead of the cage, while "Drive the skin" is on. What it does is the workspace's
// (app/workspace/workspace_patch.cpp: the document's driver, its background bind, the patch_* actions);
// this window only draws and runs them. Its being open is view state (ViewState::patch.editing).
#pragma once

#include <optional>

#include "app/workspace/picking.h"
#include "app/workspace/workspace.h"
#include "render/viewport_renderer.h"

namespace cagewrap::app {

class PatchPanel {
 public:
  void draw(Workspace& ws);
  // The control net, into the renderer.
  void update_display(Workspace& ws, render::ViewportRenderer& renderer);
  // While the window is open, a click within 8 pixels of a control point selects it
  // (app/workspace/picking.h pick_vertex); false when none is near. With the sample tool on, a click within
  // 6 pixels of a sample picks it instead (`add`: shift, `remove`: ctrl); a click beside them selects as usual.
  bool pick(Workspace& ws, const Camera& camera, Viewport viewport, glm::dvec2 pixel, bool add = false, bool remove = false);

 private:
#if CAGEWRAP_GUI
  void draw_stack_place(Workspace& ws);
#endif
  char path_field_[512] = "";
  char mask_field_[256] = "";
  struct ParamsField {
    float local = 0, epsilon = 0;
    int k = 0;
  } params_field_;
  bool params_edited_ = false;  // the fields hold the artist's values, not the driver's
  bool samples_shown_ = false;  // the sample tool was on at the last frame
};

}  // namespace cagewrap::app
