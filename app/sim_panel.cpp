#include "app/sim_panel.h"
#include "app/ui_text.h"

#if CAGEWRAP_GUI
#include <imgui/imgui.h>
#endif

#include <algorithm>
#include <cstdio>

namespace cagewrap::app {

bool SimPanel::commit(Scene& scene, SimSettings sim, const std::string& label, const EditorHooks& hooks) {
  const Document& doc = scene.doc();
  if (sim == doc.sim) return true;
  const size_t nv = doc.cage ? doc.cage->num_vertices() : 0;
  if (auto v = validate_sim_settings(sim, nv, doc.character->skeleton.size()); !v) {
    hooks.show_error(v.error().message);  // the document is kept as it was
    return false;
  }
  scene.apply(label, with_sim(doc, std::move(sim)));
  return true;
}

bool SimPanel::set_enabled(Scene& scene, bool on, const EditorHooks& hooks) {
  SimSettings sim = scene.doc().sim;
  sim.enabled = on;
  return commit(scene, std::move(sim), on ? "Simulation on" : "Simulation off", hooks);
}

bool SimPanel::set_params(Scene& scene, const SimParams& params, const EditorHooks& hooks) {
  SimSettings sim = scene.doc().sim;
  sim.params = params;
  return commit(scene, std::move(sim), "Simulation parameters", hooks);
}

bool SimPanel::set_weights(Scene& scene, std::span<const std::pair<uint32_t, float>> weights, bool pinned, float mass,
                           float stiffness, const EditorHooks& hooks) {
  const Document& doc = scene.doc();
  if (!doc.cage || weights.empty()) {
    hooks.log("error: select cage vertices first (F5)", true);
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
  return commit(scene, std::move(sim), label, hooks);
}

bool SimPanel::add_collider(Scene& scene, Collider collider, const EditorHooks& hooks) {
  SimSettings sim = scene.doc().sim;
  const std::string label = std::string("Add ") + collider_kind_name(collider.kind) + " collider";
  sim.colliders.push_back(std::move(collider));
  return commit(scene, std::move(sim), label, hooks);
}

bool SimPanel::remove_collider(Scene& scene, size_t index, const EditorHooks& hooks) {
  SimSettings sim = scene.doc().sim;
  if (index >= sim.colliders.size()) {
    hooks.log("error: there is no collider " + std::to_string(index), true);
    return false;
  }
  sim.colliders.erase(sim.colliders.begin() + static_cast<ptrdiff_t>(index));
  return commit(scene, std::move(sim), "Remove collider " + std::to_string(index), hooks);
}

std::vector<glm::vec4> SimPanel::vertex_colors(const SimSettings& sim, size_t num_vertices) {
  std::vector<glm::vec4> out(num_vertices, glm::vec4(0.55f, 0.58f, 0.65f, 1.0f));
  for (size_t v = 0; v < num_vertices && v < sim.vertices.size(); ++v) {
    const SimVertex& w = sim.vertices[v];
    if (w.pinned || w.stiffness >= 1.0f) continue;
    const float soft = 1.0f - std::clamp(w.stiffness, 0.0f, 1.0f);
    out[v] = glm::vec4(1.0f, 0.95f * (1.0f - soft), 0.1f, 1.0f);
  }
  return out;
}

#if CAGEWRAP_GUI

void SimPanel::draw(Scene& scene, int32_t clip, std::span<const std::pair<uint32_t, float>> weights, const EditorHooks& hooks) {
  if (!visible_) return;
  // over the view's right edge, so the character in the middle stays visible
  ImGui::SetNextWindowPos(ImVec2(668, 90), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(310, 455), ImGuiCond_FirstUseEver);
  if (!ImGui::Begin("Simulation", &visible_)) {
    ImGui::End();
    return;
  }
  const Document& doc = scene.doc();
  if (!doc.cage) {
    hint("no cage");
    ImGui::End();
    return;
  }
  bool on = doc.sim.enabled;
  if (ImGui::Checkbox("Simulate the cage", &on)) set_enabled(scene, on, hooks);
  // progress of the current clip's frames
  if (ClipSimulation* sim = on ? scene.simulation(clip) : nullptr) {
    const float share = static_cast<float>(sim->frames_done()) / static_cast<float>(std::max<size_t>(1, sim->frames_total()));
    char text[96];
    std::snprintf(text, sizeof text, "%zu / %zu frames", sim->frames_done(), sim->frames_total());
    ImGui::ProgressBar(share, ImVec2(-1, 0), text);
    if (!sim->stats().empty()) {
      std::vector<double> ms;
      for (const SimFrameStats& s : sim->stats()) ms.push_back(s.ms);
      std::nth_element(ms.begin(), ms.begin() + static_cast<ptrdiff_t>(ms.size() / 2), ms.end());
      hint("%zu free of %zu vertices, %zu edges; %.3f ms a frame (median)", sim->solver().num_free(),
                          sim->solver().num_vertices(), sim->solver().num_edges(), ms[ms.size() / 2]);
    }
  } else if (on && !scene.sim_error.empty()) {
    ImGui::TextColored(ImVec4(1, 0.4f, 0.3f, 1), "%s", scene.sim_error.c_str());
  } else if (on) {
    hint("plays with a clip (choose one in the timeline)");
  }

  if (ImGui::CollapsingHeader("Parameters", ImGuiTreeNodeFlags_DefaultOpen)) {
    SimParams p = doc.sim.params;
    bool done = false;
    auto edited = [&] { done |= ImGui::IsItemDeactivatedAfterEdit(); };
    float fr = static_cast<float>(p.frame_rate), g = static_cast<float>(p.gravity.y),
          damping = static_cast<float>(p.damping), freq = static_cast<float>(p.goal_frequency),
          compliance = static_cast<float>(p.edge_compliance), margin = static_cast<float>(p.collision_margin),
          scale = static_cast<float>(p.skeleton_radius_scale), preroll = static_cast<float>(p.preroll);
    ImGui::PushItemWidth(110);
    ImGui::DragFloat("frames per second", &fr, 1.0f, 1.0f, 240.0f, "%.0f");
    edited();
    ImGui::DragInt("substeps", &p.substeps, 0.2f, 1, 100);
    edited();
    ImGui::DragInt("edge iterations", &p.iterations, 0.2f, 0, 100);
    edited();
    ImGui::DragFloat("gravity (m/s2, y)", &g, 0.1f, -50.0f, 50.0f, "%.2f");
    edited();
    ImGui::DragFloat("damping (1/s)", &damping, 0.05f, 0.0f, 100.0f, "%.2f");
    edited();
    ImGui::DragFloat("goal frequency (Hz)", &freq, 0.05f, 0.0f, 50.0f, "%.2f");
    edited();
    done |= ImGui::Checkbox("keep edge lengths (cloth)", &p.edges);
    ImGui::DragFloat("edge compliance", &compliance, 1e-4f, 0.0f, 1.0f, "%.5f");
    edited();
    ImGui::DragFloat("collision margin (m)", &margin, 0.001f, 0.0f, 1.0f, "%.3f");
    edited();
    done |= ImGui::Checkbox("collide with the skeleton", &p.skeleton_colliders);
    ImGui::DragFloat("bone radius scale", &scale, 0.01f, 0.05f, 5.0f, "%.2f");
    edited();
    ImGui::DragFloat("pre-roll (s)", &preroll, 0.05f, 0.0f, 60.0f, "%.2f");
    edited();
    ImGui::PopItemWidth();
    if (done) {
      p.frame_rate = fr;
      p.gravity.y = g;
      p.damping = damping;
      p.goal_frequency = freq;
      p.edge_compliance = compliance;
      p.collision_margin = margin;
      p.skeleton_radius_scale = scale;
      p.preroll = preroll;
      set_params(scene, p, hooks);
    }
  }

  if (ImGui::CollapsingHeader("Weights", ImGuiTreeNodeFlags_DefaultOpen)) {
    size_t free = 0;
    for (const SimVertex& w : doc.sim.vertices) free += !w.pinned && w.stiffness < 1.0f;
    hint("%zu of %zu cage vertices simulated; %zu selected", free, doc.cage->num_vertices(), weights.size());
    ImGui::PushItemWidth(70);
    ImGui::DragFloat("mass", &mass_, 0.01f, 0.01f, 100.0f, "%.2f");
    ImGui::SameLine();
    ImGui::DragFloat("stiffness", &stiffness_, 0.01f, 0.0f, 1.0f, "%.2f");
    ImGui::PopItemWidth();
    ImGui::BeginDisabled(weights.empty());
    if (ImGui::Button("Simulate selected")) set_weights(scene, weights, false, mass_, stiffness_, hooks);
    ImGui::SameLine();
    if (ImGui::Button("Pin selected")) set_weights(scene, weights, true, mass_, stiffness_, hooks);
    ImGui::EndDisabled();
    hint("soft selection (B) blends the weights in; colours: grey pinned, yellow stiff, red soft");
  }

  if (ImGui::CollapsingHeader("Colliders", ImGuiTreeNodeFlags_DefaultOpen)) {
    int remove = -1;
    for (size_t i = 0; i < doc.sim.colliders.size(); ++i) {
      const Collider& c = doc.sim.colliders[i];
      ImGui::PushID(static_cast<int>(i));
      ImGui::Text("%zu %s %s: (%.2f %.2f %.2f) r %.3f%s", i, collider_kind_name(c.kind), c.name.c_str(), c.a.x, c.a.y,
                  c.a.z, c.radius, c.node >= 0 ? " (follows a joint)" : "");
      ImGui::SameLine();
      if (ImGui::SmallButton("Delete")) remove = static_cast<int>(i);
      ImGui::PopID();
    }
    if (remove >= 0) remove_collider(scene, static_cast<size_t>(remove), hooks);
    // new shapes go where the character stands: a floor at its feet, a ball and a bar in front of it
    if (ImGui::Button("Add floor")) add_collider(scene, {"floor", ColliderKind::kPlane, {0, 0, 0}, {0, 1, 0}, 0.0, -1}, hooks);
    ImGui::SameLine();
    if (ImGui::Button("Add sphere"))
      add_collider(scene, {"sphere", ColliderKind::kSphere, {0, 1.0, 0.4}, {}, 0.15, -1}, hooks);
    ImGui::SameLine();
    if (ImGui::Button("Add capsule"))
      add_collider(scene, {"capsule", ColliderKind::kCapsule, {-0.4, 0.9, 0.4}, {0.4, 0.9, 0.4}, 0.08, -1}, hooks);
    hint("%s", doc.sim.params.skeleton_colliders ? "and the skeleton's bone capsules" : "");
  }
  ImGui::End();
}

#else
void SimPanel::draw(Scene&, int32_t, std::span<const std::pair<uint32_t, float>>, const EditorHooks&) {}
#endif

}  // namespace cagewrap::app
