// The editor's Fidelity section (Properties): how far the rig is from the character's own skinning
// (core/deform/fidelity.h), where an artist looks. After a bind it shows the current frame's worst vertex,
// RMS and largest skin-edge stretch with the joint they are at, colours the skin by its distance to
// the file's skinning (the heat map: grey within 0.5% of the diagonal, through yellow at 1%, red at
// 5% and beyond), and warns, naming the worst joint, when a threshold is passed. "Check all clips"
// poses the rig at every clip's frames in the background (its own bind, as the export does) with
// progress and Cancel, and lists the clips as `cagewrap check` does.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec4.hpp>

#include "app/workspace/background_task.h"
#include "app/cage_tools.h"
#include "app/workspace/scene.h"
#include "core/deform/fidelity.h"

namespace cagewrap::app {

class FidelityPanel {
 public:
  // Measures the current frame when it changed (pose, binding, attachment, document; while a clip
  // plays, at most 4 times a second); cheap when not.
  void update(Scene& scene, const Playback& playback);
  // The section in Properties (call inside the Properties window).
  void draw(Scene& scene, const Playback& playback, const EditorHooks& hooks);
  // The warning in the 3-D view (its bottom-left corner at x, y: screen pixels), when this frame
  // passes a threshold: the figure and the joint nearest the worst vertex or the most stretched edge.
  void draw_warning(const Scene& scene, float x, float y);
  // Finishes a running check: the report into the panel and the log.
  void poll(const Scene& scene, const EditorHooks& hooks);
  void start_check(const Scene& scene, const EditorHooks& hooks);
  void cancel();
  bool busy() const { return job_ != nullptr; }
  // Another document opened: a running check is cancelled (and waited for), and what was measured
  // for the previous one is dropped (its edges and joints index another skin). Settings stay.
  void scene_changed();

  bool heat_map = false;
  // The heat map's colours for the current frame (#V), empty when it is off or nothing is measured.
  const std::vector<glm::vec4>& colors() const { return colors_; }
  // The current frame's figures, when measured.
  const std::optional<FrameFidelity>& frame() const { return frame_; }
  const std::optional<FidelityReport>& report() const { return report_; }
  FidelityThresholds thresholds;

 private:
  std::optional<FrameFidelity> frame_;
  std::vector<float> distance_;      // #V d / diagonal of the current frame
  std::vector<glm::vec4> colors_;
  std::vector<std::pair<uint32_t, uint32_t>> edges_;
  std::vector<int32_t> joints_;
  const Character* character_ = nullptr;  // edges_ and joints_ are of this character
  double diagonal_ = 1.0;
  std::string key_;  // what frame_ was measured for
  double measured_at_ = -1e9;  // steady-clock seconds of the last measurement
  std::optional<FidelityReport> report_;
  std::string report_key_;  // the document the report is of (stale when it changed)
  std::unique_ptr<BackgroundTask<FidelityReport>> job_;
  std::string last_outcome_;
};

// The heat-map colour of a distance (share of the diagonal).
glm::vec4 fidelity_color(float share);

}  // namespace cagewrap::app
