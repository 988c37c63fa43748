// The first parametric driver's contributing-set edits picked in the view (issue 21): the driver's samples
// (its control elements, core/deform/patch_binding.h) drawn on its surface while the driver window's sample
// tool is on, clicked into view.patch.picked, and applied to the selected skin vertices as remove / add /
// only / reset, as the Sets window does with cage faces (core/deform/set_editing.h apply_element_set_edit).
// Each edit is one undo step; the driver binds again (Workspace::poll_patch). The driver window and the
// actions patch_samples, patch_sample_select, patch_select_set_samples and patch_set_edit run these.
#include <algorithm>

#include "app/workspace/workspace.h"
#include "core/deform/patch_binding.h"

namespace cagewrap::app {

namespace {
constexpr const char* kNoDriver = "parametric driver: import or fit one first";
}  // namespace

const std::vector<glm::vec3>& Workspace::driver_sample_points() {
  const auto& driver = scene_ ? scene_->work().patch_driver : nullptr;
  if (!driver) {
    sample_points_ = {};
    return sample_points_.points;
  }
  if (sample_points_.driver != driver) {
    sample_points_.driver = driver;
    auto samples = sample_patch_surface(driver->posed, driver->density);
    sample_points_.points = samples ? sample_positions(driver->posed, *samples) : std::vector<glm::vec3>{};
  }
  return sample_points_.points;
}

namespace {
// The samples in the contributing sets of `points` in the driver's binding (ascending, with a weight > 0).
std::vector<uint32_t> driving_samples(const Binding& b, const IndexSet& points) {
  std::vector<uint32_t> out;
  for (uint32_t p : points)
    if (p < b.num_points)
      for (uint32_t i = b.offsets[p]; i < b.offsets[p + 1]; ++i)
        if (b.weights[i] > 0.0f) out.push_back(b.ids[i]);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}
}  // namespace

std::vector<uint8_t> Workspace::driver_sample_states() const {
  const auto& driver = scene_ ? scene_->work().patch_driver : nullptr;
  if (!driver) return {};
  std::vector<uint8_t> state(patch_sample_count(driver->rest, driver->density), 0);
  if (scene_->driver_bound())
    for (uint32_t s : driving_samples(*scene_->driver_binding.binding, view.selection.skin_vertices))
      if (s < state.size()) state[s] = 1;
  for (uint32_t s : view.patch.picked)
    if (s < state.size()) state[s] = 2;
  return state;
}

bool Workspace::select_driver_set_samples() {
  if (!scene_ || !scene_->doc().patch_driver) return fail(kNoDriver), false;
  if (view.selection.skin_vertices.empty()) return fail("select the skin vertices first (F7)"), false;
  if (!scene_->driver_bound()) return fail("parametric driver: it is still binding; try again when the bind is done"), false;
  view.patch.picked.set(driving_samples(*scene_->driver_binding.binding, view.selection.skin_vertices));
  log("parametric driver: picked the " + std::to_string(view.patch.picked.size()) + " samples driving the " +
      std::to_string(view.selection.skin_vertices.size()) + " selected skin vertices");
  return true;
}

bool Workspace::driver_set_edit(SetEditMode mode) {
  if (!scene_ || !scene_->doc().patch_driver) return fail(kNoDriver), false;
  const Document& w = scene_->work();
  const IndexSet& points = view.selection.skin_vertices;
  if (points.empty()) return fail("select the skin vertices to edit first (F7)"), false;
  if (mode != SetEditMode::kReset && view.patch.picked.empty())
    return fail(std::string("pick the driver's samples to ") + set_edit_mode_name(mode) + " first (the driver window's sample tool)"), false;
  const size_t samples = patch_sample_count(w.patch_driver->rest, w.patch_driver->density);
  auto r = apply_element_set_edit(w.driver_place.set_edits, mode, points, view.patch.picked.indices(), scene_->skin_rest.size(), samples);
  if (!r) {
    report_error("parametric driver: " + r.error().message);
    return false;
  }
  if (r->changed_points.empty()) {
    log("parametric driver: the set edit changes nothing");
    return true;
  }
  DriverPlacement place = w.driver_place;
  place.set_edits = std::move(r->edits);
  const std::string label = std::string("Driver sets: ") + set_edit_mode_name(mode) + " " + std::to_string(view.patch.picked.size()) +
                            " samples on " + std::to_string(points.size()) + " points";
  return apply_driver_place(0, label, std::move(place));
}

}  // namespace cagewrap::app
