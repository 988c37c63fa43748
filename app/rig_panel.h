// The editor's Rig window: how the cage follows the skeleton (rigid or smooth attachment, bones
// assigned to selected cage vertices, mirrored) and keyposes (sets of drivers, keys made from what
// was sculpted at a pose, values, mute/solo, delete, mirror, and a curve of the correction's size
// against the driver). Every document change is one undo step, made by the workspace. ImGui only.
#pragma once

#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "app/workspace/workspace.h"

namespace cagewrap::app {

class RigPanel {
 public:
  bool& visible() { return visible_; }
  // The window: its edits are the workspace's (Workspace::set_attachment_mode, assign_cage_vertices,
  // the keypose sets: app/workspace/workspace_rig.cpp), run as actions where a script can run them too.
  void draw(Workspace& ws);

 private:
  bool visible_ = false;
};

}  // namespace cagewrap::app
