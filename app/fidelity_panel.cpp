#include "app/fidelity_panel.h"
#include "app/ui_text.h"

// The panel lives in the editor only (a build without the GUI has none).
#if CAGEWRAP_GUI
#include <imgui/imgui.h>

namespace cagewrap::app {

void FidelityPanel::draw_warning(const Workspace& ws, float x, float y) {
  const auto& frame = ws.fidelity().frame;
  const FidelityThresholds& thresholds = ws.view.fidelity.thresholds;
  if (!frame) return;
  const FrameFidelity& f = *frame;
  const bool worst = f.worst > thresholds.worst, rms = f.rms > thresholds.rms, stretch = f.stretch > thresholds.stretch;
  if (!worst && !rms && !stretch) return;
  ImGui::SetNextWindowPos(ImVec2(x, y), ImGuiCond_Always, ImVec2(0, 1));
  ImGui::SetNextWindowBgAlpha(0.7f);
  ImGui::Begin("fidelity warning", nullptr,
               ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoSavedSettings |
                   ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav | ImGuiWindowFlags_NoInputs);
  const ImVec4 bad(1.0f, 0.45f, 0.3f, 1);
  if (worst || rms)
    ImGui::TextColored(bad, "Not faithful: %.1f%% of the diagonal off the file's skinning near joint '%s' (RMS %.2f%%)",
                       100 * f.worst, ws.joint_name(f.worst_joint).c_str(), 100 * f.rms);
  if (stretch)
    ImGui::TextColored(bad, "A skin edge stretched %.1fx the file's skinning near joint '%s'", f.stretch,
                       ws.joint_name(f.stretch_joint).c_str());
  hint("Properties > Fidelity: heat map, check all clips; L shows the file's skinning");
  ImGui::End();
}

void FidelityPanel::draw(Workspace& ws) {
  const Scene& scene = *ws.scene();
  if (!scene.doc().cage || scene.doc().character->skins.empty()) return;
  const Workspace::FidelityState& state = ws.fidelity();
  const FidelityThresholds& thresholds = ws.view.fidelity.thresholds;
  ImGui::Spacing();
  ImGui::TextUnformatted("Fidelity to the file's skinning");
  ImGui::Separator();
  const ImVec4 bad(1.0f, 0.45f, 0.3f, 1), good(0.55f, 0.85f, 0.55f, 1);
  if (state.frame) {
    const FrameFidelity& f = *state.frame;
    const bool over = f.worst > thresholds.worst || f.rms > thresholds.rms || f.stretch > thresholds.stretch;
    ImGui::Text("this frame: worst %.2f%%, RMS %.2f%%", 100 * f.worst, 100 * f.rms);
    ImGui::Text("edge stretch %.2fx", f.stretch);
    if (over) {
      const bool by_edge = f.stretch > thresholds.stretch && !(f.worst > thresholds.worst);
      ImGui::PushTextWrapPos(0);
      ImGui::TextColored(bad, "Warning: the rig leaves the file's skinning near joint '%s' (%s)",
                         ws.joint_name(by_edge ? f.stretch_joint : f.worst_joint).c_str(),
                         by_edge ? "a skin edge stretched" : "worst vertex");
      ImGui::PopTextWrapPos();
    } else {
      ImGui::TextColored(good, "within the thresholds");
    }
  } else {
    hint(ws.view.playback.show_file_skinning ? "showing the file's skinning (L)" : "not bound yet");
  }
  ImGui::Checkbox("heat map (distance to the file's skinning)", &ws.view.fidelity.heat_map);
  if (state.job) {
    ImGui::ProgressBar(static_cast<float>(state.job->progress()), ImVec2(-70, 0), state.job->stage().c_str());
    ImGui::SameLine();
    if (ImGui::Button("Cancel##fidelity")) ws.cancel_fidelity_check();
  } else if (ImGui::Button("Check all clips", ImVec2(-1, 0))) {
    ws.start_fidelity_check();
  }
  if (state.report) {
    const FidelityReport& r = *state.report;
    if (state.report_key != ws.rig_key()) hint("(of an earlier rig: check again)");
    if (ImGui::BeginTable("fidelity_clips", 4, ImGuiTableFlags_SizingStretchProp | ImGuiTableFlags_RowBg)) {
      ImGui::TableSetupColumn("clip");
      ImGui::TableSetupColumn("worst%");
      ImGui::TableSetupColumn("RMS%");
      ImGui::TableSetupColumn("stretch");
      ImGui::TableHeadersRow();
      auto row = [&](const ClipFidelity& c) {
        ImGui::TableNextRow();
        ImGui::TableNextColumn();
        ImGui::TextUnformatted(c.name.c_str());
        ImGui::TableNextColumn();
        ImGui::TextColored(c.worst.worst > r.thresholds.worst ? bad : good, "%.2f", 100 * c.worst.worst);
        if (ImGui::IsItemHovered())
          ImGui::SetTooltip("at %.3f s, vertex %u, joint '%s'", c.worst.time, c.worst.worst_vertex,
                            ws.joint_name(c.worst.worst_joint).c_str());
        ImGui::TableNextColumn();
        ImGui::TextColored(c.rms.rms > r.thresholds.rms ? bad : good, "%.2f", 100 * c.rms.rms);
        ImGui::TableNextColumn();
        ImGui::TextColored(c.stretch.stretch > r.thresholds.stretch ? bad : good, "%.2f", c.stretch.stretch);
        if (ImGui::IsItemHovered())
          ImGui::SetTooltip("at %.3f s, joint '%s'", c.stretch.time, ws.joint_name(c.stretch.stretch_joint).c_str());
      };
      for (const ClipFidelity& c : r.clips) row(c);
      row(r.overall);
      ImGui::EndTable();
    }
    ImGui::PushTextWrapPos(0);
    for (const std::string& f : r.failures(scene.doc().character->skeleton)) ImGui::TextColored(bad, "%s", f.c_str());
    ImGui::PopTextWrapPos();
  } else if (!state.outcome.empty()) {
    hint("last check: %s", state.outcome.c_str());
  }
}

}  // namespace cagewrap::app

#endif  // CAGEWRAP_GUI
