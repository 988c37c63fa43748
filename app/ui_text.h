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

// The width that leaves room for `label` beside a field (for SetNextItemWidth / PushItemWidth).
inline float width_beside(const char* label) {
  return -(ImGui::CalcTextSize(label).x + 2 * ImGui::GetStyle().ItemInnerSpacing.x);
}

}  // namespace cagewrap::app

#endif  // CAGEWRAP_GUI
