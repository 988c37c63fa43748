#include "app/sets_panel.h"
#include "app/ui_text.h"

#if CAGEWRAP_GUI
#include <imgui/imgui.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/document/set_queries.h"

namespace cagewrap::app {

namespace {

// Blue (0) -> green -> yellow -> red (1): the heat map's scale, also drawn as the legend.
glm::vec4 heat(float t) {
  t = std::clamp(t, 0.0f, 1.0f);
  const glm::vec3 stops[4] = {{0.15f, 0.25f, 0.85f}, {0.15f, 0.8f, 0.35f}, {0.95f, 0.85f, 0.15f}, {0.9f, 0.15f, 0.1f}};
  const float x = t * 3.0f;
  const int i = std::min(2, static_cast<int>(x));
  return glm::vec4(glm::mix(stops[i], stops[i + 1], x - static_cast<float>(i)), 1.0f);
}

}  // namespace

const std::vector<glm::vec4>& SetsPanel::colors(const Scene& scene, const Selection& sel) {
  const Binding* b = scene.binding.get();
  if (!visible_ || map_ == SetMap::kNone || !b || !scene.doc().cage || b->num_points != scene.skin_rest.size()) {
    colors_.clear();
    colors_key_.clear();
    return colors_;
  }
  std::string key = std::to_string(reinterpret_cast<uintptr_t>(b)) + "/" + std::to_string(static_cast<int>(map_)) + "/" +
                    std::to_string(scene.doc().set_edits.size()) + "/" + std::to_string(scene.doc().revision) + "/";
  if (map_ == SetMap::kInfluence)
    for (uint32_t f : sel.cage_faces) key += std::to_string(f) + ",";
  if (key == colors_key_) return colors_;
  colors_key_ = key;
  colors_.assign(scene.skin_rest.size(), glm::vec4(0.5f, 0.5f, 0.5f, 1.0f));
  if (map_ == SetMap::kInfluence) {
    auto inf = face_influence(*b, *scene.doc().cage, sel.cage_faces);
    if (inf)
      for (size_t i = 0; i < colors_.size(); ++i) colors_[i] = heat((*inf)[i]);
  } else if (map_ == SetMap::kSeparated) {
    uint32_t most = 1;
    for (uint32_t n : b->separated) most = std::max(most, n);
    for (size_t i = 0; i < colors_.size() && i < b->separated.size(); ++i)
      colors_[i] = b->separated[i] ? heat(0.3f + 0.7f * float(b->separated[i]) / float(most)) : glm::vec4(0.55f, 0.55f, 0.6f, 1.0f);
  } else {
    auto ov = set_overview(*b, scene.skin_rest, scene.doc().set_edits);
    if (ov) {
      for (size_t i = 0; i < colors_.size(); ++i) {
        if (map_ == SetMap::kSize) {
          colors_[i] = heat(ov->max_size ? float(ov->size[i]) / float(ov->max_size) : 0.0f);
        } else {
          const uint8_t f = ov->flags[i];
          colors_[i] = (f & kSetEmpty) ? glm::vec4(0.9f, 0.1f, 0.1f, 1) : (f & kSetEdited) ? glm::vec4(0.2f, 0.5f, 1.0f, 1)
                       : (f & kSetOutside) ? glm::vec4(1.0f, 0.65f, 0.1f, 1) : glm::vec4(0.55f, 0.55f, 0.6f, 1);
        }
      }
    }
  }
  return colors_;
}

std::vector<std::pair<uint32_t, float>> SetsPanel::member_face_weights(const Scene& scene, const Selection& sel) const {
  std::vector<std::pair<uint32_t, float>> out;
  if (!visible_ || !scene.binding || !scene.doc().cage || sel.skin_vertices.size() != 1) return out;
  auto ps = point_set(*scene.binding, *scene.doc().cage, sel.skin_vertices.indices()[0], scene.doc().set_edits);
  if (!ps) return out;
  for (const auto& m : ps->members) {
    auto it = std::find_if(out.begin(), out.end(), [&](const auto& p) { return p.first == m.face; });
    if (it == out.end()) out.emplace_back(m.face, m.weight);
    else it->second += m.weight;
  }
  return out;
}

std::vector<uint32_t> SetsPanel::highlighted_faces(const Scene& scene, const Selection& sel) const {
  std::vector<uint32_t> faces;
  if (!visible_ || !scene.binding || !scene.doc().cage || sel.skin_vertices.size() != 1) return faces;
  auto ps = point_set(*scene.binding, *scene.doc().cage, sel.skin_vertices.indices()[0], scene.doc().set_edits);
  if (ps)
    for (const auto& m : ps->members) faces.push_back(m.face);
  return faces;
}

#if CAGEWRAP_GUI

void SetsPanel::draw(Workspace& ws) {
  if (!visible_ || !ws.scene()) return;
  const Scene& scene = *ws.scene();
  const Selection& sel = ws.view.selection;
  auto& tool = ws.view.sets;
  ImGui::SetNextWindowPos(ImVec2(270, 330), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(390, 380), ImGuiCond_FirstUseEver);
  if (!ImGui::Begin("Contributing sets", &visible_)) {
    ImGui::End();
    return;
  }
  const Binding* b = scene.binding.get();
  if (!b || !scene.doc().cage) {
    hint("bind a cage first");
    ImGui::End();
    return;
  }
  int map = static_cast<int>(map_);
  const char* maps[] = {"none", "selected faces' influence", "set size", "empty / edited / outside", "kept apart by separation"};
  if (combo("skin map", &map, maps, 5)) map_ = static_cast<SetMap>(map);
  if (map_ == SetMap::kInfluence || map_ == SetMap::kSize || map_ == SetMap::kSeparated) {  // the legend
    ImDrawList* dl = ImGui::GetWindowDrawList();
    const ImVec2 p = ImGui::GetCursorScreenPos();
    const float w = ImGui::GetContentRegionAvail().x - 80, h = 12;
    for (int i = 0; i < 32; ++i) {
      const glm::vec4 c = heat(i / 31.0f);
      dl->AddRectFilled(ImVec2(p.x + w * i / 32, p.y), ImVec2(p.x + w * (i + 1) / 32, p.y + h), ImGui::ColorConvertFloat4ToU32(ImVec4(c.x, c.y, c.z, 1)));
    }
    ImGui::Dummy(ImVec2(w, h));
    ImGui::SameLine();
    hint(map_ == SetMap::kInfluence ? "0 .. 1" : "low .. high");
  } else if (map_ == SetMap::kFlags) {
    ImGui::TextColored(ImVec4(0.9f, 0.1f, 0.1f, 1), "empty");
    ImGui::SameLine();
    ImGui::TextColored(ImVec4(0.2f, 0.5f, 1, 1), "edited");
    ImGui::SameLine();
    ImGui::TextColored(ImVec4(1, 0.65f, 0.1f, 1), "projects outside every element");
  }
  if (b->separation_applied) hint("separation kept %llu element-point pairs apart", static_cast<unsigned long long>(b->total_separated));
  ImGui::Separator();
  if (sel.skin_vertices.size() == 1) {
    const uint32_t p = sel.skin_vertices.indices()[0];
    auto ps = point_set(*b, *scene.doc().cage, p, scene.doc().set_edits);
    if (ps) {
      ImGui::Text("skin vertex %u: %zu elements%s", p, ps->members.size(), ps->edited ? " (edited)" : "");
      for (const auto& m : ps->members) ImGui::BulletText("element %u (face %u): weight %.3f", m.element, m.face, m.weight);
    }
  } else {
    hint("select one skin vertex (F7) to list its elements and weights");
  }
  ImGui::Separator();
  int mode = static_cast<int>(tool.mode);
  const char* modes[] = {"remove these faces", "add these faces", "only these faces", "reset to automatic"};
  combo("edit", &mode, modes, 4);
  tool.mode = static_cast<SetEditMode>(mode);
  ImGui::Checkbox("mirror (X)", &tool.mirror);
  hint("%zu cage faces selected (F6), %zu skin vertices (F7)", sel.cage_faces.size(), sel.skin_vertices.size());
  ImGui::BeginDisabled(sel.joints.empty());
  if (ImGui::Button("Select the faces of the selected joints' limbs")) select_limb_ = true;
  ImGui::EndDisabled();
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Cage faces whose corners all follow the selected joints (select joints in the outliner)");
  ImGui::BeginDisabled(sel.skin_vertices.empty());
  if (ImGui::Button("Apply to the selected skin vertices", ImVec2(-1, 0)))
    ws.run(std::string("set_edit ") + set_edit_mode_name(tool.mode) + (tool.mirror ? " mirror" : ""));
  ImGui::EndDisabled();
  ImGui::Checkbox("paint on the skin (skin mode, LMB)", &paint_);
  if (tool.brush_radius <= 0.0) tool.brush_radius = 0.03 * scene.skin_diagonal;
  float r = static_cast<float>(tool.brush_radius);
  const float size = static_cast<float>(scene.skin_diagonal);
  ImGui::Checkbox("radius in screen pixels", &screen_radius_);
  if (screen_radius_) {
    float px = static_cast<float>(radius_pixels_);
    if (ImGui::SliderFloat("brush radius (px)", &px, 2.0f, 300.0f, "%.0f")) radius_pixels_ = px;
  } else if (ImGui::SliderFloat("brush radius", &r, 1e-3f * size, 0.3f * size, "%.4f", ImGuiSliderFlags_Logarithmic)) {
    tool.brush_radius = r;
  }
  hint("%zu points have edited sets", scene.doc().set_edits.size());
  ImGui::End();
}

#else
void SetsPanel::draw(Workspace&) {}
#endif

}  // namespace cagewrap::app
