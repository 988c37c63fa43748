#include "app/cage_tools.h"
#include "app/ui_text.h"

#if CAGEWRAP_GUI
#include <imgui/imgui.h>
#endif

#include <cstdio>

#include "core/geometry/mesh.h"

namespace cagewrap::app {

std::span<const uint32_t> CageTools::failing_points(const Workspace& ws) const {
  if (!show_failing_ || !has_failing_points(ws)) return {};
  return ws.auto_cage_state().report->failures;
}

bool CageTools::has_failing_points(const Workspace& ws) const {
  const auto& state = ws.auto_cage_state();
  return ws.scene() && state.cage && ws.scene()->doc().cage == state.cage && state.report && !state.report->failures.empty();
}

#if CAGEWRAP_GUI

void CageTools::menu_items(Workspace& ws) {
  const Scene& scene = *ws.scene();
  const Selection& sel = ws.view.selection;
  const bool building = ws.building_cage();
  if (ImGui::MenuItem("Automatic cage...", nullptr, false, !building)) show_dialog_ = true;
  if (ImGui::MenuItem("Import cage... (also in File)")) import_requested_ = true;
  ImGui::Separator();
  const bool cage = scene.doc().cage != nullptr && !building;
  if (ImGui::MenuItem("Merge selected vertices", nullptr, false, cage && sel.cage_vertices.size() >= 2)) ws.run("cage_op merge");
  if (ImGui::BeginMenu("Weld by distance", cage)) {
    ImGui::SliderFloat("distance (% of size)", &weld_distance_share_, 0.01f, 5.0f, "%.2f", ImGuiSliderFlags_Logarithmic);
    if (ImGui::MenuItem("Weld")) {
      char line[64];
      std::snprintf(line, sizeof line, "cage_op weld %.9g", weld_distance_share_ / 100.0 * bounding_box(scene.doc().cage->polygons.positions).diagonal());
      ws.run(line);
    }
    ImGui::EndMenu();
  }
  if (ImGui::MenuItem("Flip selected faces", nullptr, false, cage && !sel.cage_faces.empty())) ws.run("cage_op flip");
  if (ImGui::MenuItem("Flip all faces", nullptr, false, cage)) ws.run("cage_op flip_all");
  ImGui::Separator();
  if (ImGui::MenuItem("Subdivide (linear)", nullptr, false, cage)) ws.run("cage_op linear");
  if (ImGui::MenuItem("Subdivide (Loop, smooths)", nullptr, false, cage)) ws.run("cage_op loop");
  if (ImGui::MenuItem("Refine selected faces (red-green)", nullptr, false, cage && !sel.cage_faces.empty())) ws.run("cage_op refine");
  if (ImGui::MenuItem("Triangulate", nullptr, false, cage)) ws.run("cage_op triangulate");
  ImGui::Separator();
  ImGui::MenuItem("Show points failing the quality test", nullptr, &show_failing_, has_failing_points(ws));
  if (ImGui::MenuItem("Last automatic cage report", nullptr, false, ws.auto_cage_state().report.has_value())) show_report_ = true;
}

void CageTools::draw_windows(Workspace& ws) {
  const auto& state = ws.auto_cage_state();
  if (state.builds != shown_builds_) {  // a build ended: its report takes the dialog's place
    shown_builds_ = state.builds;
    show_report_ = true;
    show_dialog_ = false;
  }
  const auto& job_ = state.job;
  if (show_dialog_) {
    ImGui::SetNextWindowPos(ImVec2(280, 130), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(380, 0), ImGuiCond_FirstUseEver);
    if (ImGui::Begin("Automatic cage", &show_dialog_)) {
      ImGui::TextWrapped("Builds a closed cage around the character in its bind pose (joined, welded, decimated, inflated).");
      int faces = static_cast<int>(params_.target_faces);
      if (ImGui::DragInt("faces (triangles)", &faces, 10.0f, 50, 100000)) params_.target_faces = static_cast<uint32_t>(std::max(50, faces));
      float detail = static_cast<float>(params_.joint_detail), radius = static_cast<float>(params_.joint_radius),
            inflate = static_cast<float>(params_.inflate);
      if (ImGui::SliderFloat("joint detail", &detail, 0.0f, 4.0f, "%.2f")) params_.joint_detail = detail;
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("0 = uniform; larger keeps more faces near the joints");
      if (ImGui::SliderFloat("joint radius", &radius, 0.005f, 0.2f, "%.3f", ImGuiSliderFlags_Logarithmic)) params_.joint_radius = radius;
      if (ImGui::SliderFloat("inflate", &inflate, 0.0f, 0.05f, "%.4f")) params_.inflate = inflate;
      ImGui::Checkbox("inflate in scene units (else share of the size)", &params_.inflate_absolute);
      ImGui::Checkbox("push out where skin points are outside", &params_.fit_skin);
      int wrap = static_cast<int>(params_.wrap);
      const char* wraps[] = {"auto", "always wrap", "never wrap"};
      if (combo("offset wrap", &wrap, wraps, 3)) params_.wrap = static_cast<WrapMode>(wrap);
      const bool valid = validate(params_).ok();
      if (job_) {
        const std::string stage = job_->stage();
        ImGui::ProgressBar(static_cast<float>(job_->progress()), ImVec2(-70, 0), stage.empty() ? "building" : stage.c_str());
        ImGui::SameLine();
        if (ImGui::Button("Cancel")) ws.cancel_auto_cage();
      } else {
        ImGui::BeginDisabled(!valid);
        if (ImGui::Button("Build", ImVec2(-1, 0))) ws.start_auto_cage(params_);
        ImGui::EndDisabled();
        if (!valid) ImGui::TextColored(ImVec4(1, 0.5f, 0.3f, 1), "%s", validate(params_).error().message.c_str());
      }
    }
    ImGui::End();
  }
  if (show_report_ && state.report) {
    const AutoCageReport& r = *state.report;
    ImGui::SetNextWindowPos(ImVec2(280, 400), ImGuiCond_FirstUseEver);
    if (ImGui::Begin("Automatic cage report", &show_report_, ImGuiWindowFlags_AlwaysAutoResize)) {
      ImGui::PushTextWrapPos(ImGui::GetFontSize() * 36.0f);
      ImGui::Text("%u faces, %u vertices, built in %.2f s (+%.2f s to bind for the figures)", r.faces, r.vertices, r.seconds, r.bind_seconds);
      ImGui::Text("input: %u vertices, %u triangles; %u after welding%s", r.input_vertices, r.input_triangles, r.welded_vertices,
                  r.wrapped ? "; wrapped by an offset surface" : "");
      ImGui::Text("largest skin-to-cage distance %.4g; %u skin points outside (worst by %.3g)", r.max_distance, r.outside_points, r.max_outside);
      const bool good = r.quality >= 0.95;
      ImGui::TextColored(good ? ImVec4(0.5f, 0.9f, 0.5f, 1) : ImVec4(1, 0.7f, 0.3f, 1), "cage quality %.1f%%", 100.0 * r.quality);
      hint("share of skin points close to an element and projecting inside it (algorithm.md section 4)");
      if (!r.failures.empty()) {
        ImGui::Checkbox("show the failing points in the viewport (red)", &show_failing_);
        ImGui::SameLine();
        hint("%zu points", r.failures.size());
      }
      ImGui::TextWrapped("%s", r.check.summary().c_str());
      for (const auto& w : r.warnings) {
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1, 0.8f, 0.3f, 1));
        ImGui::TextWrapped("%s", w.c_str());
        ImGui::PopStyleColor();
      }
      ImGui::PopTextWrapPos();
    }
    ImGui::End();
  }
}

#else

void CageTools::menu_items(Workspace&) {}
void CageTools::draw_windows(Workspace&) {}

#endif

}  // namespace cagewrap::app
