// The editor's Simulation window: the cage's secondary motion (core/cage/cage_sim.h, core/rig/clip_sim.h) on
// or off, its parameters, the per-vertex weights of the selected cage vertices (pinned, mass,
// stiffness; the soft selection blends them in), the colliders, and how far the current clip's
// simulation has been filled. While the window is open the cage shows the weights: pinned vertices
// grey, free ones from yellow (stiff) to red (soft). The changes are the workspace's
// (app/workspace/workspace_sim.cpp), each one undo step.
#pragma once

#include <span>
#include <string>
#include <vector>

#include <glm/vec4.hpp>

#include "app/cage_tools.h"
#include "app/workspace/scene.h"
#include "app/workspace/workspace.h"

namespace cagewrap::app {

class SimPanel {
 public:
  bool& visible() { return visible_; }
  // The window for the open document: its clip's simulation progress, and the selected cage vertices'
  // soft-selection shares for the weight buttons.
  void draw(Workspace& ws);

  // #Vc display colours of the weights (see above).
  static std::vector<glm::vec4> vertex_colors(const SimSettings& sim, size_t num_vertices);

 private:
  bool visible_ = false;
  float mass_ = 1.0f, stiffness_ = 0.3f;
};

}  // namespace cagewrap::app
