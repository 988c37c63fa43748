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

#include "core/rig/cage_attachment.h"
#include "core/rig/keyposes.h"
#include "core/rig/mirror_names.h"

namespace cagewrap::app {

void RigPanel::commit(Scene& scene, Document doc, const std::string& label) {
  scene.apply(label, std::move(doc));
}

bool RigPanel::set_attachment_mode(Scene& scene, AttachmentMode mode, double width, const EditorHooks&) {
  AttachmentSettings a = scene.doc().attachment;
  a.mode = mode;
  a.smooth_width = width;
  if (a == scene.doc().attachment) return true;
  commit(scene, with_attachment(scene.doc(), a), std::string("Attachment: ") + attachment_mode_name(mode));
  return true;
}

bool RigPanel::assign(Scene& scene, const Selection& sel, bool automatic, bool mirror, double tolerance, const EditorHooks& hooks) {
  const Document& doc = scene.doc();
  if (!doc.cage || sel.cage_vertices.empty()) {
    hooks.log("error: select cage vertices first (F5)", true);
    return false;
  }
  std::optional<uint32_t> node;
  if (!automatic) {
    if (sel.joints.size() != 1) {
      hooks.log("error: select exactly one joint to assign the cage vertices to (F8 or the outliner)", true);
      return false;
    }
    node = sel.joints.indices()[0];
  }
  AttachmentSettings a = assign_vertices(doc.attachment, sel.cage_vertices.indices(), node);
  if (mirror) {
    auto m = mirror_assignment(a, doc.character->skeleton, doc.cage->polygons.positions, sel.cage_vertices.indices(), tolerance);
    if (!m) {
      hooks.show_error(m.error().message);
      return false;
    }
    if (!m->unmatched.empty()) hooks.log("warning: " + std::to_string(m->unmatched.size()) + " vertices have no mirror counterpart", false);
    a = m->settings;
  }
  // the attachment must be valid before it is committed
  if (auto att = attach_cage(*doc.character, doc.cage->polygons.positions, a, doc.cage->elements); !att) {
    hooks.show_error(att.error().message);
    return false;
  }
  const std::string what = automatic ? "automatic" : doc.character->skeleton.node(*node).name;
  commit(scene, with_attachment(doc, a), "Attach " + std::to_string(sel.cage_vertices.size()) + " vertices: " + what);
  return true;
}

bool RigPanel::add_set(Scene& scene, const Selection& sel, int axis, const EditorHooks& hooks) {
  if (sel.joints.size() != 1) {
    hooks.log("error: select the joint that drives the keypose (F8)", true);
    return false;
  }
  const uint32_t node = sel.joints.indices()[0];
  KeyposeSet set;
  set.name = scene.doc().character->skeleton.node(node).name + "_" + "XYZ"[axis % 3];
  JointDriver d;
  d.node = node;
  d.axis = glm::vec3(0.f);
  d.axis[axis % 3] = 1.f;
  set.drivers.push_back(d);
  std::vector<KeyposeSet> sets = scene.doc().keyposes;
  current_ = upsert_keypose_set(sets, set);
  commit(scene, with_keyposes(scene.doc(), std::move(sets)), "Add keypose set " + set.name);
  return true;
}

bool RigPanel::key(Scene& scene, const Pose& pose, const EditorHooks& hooks) {
  const Document& doc = scene.doc();
  if (!doc.cage || current_ >= doc.keyposes.size()) {
    hooks.log("error: add a keypose set first (select a joint, Rig > Keyposes > Add set)", true);
    return false;
  }
  const KeyposeSet& set = doc.keyposes[current_];
  std::vector<double> values = driver_values(set, doc.character->skeleton, pose);
  for (double& v : values) v = std::round(v * 10.0) / 10.0;  // keys at tenths of a degree
  // what was sculpted since the last key: the driver offsets, taken out of them into the key
  std::vector<glm::vec3> delta = doc.cage_offsets;
  delta.resize(doc.cage->num_vertices(), glm::vec3(0.f));
  std::vector<KeyposeSet> sets = doc.keyposes;
  sets[current_] = key_sculpt(set, values, delta);
  Document d = with_keyposes(doc, std::move(sets));
  d = with_cage_offsets(d, {});
  char label[128];
  std::snprintf(label, sizeof label, "Key %s at %.1f", set.name.c_str(), values.empty() ? 0.0 : values[0]);
  commit(scene, std::move(d), label);
  hooks.log(label, false);
  return true;
}

bool RigPanel::remove_key(Scene& scene, size_t k, const EditorHooks&) {
  const Document& doc = scene.doc();
  if (current_ >= doc.keyposes.size() || k >= doc.keyposes[current_].keys.size()) return false;
  std::vector<KeyposeSet> sets = doc.keyposes;
  const std::vector<double> values = sets[current_].keys[k].values;
  cagewrap::remove_key(sets[current_], values);
  commit(scene, with_keyposes(doc, std::move(sets)), "Delete key of " + doc.keyposes[current_].name);
  return true;
}

bool RigPanel::mirror_set(Scene& scene, double tolerance, const EditorHooks& hooks) {
  const Document& doc = scene.doc();
  if (!doc.cage || current_ >= doc.keyposes.size()) return false;
  auto m = mirror_keypose_set(doc.keyposes[current_], doc.character->skeleton, doc.cage->polygons.positions, tolerance);
  if (!m) {
    hooks.show_error(m.error().message);
    return false;
  }
  std::vector<KeyposeSet> sets = doc.keyposes;
  upsert_keypose_set(sets, m->set);
  commit(scene, with_keyposes(doc, std::move(sets)), "Mirror keypose set " + doc.keyposes[current_].name);
  return true;
}

#if CAGEWRAP_GUI

void RigPanel::draw(Scene& scene, const Pose& pose, const Selection& sel, bool mirror, double tolerance, const EditorHooks& hooks) {
  if (!visible_) return;
  ImGui::SetNextWindowPos(ImVec2(270, 120), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(380, 460), ImGuiCond_FirstUseEver);
  if (!ImGui::Begin("Rig: attachment and keyposes", &visible_)) {
    ImGui::End();
    return;
  }
  const Document& doc = scene.doc();
  const Skeleton& sk = doc.character->skeleton;
  if (!doc.cage) {
    hint("no cage");
    ImGui::End();
    return;
  }
  if (ImGui::CollapsingHeader("Attachment", ImGuiTreeNodeFlags_DefaultOpen)) {
    // the order of AttachmentMode
    const char* modes[] = {"rigid: closest limb", "smooth near joints", "character's skin weights",
                           "skin weights, fitted to the file's skinning"};
    int mode = static_cast<int>(doc.attachment.mode);
    float width = static_cast<float>(doc.attachment.smooth_width);
    ImGui::SetNextItemWidth(doc.attachment.mode == AttachmentMode::kSmooth ? 220 : width_beside("cage follows"));
    bool changed = ImGui::Combo("cage follows", &mode, modes, 4);
    if (doc.attachment.mode == AttachmentMode::kSmooth) {
      ImGui::SameLine();
      ImGui::SetNextItemWidth(120);
      changed |= ImGui::InputFloat("width", &width, 0.0f, 0.0f, "%.2f", ImGuiInputTextFlags_EnterReturnsTrue);
    }
    if (changed && width > 0.f) set_attachment_mode(scene, static_cast<AttachmentMode>(mode), width, hooks);
    hint("%zu vertices assigned by hand", doc.attachment.overrides.size());
    const bool can = !sel.cage_vertices.empty();
    ImGui::BeginDisabled(!can || sel.joints.size() != 1);
    if (ImGui::Button("Assign to selected joint")) assign(scene, sel, false, mirror, tolerance, hooks);
    ImGui::EndDisabled();
    ImGui::SameLine();
    ImGui::BeginDisabled(!can);
    if (ImGui::Button("Restore automatic")) assign(scene, sel, true, mirror, tolerance, hooks);
    ImGui::EndDisabled();
    hint("select cage vertices (F5) and a joint (outliner); X-mirror applies too");
  }
  if (ImGui::CollapsingHeader("Keyposes", ImGuiTreeNodeFlags_DefaultOpen)) {
    ImGui::BeginDisabled(sel.joints.size() != 1);
    if (ImGui::Button("Add set: X")) add_set(scene, sel, 0, hooks);
    ImGui::SameLine();
    if (ImGui::Button("Y")) add_set(scene, sel, 1, hooks);
    ImGui::SameLine();
    if (ImGui::Button("Z")) add_set(scene, sel, 2, hooks);
    ImGui::EndDisabled();
    ImGui::SameLine();
    hint("(rotation of the selected joint)");
    if (doc.keyposes.empty()) {
      hint("no keypose sets");
    } else {
      current_ = std::min(current_, doc.keyposes.size() - 1);
      if (ImGui::BeginListBox("##sets", ImVec2(-1, 70))) {
        for (size_t i = 0; i < doc.keyposes.size(); ++i) {
          const KeyposeSet& s = doc.keyposes[i];
          std::string label = s.name + (s.mute ? "  [muted]" : "") + (s.solo ? "  [solo]" : "") + "  (" + std::to_string(s.keys.size()) + " keys)";
          if (ImGui::Selectable(label.c_str(), current_ == i)) current_ = i;
        }
        ImGui::EndListBox();
      }
      KeyposeSet set = doc.keyposes[current_];
      bool edited = false;
      std::string edit_label;
      for (size_t d = 0; d < set.drivers.size(); ++d) {
        const JointDriver& dr = set.drivers[d];
        const double now = driver_value(dr, sk, pose);
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
      if (ImGui::Combo("interpolation", &interp, interps, 2)) {
        set.interpolation = static_cast<KeyInterpolation>(interp);
        edited = true, edit_label = "Interpolation of " + set.name;
      }
      if (ImGui::Button("Key the sculpt at this pose", ImVec2(-1, 0))) key(scene, pose, hooks);
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
      if (ImGui::Button("Mirror set to the other side")) mirror_set(scene, tolerance, hooks);
      if (edited && !(set == doc.keyposes[current_])) {
        std::sort(set.keys.begin(), set.keys.end(), [](const KeyposeKey& a, const KeyposeKey& b) { return a.values < b.values; });
        if (auto st = validate_keypose_set(set, sk.size(), doc.cage->num_vertices()); !st) {
          hooks.show_error(st.error().message);
          edited = false;
        }
      }
      if (edited && !(set == doc.keyposes[current_])) {
        std::vector<KeyposeSet> sets = doc.keyposes;
        sets[current_] = set;
        commit(scene, with_keyposes(doc, std::move(sets)), edit_label);
      }
      if (remove >= 0) remove_key(scene, static_cast<size_t>(remove), hooks);
    }
  }
  ImGui::End();
}

#else
void RigPanel::draw(Scene&, const Pose&, const Selection&, bool, double, const EditorHooks&) {}
#endif

}  // namespace cagewrap::app
