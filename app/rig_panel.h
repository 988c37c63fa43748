// The editor's Rig window: how the cage follows the skeleton (rigid or smooth attachment, bones
// assigned to selected cage vertices, mirrored) and keyposes (sets of drivers, keys made from what
// was sculpted at a pose, values, mute/solo, delete, mirror, and a curve of the correction's size
// against the driver). Every document change is one undo step. ImGui only; the data is core's.
#pragma once

#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "app/cage_tools.h"
#include "app/workspace/scene.h"
#include "core/geometry/selection.h"

namespace cagewrap::app {

class RigPanel {
 public:
  bool& visible() { return visible_; }
  // `mirror`: X-mirror editing is on (assignments and keys go to the other side too);
  // `tolerance`: scene units for finding mirror counterparts.
  // `pose`: the pose shown (the drivers' current values).
  void draw(Scene& scene, const Pose& pose, const Selection& selection, bool mirror, double tolerance, const EditorHooks& hooks);

  // Operations (also for scripts). Each commits one undo step and returns false (logged) on failure.
  bool set_attachment_mode(Scene& scene, AttachmentMode mode, double width, const EditorHooks& hooks);
  bool assign(Scene& scene, const Selection& selection, bool automatic, bool mirror, double tolerance, const EditorHooks& hooks);
  // A new set driven by the selected joint's rotation about its local axis (0 X, 1 Y, 2 Z).
  bool add_set(Scene& scene, const Selection& selection, int axis, const EditorHooks& hooks);
  // Keys what was sculpted since the last key (the driver offsets' change) at `pose` (the one shown).
  bool key(Scene& scene, const Pose& pose, const EditorHooks& hooks);
  bool remove_key(Scene& scene, size_t key, const EditorHooks& hooks);
  bool mirror_set(Scene& scene, double tolerance, const EditorHooks& hooks);
  size_t& current_set() { return current_; }

 private:
  void commit(Scene& scene, Document doc, const std::string& label);
  bool visible_ = false;
  size_t current_ = 0;
};

}  // namespace cagewrap::app
