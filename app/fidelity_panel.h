// The editor's Fidelity section (Properties) and the view's fidelity warning: how far the rig is from
// the character's own skinning (core/rig/fidelity.h), where an artist looks. After a bind it shows the
// current frame's worst vertex, RMS and largest skin-edge stretch with the joint they are at, the heat
// map toggle (grey within 0.5% of the diagonal, through yellow at 1%, red at 5% and beyond), a warning
// naming the worst joint when a threshold is passed, and "Check all clips" with progress, Cancel and
// the clips' table as `cagewrap check` lists them. What it shows and runs is the workspace's
// (app/workspace/workspace_fidelity.cpp); this only draws.
#pragma once

#include "app/workspace/workspace.h"

namespace cagewrap::app {

class FidelityPanel {
 public:
  // The section in Properties (call inside the Properties window).
  void draw(Workspace& ws);
  // The warning in the 3-D view (its bottom-left corner at x, y: screen pixels), when this frame
  // passes a threshold: the figure and the joint nearest the worst vertex or the most stretched edge.
  void draw_warning(const Workspace& ws, float x, float y);
};

}  // namespace cagewrap::app
