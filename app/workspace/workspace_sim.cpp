// The workspace's cage-simulation edits (app/workspace/workspace.h "the cage simulation"): on or off,
// its parameters, the per-vertex weights of the selected cage vertices, the colliders. The Simulation
// window and the actions sim, sim_param, sim_weights, sim_collider and sim_remove_collider run these;
// each change is one undo step, checked (validate_sim_settings) before it enters the document.
#include <cstdio>

#include "app/workspace/workspace.h"

namespace cagewrap::app {

bool Workspace::commit_sim(SimSettings sim, const std::string& label) {
  if (!scene_) return false;
  const Document& doc = scene_->doc();
  if (sim == doc.sim) return true;
  const size_t nv = doc.cage ? doc.cage->num_vertices() : 0;
  if (auto v = validate_sim_settings(sim, nv, doc.character->skeleton.size()); !v) {
    report_error(v.error().message);  // the document is kept as it was
    return false;
  }
  scene_->apply(label, with_sim(doc, std::move(sim)));
  return true;
}

bool Workspace::set_simulation(bool on) {
  if (!scene_) return false;
  SimSettings sim = scene_->doc().sim;
  sim.enabled = on;
  return commit_sim(std::move(sim), on ? "Simulation on" : "Simulation off");
}

bool Workspace::set_sim_params(const SimParams& params) {
  if (!scene_) return false;
  SimSettings sim = scene_->doc().sim;
  sim.params = params;
  return commit_sim(std::move(sim), "Simulation parameters");
}

bool Workspace::set_sim_weights(bool pinned, float mass, float stiffness) {
  if (!scene_) return false;
  const Document& doc = scene_->doc();
  const std::vector<std::pair<uint32_t, float>> weights = sim_paint_weights();
  if (!doc.cage || weights.empty()) {
    log("error: select cage vertices first (F5)", true);
    return false;
  }
  SimSettings sim = doc.sim;
  if (sim.vertices.size() != doc.cage->num_vertices()) sim.vertices.assign(doc.cage->num_vertices(), SimVertex{});
  for (auto [v, share] : weights) {
    if (v >= sim.vertices.size()) continue;
    SimVertex& w = sim.vertices[v];
    if (pinned) {
      if (share >= 0.5f) w.pinned = true;
      continue;
    }
    // a vertex freed from a pin starts from the new weights; a free one blends toward them
    const SimVertex from = w.pinned ? SimVertex{false, mass, stiffness} : w;
    w = {false, from.mass + (mass - from.mass) * share, from.stiffness + (stiffness - from.stiffness) * share};
  }
  char label[96];
  std::snprintf(label, sizeof label, pinned ? "Pin %zu cage vertices" : "Simulate %zu cage vertices (mass %.2g, stiffness %.2g)",
                weights.size(), static_cast<double>(mass), static_cast<double>(stiffness));
  return commit_sim(std::move(sim), label);
}

bool Workspace::add_collider(Collider collider) {
  if (!scene_) return false;
  SimSettings sim = scene_->doc().sim;
  const std::string label = std::string("Add ") + collider_kind_name(collider.kind) + " collider";
  sim.colliders.push_back(std::move(collider));
  return commit_sim(std::move(sim), label);
}

bool Workspace::remove_collider(size_t index) {
  if (!scene_) return false;
  SimSettings sim = scene_->doc().sim;
  if (index >= sim.colliders.size()) {
    log("error: there is no collider " + std::to_string(index) + " (the simulation has " + std::to_string(sim.colliders.size()) + ")", true);
    return false;
  }
  sim.colliders.erase(sim.colliders.begin() + static_cast<ptrdiff_t>(index));
  return commit_sim(std::move(sim), "Remove collider " + std::to_string(index));
}

}  // namespace cagewrap::app
