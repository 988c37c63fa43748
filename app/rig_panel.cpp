#include "app/rig_panel.h"
#include "app/ui_text.h"

#if CAGEWRAP_GUI
#include <imgui/imgui.h>
#endif

#include <algorithm>
#include <cmath>
#include <cfloat>
#include <cstdio>

#include <glm/geometric.hpp>

#include "core/cage/cage_attachment.h"
#include "core/cage/keyposes.h"
#include "core/character/mirror_names.h"

namespace cagewrap::app {

#if CAGEWRAP_GUI

void RigPanel::draw(Workspace& ws) {
  if (!visible_) return;
  ImGui::SetNextWindowPos(ImVec2(270, 120), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(380, 460), ImGuiCond_FirstUseEver);
  if (!ImGui::Begin("Rig: attachment and keyposes", &visible_)) {
    ImGui::End();
    return;
  }
  if (!ws.scene()) {
    ImGui::End();
    return;
  }
  const Document& doc = ws.scene()->doc();
  const Skeleton& sk = doc.character->skeleton;
  const Selection& sel = ws.view.selection;
  if (!doc.cage) {
    hint("no cage");
    ImGui::End();
    return;
  }
  if (ImGui::CollapsingHeader("Attachment", ImGuiTreeNodeFlags_DefaultOpen)) {
    // the order of AttachmentMode
    const char* modes[] = {"rigid: closest limb", "smooth near joints", "character's skin weights",
                           "skin weights, fitted"};  // to the file's skinning (the default)
    int mode = static_cast<int>(doc.attachment.mode);
    float width = static_cast<float>(doc.attachment.smooth_width);
    ImGui::SetNextItemWidth(doc.attachment.mode == AttachmentMode::kSmooth ? 220 : width_beside("cage follows"));
    bool changed = combo("cage follows", &mode, modes, 4);
    if (doc.attachment.mode == AttachmentMode::kSmooth) {
      ImGui::SameLine();
      ImGui::SetNextItemWidth(120);
      changed |= ImGui::InputFloat("width", &width, 0.0f, 0.0f, "%.2f", ImGuiInputTextFlags_EnterReturnsTrue);
    }
    if (changed) ws.set_attachment_mode(static_cast<AttachmentMode>(mode), width);
    hint("%zu vertices assigned by hand", doc.attachment.overrides.size());
    const bool can = !sel.cage_vertices.empty();
    ImGui::BeginDisabled(!can || sel.joints.size() != 1);
    if (ImGui::Button("Assign to selected joint")) ws.run("attach joint");
    ImGui::EndDisabled();
    ImGui::SameLine();
    ImGui::BeginDisabled(!can);
    if (ImGui::Button("Restore automatic")) ws.run("attach auto");
    ImGui::EndDisabled();
    hint("select cage vertices (F5) and a joint (outliner); X-mirror applies too");
  }
  if (ImGui::CollapsingHeader("Keyposes", ImGuiTreeNodeFlags_DefaultOpen)) {
    ImGui::BeginDisabled(sel.joints.size() != 1);
    if (ImGui::Button("Add set: X")) ws.run("keyset x");
    ImGui::SameLine();
    if (ImGui::Button("Y")) ws.run("keyset y");
    ImGui::SameLine();
    if (ImGui::Button("Z")) ws.run("keyset z");
    ImGui::EndDisabled();
    ImGui::SameLine();
    hint("(rotation of the selected joint)");
    if (!ws.active_keypose_set()) {
      hint("no keypose sets");
    } else {
      size_t& current_ = ws.view.keypose_set;
      if (ImGui::BeginListBox("##sets", ImVec2(-1, 70))) {
        for (size_t i = 0; i < doc.keyposes.size(); ++i) {
          const KeyposeSet& s = doc.keyposes[i];
          std::string label = s.name + (s.mute ? "  [muted]" : "") + (s.solo ? "  [solo]" : "") + "  (" + std::to_string(s.keys.size()) + " keys)";
          if (ImGui::Selectable(label.c_str(), current_ == i)) current_ = i;
        }
        ImGui::EndListBox();
      }
      const Pose& pose = ws.scene()->shown_pose();  // this frame's, posed already
      KeyposeSet set = doc.keyposes[current_];
      bool edited = false;
      std::string edit_label;
      for (size_t d = 0; d < set.drivers.size(); ++d) {
        const JointDriver& dr = set.drivers[d];
        const double now = driver_value(dr, sk, pose);  // (the pose shown)
        ImGui::Text("driver: %s %s about (%.0f %.0f %.0f), now %.1f deg", dr.node < sk.size() ? sk.node(dr.node).name.c_str() : "?",
                    driver_kind_name(dr.kind), dr.axis.x, dr.axis.y, dr.axis.z, now);
      }
      if (ImGui::Checkbox("mute", &set.mute)) edited = true, edit_label = "Mute " + set.name;
      ImGui::SameLine();
      if (ImGui::Checkbox("solo", &set.solo)) edited = true, edit_label = "Solo " + set.name;
      ImGui::SameLine();
      if (ImGui::Checkbox("rest key", &set.rest_key)) edited = true, edit_label = "Rest key " + set.name;
      int interp = static_cast<int>(set.interpolation);
      const char* interps[] = {"linear", "smooth (monotone cubic)"};
      if (combo("interpolation", &interp, interps, 2)) {
        set.interpolation = static_cast<KeyInterpolation>(interp);
        edited = true, edit_label = "Interpolation of " + set.name;
      }
      if (ImGui::Button("Key the sculpt at this pose", ImVec2(-1, 0))) ws.run("key");
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("Pose the joint, move cage vertices, then Key: what you moved becomes the key");
      int remove = -1;
      for (size_t k = 0; k < set.keys.size(); ++k) {
        ImGui::PushID(static_cast<int>(k));
        float v = set.keys[k].values.empty() ? 0.f : static_cast<float>(set.keys[k].values[0]);
        ImGui::SetNextItemWidth(110);
        if (ImGui::InputFloat("##value", &v, 0.0f, 0.0f, "%.1f deg", ImGuiInputTextFlags_EnterReturnsTrue) && !set.keys[k].values.empty()) {
          set.keys[k].values[0] = v;
          edited = true, edit_label = "Key value of " + set.name;
        }
        ImGui::SameLine();
        float biggest = 0.f;
        for (const auto& o : set.keys[k].offsets) biggest = std::max(biggest, glm::length(o));
        ImGui::Text("%zu vertices, up to %.4g", set.keys[k].vertices.size(), biggest);
        ImGui::SameLine();
        if (ImGui::SmallButton("Delete")) remove = static_cast<int>(k);
        ImGui::PopID();
      }
      // the correction's size against the driver (one-driver sets)
      if (set.drivers.size() == 1 && !set.keys.empty()) {
        double lo = set.rest_key ? 0.0 : set.keys.front().values[0], hi = lo;
        for (const auto& k : set.keys) lo = std::min(lo, k.values[0]), hi = std::max(hi, k.values[0]);
        lo -= 0.1 * (hi - lo + 1.0), hi += 0.1 * (hi - lo + 1.0);
        float curve[64];
        std::vector<glm::vec3> out(doc.cage->num_vertices());
        for (int i = 0; i < 64; ++i) {
          std::fill(out.begin(), out.end(), glm::vec3(0.f));
          const double x[1] = {lo + (hi - lo) * i / 63.0};
          add_keypose_set_offsets(set, x, out);
          float m = 0.f;
          for (const auto& o : out) m = std::max(m, glm::length(o));
          curve[i] = m;
        }
        char overlay[64];
        std::snprintf(overlay, sizeof overlay, "largest offset, %.0f..%.0f deg", lo, hi);
        ImGui::PlotLines("##curve", curve, 64, 0, overlay, 0.0f, FLT_MAX, ImVec2(-1, 60));
      }
      if (ImGui::Button("Mirror set to the other side")) ws.run("mirror_keyset");
      // (after the drawing: a change replaces the document the references above point into)
      if (edited) ws.replace_keypose_set(std::move(set), edit_label);
      if (remove >= 0) ws.run("remove_key " + std::to_string(remove));
    }
  }
  ImGui::End();
}

#else
void RigPanel::draw(Workspace&) {}
#endif

}  // namespace cagewrap::app
