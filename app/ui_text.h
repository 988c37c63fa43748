// Small Dear ImGui helpers shared by the editor's panels.
#pragma once

#if CAGEWRAP_GUI
#include <cstdarg>

#include <imgui/imgui.h>

namespace cagewrap::app {

// A greyed hint or note that wraps at the window's edge instead of being cut off.
inline void hint(const char* fmt, ...) IM_FMTARGS(1);
inline void hint(const char* fmt, ...) {
  va_list args;
  va_start(args, fmt);
  ImGui::PushTextWrapPos(0.0f);
  ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
  ImGui::TextV(fmt, args);
  ImGui::PopStyleColor();
  ImGui::PopTextWrapPos();
  va_end(args);
}

// SameLine when a small button labelled `label` still fits on this line of the window, else a new line
// (a row of buttons wraps instead of running past the panel's edge).
inline void same_line_for(const char* label) {
  const ImGuiStyle& st = ImGui::GetStyle();
  const float w = ImGui::CalcTextSize(label).x + 2.0f * st.FramePadding.x;
  const float right = ImGui::GetWindowPos().x + ImGui::GetWindowContentRegionMax().x;
  if (ImGui::GetItemRectMax().x + st.ItemSpacing.x + w <= right) ImGui::SameLine();
}

// The width that leaves room for `label` beside a field (for SetNextItemWidth / PushItemWidth).
inline float width_beside(const char* label) {
  return -(ImGui::CalcTextSize(label).x + 2 * ImGui::GetStyle().ItemInnerSpacing.x);
}

// ImGui::Combo whose chosen item, when it is wider than the box, is shown whole in a tooltip while
// the mouse is over it (a label is never silently cut).
inline bool combo(const char* label, int* current, const char* const items[], int count) {
  const float box = ImGui::CalcItemWidth() - ImGui::GetFrameHeight() - 2 * ImGui::GetStyle().FramePadding.x;
  const bool changed = ImGui::Combo(label, current, items, count);
  if (ImGui::IsItemHovered() && *current >= 0 && *current < count && ImGui::CalcTextSize(items[*current]).x > box)
    ImGui::SetTooltip("%s", items[*current]);
  return changed;
}

}  // namespace cagewrap::app

#endif  // CAGEWRAP_GUI
