// The editor's Simulation window: the cage's secondary motion (core/cage/cage_sim.h, core/cage/clip_sim.h) on
// or off, its parameters, the per-vertex weights of the selected cage vertices (pinned, mass,
// stiffness; the soft selection blends them in), the colliders, and how far the current clip's
// simulation has been filled. While the window is open the cage shows the weights: pinned vertices
// grey, free ones from yellow (stiff) to red (soft). Every document change is one undo step.
#pragma once

#include <span>
#include <string>
#include <vector>

#include <glm/vec4.hpp>

#include "app/cage_tools.h"
#include "app/workspace/scene.h"

namespace cagewrap::app {

class SimPanel {
 public:
  bool& visible() { return visible_; }
  // `weights`: the selected cage vertices with their soft-selection shares (vertex, 0..1].
  // `clip`: the clip playing (its simulation's progress is shown).
  void draw(Scene& scene, int32_t clip, std::span<const std::pair<uint32_t, float>> weights, const EditorHooks& hooks);

  // Operations (also for scripts). Each commits one undo step and returns false (logged) on failure.
  bool set_enabled(Scene& scene, bool on, const EditorHooks& hooks);
  bool set_params(Scene& scene, const SimParams& params, const EditorHooks& hooks);
  // Pins the vertices, or frees them with this mass and stiffness, each blended with what it had by
  // its share (a share of 1 takes the new weights as they are; pinning needs a share of 1/2).
  bool set_weights(Scene& scene, std::span<const std::pair<uint32_t, float>> weights, bool pinned, float mass,
                   float stiffness, const EditorHooks& hooks);
  bool add_collider(Scene& scene, Collider collider, const EditorHooks& hooks);
  bool remove_collider(Scene& scene, size_t index, const EditorHooks& hooks);

  // #Vc display colours of the weights (see above).
  static std::vector<glm::vec4> vertex_colors(const SimSettings& sim, size_t num_vertices);

 private:
  bool commit(Scene& scene, SimSettings sim, const std::string& label, const EditorHooks& hooks);
  bool visible_ = false;
  float mass_ = 1.0f, stiffness_ = 0.3f;
};

}  // namespace cagewrap::app
