#include "app/sim_panel.h"
#include "app/ui_text.h"

#if CAGEWRAP_GUI
#include <imgui/imgui.h>
#endif

#include <algorithm>
#include <cstdio>

namespace cagewrap::app {

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

void SimPanel::draw(Workspace& ws) {
  if (!visible_ || !ws.scene()) return;
  Scene& scene = *ws.scene();
  const int32_t clip = ws.view.playback.clip;
  const std::vector<std::pair<uint32_t, float>> weights = ws.sim_paint_weights();
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
  if (ImGui::Checkbox("Simulate the cage", &on)) ws.run(on ? "sim on" : "sim off");
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
      ws.set_sim_params(p);
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
    if (ImGui::Button("Simulate selected")) ws.set_sim_weights(false, mass_, stiffness_);
    ImGui::SameLine();
    if (ImGui::Button("Pin selected")) ws.set_sim_weights(true, mass_, stiffness_);
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
    if (remove >= 0) ws.run("sim_remove_collider " + std::to_string(remove));
    // new shapes go where the character stands: a floor at its feet, a ball and a bar in front of it
    if (ImGui::Button("Add floor")) ws.add_collider({"floor", ColliderKind::kPlane, {0, 0, 0}, {0, 1, 0}, 0.0, -1});
    ImGui::SameLine();
    if (ImGui::Button("Add sphere")) ws.add_collider({"sphere", ColliderKind::kSphere, {0, 1.0, 0.4}, {}, 0.15, -1});
    ImGui::SameLine();
    if (ImGui::Button("Add capsule")) ws.add_collider({"capsule", ColliderKind::kCapsule, {-0.4, 0.9, 0.4}, {0.4, 0.9, 0.4}, 0.08, -1});
    hint("%s", doc.sim.params.skeleton_colliders ? "and the skeleton's bone capsules" : "");
  }
  ImGui::End();
}

#else
void SimPanel::draw(Workspace&) {}
#endif

}  // namespace cagewrap::app
