#include "app/cage_tools.h"
#include "app/ui_text.h"

#if CAGEWRAP_GUI
#include <imgui/imgui.h>
#endif

#include <cstdio>
#include <filesystem>

#include "core/cage/cage_edit.h"
#include "core/cage/cage_import.h"
#include "core/rig/keyposes.h"
#include "core/cage/cage_subdivide.h"
#include "core/rig/skinning.h"

namespace cagewrap::app {

void CageTools::commit_cage(Scene& scene, std::shared_ptr<const Cage> cage, const std::string& label) {
  const Document& before = scene.doc();
  Document d = with_cage(before, std::move(cage));
  // a different cage: sculpted offsets and set edits named the old one's vertices and elements
  if (!d.cage_offsets.empty()) d = with_cage_offsets(d, {});
  if (!d.set_edits.empty()) d = with_set_edits(d, {});
  if (!d.attachment.overrides.empty()) {
    AttachmentSettings a = d.attachment;
    a.overrides.clear();
    d = with_attachment(d, a);
  }
  std::vector<KeyposeSet> sets = d.keyposes;  // drivers and key values stay, their vertices go
  clear_vertex_data(sets);
  if (sets != d.keyposes) d = with_keyposes(d, std::move(sets));
  scene.apply(label, std::move(d));
}

void CageTools::start_auto_cage(Scene& scene) {
  if (job_) return;
  auto character = scene.doc().character;
  AutoCageParams params = params_;
  params.bind = scene.params;
  job_ = std::make_unique<BackgroundTask<AutoCageReport>>(
      "automatic cage", [character, params](const BackgroundTask<AutoCageReport>::Progress& progress, const std::atomic<bool>& cancel) {
        AutoCageProgress p;
        p.on_progress = [&progress](const char* stage, double share) { progress(stage, share); };
        p.cancel = &cancel;
        return build_auto_cage(*character, params, p);
      });
}

void CageTools::poll(Scene& scene, const EditorHooks& hooks) {
  if (!job_ || !job_->done()) return;
  auto& r = job_->result();
  if (!r.ok()) {
    if (r.error().code == ErrorCode::kCancelled) hooks.log("automatic cage cancelled", false);
    else hooks.show_error(r.error().message);
    job_.reset();
    return;
  }
  AutoCageReport report = std::move(r).value();
  job_.reset();
  auto cage = make_cage(report.cage, "automatic cage");
  if (!cage) {
    hooks.show_error(cage.error().message);
    return;
  }
  char buf[320];
  std::snprintf(buf, sizeof buf,
                "automatic cage: %u faces, %u vertices in %.2f s; largest skin-to-cage distance %.4g, %u skin points outside; "
                "cage quality %.1f%%",
                report.faces, report.vertices, report.seconds, report.max_distance, report.outside_points, 100.0 * report.quality);
  hooks.log(buf, false);
  for (const auto& w : report.warnings) hooks.log("warning: " + w, false);
  failing_ = report.failures;
  report.cage = PolyMesh{};  // the document holds it
  report_ = std::move(report);
  show_report_ = true;
  show_dialog_ = false;  // done: the report takes its place
  commit_cage(scene, std::make_shared<const Cage>(std::move(cage).value()), "Automatic cage");
}

bool CageTools::import_cage(Scene& scene, const std::string& path, const EditorHooks& hooks) {
  auto mesh = load_cage_mesh(path);
  if (!mesh) {
    hooks.show_error(mesh.error().message);
    return false;
  }
  if (auto st = validate_mesh(*mesh, path); !st.ok()) {
    hooks.show_error(st.error().message);
    return false;
  }
  auto cage = make_cage(std::move(mesh).value(), path);
  if (!cage) {
    hooks.show_error(cage.error().message);
    return false;
  }
  CageProblems problems = find_cage_problems(*cage);
  hooks.log("imported cage " + path + ": " + std::to_string(cage->num_vertices()) + " vertices, " +
                std::to_string(cage->polygons.num_faces()) + " faces" +
                (problems.total() ? ", " + std::to_string(problems.total()) + " problems (listed below; the bind skips bad elements)" : ", no problems"),
            false);
  for (const auto& l : problems.lines) hooks.log("warning: " + path + ": " + l, false);
  if (problems.lines.size() < problems.total())
    hooks.log("warning: " + path + ": ... and " + std::to_string(problems.total() - problems.lines.size()) + " more", false);
  failing_.clear();
  report_.reset();
  commit_cage(scene, std::make_shared<const Cage>(std::move(cage).value()), "Import cage " + std::filesystem::path(path).filename().string());
  return true;
}

bool CageTools::apply_edit(Scene& scene, Result<CageEdit> edit, const std::string& label, const EditorHooks& hooks) {
  if (!edit) {
    hooks.show_error(edit.error().message);
    return false;
  }
  auto doc = apply_topology_change(scene.doc(), *edit);
  if (!doc) {
    hooks.show_error(doc.error().message);
    return false;
  }
  for (const auto& w : edit->warnings) hooks.log("warning: " + label + ": " + w, false);
  const size_t before = scene.doc().cage->polygons.num_faces();
  scene.apply(label, std::move(doc).value());
  failing_.clear();  // they were found for the old cage
  hooks.log(label + ": " + std::to_string(before) + " -> " + std::to_string(scene.doc().cage->polygons.num_faces()) + " faces, " +
                std::to_string(scene.doc().cage->num_vertices()) + " vertices",
            false);
  return true;
}

bool CageTools::run_operation(Scene& scene, const Selection& sel, const std::string& op, double arg, const EditorHooks& hooks) {
  if (!scene.doc().cage) {
    hooks.show_error("there is no cage to edit: build or import one first (Cage menu)");
    return false;
  }
  const Cage& cage = *scene.doc().cage;
  const auto levels = static_cast<uint32_t>(arg > 0 ? arg : 1);
  if (op == "merge") return apply_edit(scene, merge_vertices(cage, sel.cage_vertices.indices()), "Merge vertices", hooks);
  if (op == "weld") return apply_edit(scene, weld_cage_vertices(cage, arg), "Weld vertices", hooks);
  if (op == "flip") return apply_edit(scene, flip_faces(cage, sel.cage_faces.indices()), "Flip faces", hooks);
  if (op == "flip_all") return apply_edit(scene, flip_all_faces(cage), "Flip all faces", hooks);
  if (op == "linear") return apply_edit(scene, subdivide_linear(cage, levels), "Subdivide (linear)", hooks);
  if (op == "loop") return apply_edit(scene, subdivide_loop(cage, levels), "Subdivide (Loop)", hooks);
  if (op == "refine") return apply_edit(scene, refine_faces(cage, sel.cage_faces.indices()), "Refine faces", hooks);
  if (op == "triangulate") return apply_edit(scene, triangulate_cage(cage), "Triangulate", hooks);
  hooks.show_error("unknown cage operation '" + op + "'");
  return false;
}

#if CAGEWRAP_GUI

void CageTools::menu_items(Scene& scene, const Selection& sel, const EditorHooks& hooks) {
  if (ImGui::MenuItem("Automatic cage...", nullptr, false, !job_)) show_dialog_ = true;
  if (ImGui::MenuItem("Import cage... (also in File)")) import_requested_ = true;
  ImGui::Separator();
  const bool cage = scene.doc().cage != nullptr && !job_;
  if (ImGui::MenuItem("Merge selected vertices", nullptr, false, cage && sel.cage_vertices.size() >= 2))
    run_operation(scene, sel, "merge", 0, hooks);
  if (ImGui::BeginMenu("Weld by distance", cage)) {
    ImGui::SliderFloat("distance (% of size)", &weld_distance_share_, 0.01f, 5.0f, "%.2f", ImGuiSliderFlags_Logarithmic);
    if (ImGui::MenuItem("Weld")) {
      const double size = bounding_box(scene.doc().cage->polygons.positions).diagonal();
      run_operation(scene, sel, "weld", weld_distance_share_ / 100.0 * size, hooks);
    }
    ImGui::EndMenu();
  }
  if (ImGui::MenuItem("Flip selected faces", nullptr, false, cage && !sel.cage_faces.empty())) run_operation(scene, sel, "flip", 0, hooks);
  if (ImGui::MenuItem("Flip all faces", nullptr, false, cage)) run_operation(scene, sel, "flip_all", 0, hooks);
  ImGui::Separator();
  if (ImGui::MenuItem("Subdivide (linear)", nullptr, false, cage)) run_operation(scene, sel, "linear", 1, hooks);
  if (ImGui::MenuItem("Subdivide (Loop, smooths)", nullptr, false, cage)) run_operation(scene, sel, "loop", 1, hooks);
  if (ImGui::MenuItem("Refine selected faces (red-green)", nullptr, false, cage && !sel.cage_faces.empty()))
    run_operation(scene, sel, "refine", 0, hooks);
  if (ImGui::MenuItem("Triangulate", nullptr, false, cage)) run_operation(scene, sel, "triangulate", 0, hooks);
  ImGui::Separator();
  ImGui::MenuItem("Show points failing the quality test", nullptr, &show_failing_, !failing_.empty());
  if (ImGui::MenuItem("Last automatic cage report", nullptr, false, report_.has_value())) show_report_ = true;
  (void)scene;
}

void CageTools::draw_windows(Scene& scene, const EditorHooks&) {
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
      if (ImGui::Combo("offset wrap", &wrap, wraps, 3)) params_.wrap = static_cast<WrapMode>(wrap);
      const bool valid = validate(params_).ok();
      if (job_) {
        const std::string stage = job_->stage();
        ImGui::ProgressBar(static_cast<float>(job_->progress()), ImVec2(-70, 0), stage.empty() ? "building" : stage.c_str());
        ImGui::SameLine();
        if (ImGui::Button("Cancel")) job_->cancel();
      } else {
        ImGui::BeginDisabled(!valid);
        if (ImGui::Button("Build", ImVec2(-1, 0))) start_auto_cage(scene);
        ImGui::EndDisabled();
        if (!valid) ImGui::TextColored(ImVec4(1, 0.5f, 0.3f, 1), "%s", validate(params_).error().message.c_str());
      }
    }
    ImGui::End();
  }
  if (show_report_ && report_) {
    const AutoCageReport& r = *report_;
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
      if (!failing_.empty()) {
        ImGui::Checkbox("show the failing points in the viewport (red)", &show_failing_);
        ImGui::SameLine();
        hint("%zu points", failing_.size());
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

void CageTools::menu_items(Scene&, const Selection&, const EditorHooks&) {}
void CageTools::draw_windows(Scene&, const EditorHooks&) {}

#endif

}  // namespace cagewrap::app
