#include "app/export_panel.h"

#include <algorithm>
#include "app/ui_text.h"

#if CAGEWRAP_GUI
#include <imgui/imgui.h>
#endif

#include <cstdio>
#include <filesystem>

namespace cagewrap::app {

namespace {

namespace fs = std::filesystem;

const char* format_extension(ExportFormat f) {
  return f == ExportFormat::kGlb ? ".glb" : f == ExportFormat::kObj ? ".obj" : ".json";
}

// The window's content width and its fields' (it sizes itself to them).
constexpr float kWindowWidth = 560.0f, kFieldWidth = kWindowWidth - 110.0f - 88.0f;

FilePurpose format_purpose(ExportFormat f) {
  return f == ExportFormat::kGlb   ? FilePurpose::kExportGlb
         : f == ExportFormat::kObj ? FilePurpose::kExportObj
                                   : FilePurpose::kExportJson;
}

}  // namespace

void ExportPanel::set_output(const std::string& path) {
  request_.out = path;
  std::snprintf(out_field_, sizeof out_field_, "%s", path.c_str());
}

// A file beside the project (or the character) named after it and the mode, never the character
// file itself: hero.cagewrap -> hero_baked-skin.glb.
void ExportPanel::default_output(const Scene& scene) {
  const Document& doc = scene.doc();
  const fs::path base = !doc.project_path.empty() ? fs::path(doc.project_path) : fs::path(doc.character_path);
  const std::string suffix =
      request_.format == ExportFormat::kJson ? "rig" : export_mode_name(request_.options.mode);
  set_output((base.parent_path() / (base.stem().string() + "_" + suffix + format_extension(request_.format)))
                 .string());
}

void ExportPanel::set_format(ExportFormat format) {
  request_.format = format;
  // keep the name, change the extension of a file path (an OBJ folder has none)
  fs::path p(request_.out);
  if (!request_.out.empty() && (p.has_extension() || format != ExportFormat::kObj))
    set_output(p.replace_extension(format_extension(format)).string());
}

ExportRequest ExportPanel::shown_request() const {
  ExportRequest request = request_;
  request.options.clips.clear();
  for (size_t c = 0; c < clip_on_.size(); ++c)
    if (clip_on_[c]) request.options.clips.push_back(static_cast<int32_t>(c));
  return request;
}

void ExportPanel::open(const Scene& scene) {
  visible_ = true;
  const void* character = scene.doc().character.get();
  if (defaults_for_ != character) {
    defaults_for_ = character;
    clip_on_.assign(scene.doc().character->clips.size(), 1);
    default_output(scene);
  }
}

std::optional<ExportPanel::BrowseRequest> ExportPanel::take_browse_request() {
  if (!browse_requested_) return std::nullopt;
  browse_requested_ = false;
  fs::path p(request_.out);
  return BrowseRequest{format_purpose(request_.format), request_.out, p.filename().string()};
}

void ExportPanel::show(const Scene& scene, const ExportRequest& request) {
  open(scene);
  request_ = request;
  set_output(request.out);
  clip_on_.assign(scene.doc().character->clips.size(), 0);
  for (int32_t c : request.options.clips)
    if (c >= 0 && static_cast<size_t>(c) < clip_on_.size()) clip_on_[c] = 1;
}

#if CAGEWRAP_GUI

void ExportPanel::draw(Workspace& ws) {
  if (!visible_ || !ws.scene()) return;
  const Scene& scene = *ws.scene();
  const Workspace::ExportState& state = ws.export_state();
  const auto& job_ = state.job;
  if (defaults_for_ != scene.doc().character.get()) open(scene);  // another document: new defaults
  ImGui::SetNextWindowPos(ImVec2(280, 60), ImGuiCond_FirstUseEver);
  if (!ImGui::Begin("Export", &visible_, ImGuiWindowFlags_AlwaysAutoResize)) {
    ImGui::End();
    return;
  }
  const Character& ch = *scene.doc().character;
  ImGui::BeginDisabled(job_ != nullptr);
  int format = static_cast<int>(request_.format);
  ImGui::TextUnformatted("format");
  ImGui::SameLine(110);
  for (ExportFormat f : {ExportFormat::kGlb, ExportFormat::kObj, ExportFormat::kJson}) {
    if (f != ExportFormat::kGlb) ImGui::SameLine();
    if (ImGui::RadioButton(export_format_name(f), &format, static_cast<int>(f))) set_format(f);
  }
  ImGui::TextDisabled("%s", request_.format == ExportFormat::kGlb
                                ? "binary glTF for engines: the skin and the clips"
                            : request_.format == ExportFormat::kObj
                                ? "one OBJ per frame: F.obj gives F_<clip>_<frame>.obj"
                                : "the cage, its attachment to the skeleton and the keyposes");
  if (request_.format != ExportFormat::kJson) {
    int mode = static_cast<int>(request_.options.mode);
    const char* modes[] = {"baked-animation", "baked-skin", "cage"};
    ImGui::TextUnformatted("mode");
    ImGui::SameLine(110);
    ImGui::SetNextItemWidth(180);
    if (request_.format == ExportFormat::kObj) {
      bool cage = request_.options.mode == ExportMode::kCage;
      if (ImGui::RadioButton("skin", !cage)) request_.options.mode = ExportMode::kBakedAnimation;
      ImGui::SameLine();
      if (ImGui::RadioButton("cage", cage)) request_.options.mode = ExportMode::kCage;
    } else if (combo("##mode", &mode, modes, 3)) {
      request_.options.mode = static_cast<ExportMode>(mode);
    }
    if (request_.format == ExportFormat::kGlb) {
      ImGui::SameLine();
      ImGui::TextDisabled("%s",
                          request_.options.mode == ExportMode::kBakedSkin ? "fitted weights + correctives"
                          : request_.options.mode == ExportMode::kBakedAnimation ? "a morph target per frame"
                                                                                 : "the cage, skinned");
    }
    ImGui::TextUnformatted("clips");
    ImGui::SameLine(110);
    if (clip_on_.size() != ch.clips.size()) clip_on_.assign(ch.clips.size(), 1);
    // the check boxes wrap within the field column, so that many clips make the window taller, not
    // wider than the screen; a long name is shortened (the tooltip has it whole)
    const float right = ImGui::GetCursorScreenPos().x + kFieldWidth;
    for (size_t c = 0; c < ch.clips.size(); ++c) {
      bool on = clip_on_[c] != 0;
      const std::string& name = ch.clips[c].name;
      const std::string shown = name.size() > 24 ? name.substr(0, 22) + ".." : name;
      char label[160];
      std::snprintf(label, sizeof label, "%s (%.1f s)##clip%zu", shown.c_str(), ch.clips[c].duration, c);
      const float w = ImGui::GetFrameHeight() + ImGui::GetStyle().ItemInnerSpacing.x + ImGui::CalcTextSize(label, nullptr, true).x;
      if (c) {
        ImGui::SameLine();
        if (ImGui::GetCursorScreenPos().x + w > right) {
          ImGui::NewLine();
          ImGui::SameLine(110);
        }
      }
      if (ImGui::Checkbox(label, &on)) clip_on_[c] = on;
      if (shown != name && ImGui::IsItemHovered()) ImGui::SetTooltip("%s", name.c_str());
    }
    if (ch.clips.empty()) ImGui::TextDisabled("the character has no clips");
    float fps = static_cast<float>(request_.options.fps);
    ImGui::TextUnformatted("fps");
    ImGui::SameLine(110);
    ImGui::SetNextItemWidth(180);
    if (ImGui::DragFloat("##fps", &fps, 0.5f, 1.0f, 240.0f, "%.1f frames/s", ImGuiSliderFlags_AlwaysClamp))
      request_.options.fps = fps;
    if (request_.format == ExportFormat::kGlb && request_.options.mode != ExportMode::kCage) {
      // the corrective morph targets: the residuals' principal components (0: one per frame)
      int targets = corrective_targets(request_.options);
      ImGui::TextUnformatted("correctives");
      ImGui::SameLine(110);
      ImGui::SetNextItemWidth(180);
      if (ImGui::InputInt("targets##ct", &targets, 1, 4)) request_.options.max_targets = std::clamp(targets, 0, 4096);
      if (ImGui::IsItemHovered())
        ImGui::SetTooltip("at most this many corrective morph targets: the principal components of every frame's residual, "
                          "each frame keyed with its weights; 0: one per frame (exact at the frames, heavy)");
      if (targets > 0 && request_.options.correctives != ExportOptions::Correctives::kPoseDriven) {
        float e = static_cast<float>(request_.options.max_error);
        ImGui::TextUnformatted("");
        ImGui::SameLine(110);
        ImGui::SetNextItemWidth(180);
        if (ImGui::InputFloat("max error##ce", &e, 0.0f, 0.0f, "%.5f")) request_.options.max_error = std::max(0.0f, e);
        if (ImGui::IsItemHovered())
          ImGui::SetTooltip("> 0: the fewest targets (up to the number above) whose largest error over the frames is within this "
                            "length, in the file's units");
      }
    }
    if (request_.format == ExportFormat::kGlb && request_.options.mode == ExportMode::kBakedSkin) {
      // how the targets' weights are made: keyed per frame, or driven by joint angles (docs/pose-correctives.md)
      using C = ExportOptions::Correctives;
      int driven = request_.options.correctives == C::kPoseDriven ? 1 : 0;
      ImGui::TextUnformatted("weights");
      ImGui::SameLine(110);
      ImGui::SetNextItemWidth(180);
      if (ImGui::Combo("##cw", &driven, "keyed per frame\0" "driven by joint angles\0")) {
        request_.options.correctives = driven ? C::kPoseDriven : C::kBaked;
        if (!driven) request_.options.hold_out = -1;
        if (driven) request_.options.max_error = 0.0;
      }
      if (ImGui::IsItemHovered())
        ImGui::SetTooltip("driven by joint angles: each target's weight is a linear function of joint-angle ramps written in the "
                          "mesh's extras, so an engine that drives morph weights from joints corrects new animations");
      if (driven) {
        std::string preview = request_.options.hold_out >= 0 && size_t(request_.options.hold_out) < ch.clips.size()
                                  ? ch.clips[request_.options.hold_out].name
                                  : "none";
        ImGui::TextUnformatted("hold out");
        ImGui::SameLine(110);
        ImGui::SetNextItemWidth(180);
        if (ImGui::BeginCombo("##ho", preview.c_str())) {
          if (ImGui::Selectable("none", request_.options.hold_out < 0)) request_.options.hold_out = -1;
          for (size_t c = 0; c < ch.clips.size(); ++c)
            if (c < clip_on_.size() && clip_on_[c] &&
                ImGui::Selectable((ch.clips[c].name + "##ho" + std::to_string(c)).c_str(), request_.options.hold_out == int32_t(c)))
              request_.options.hold_out = int32_t(c);
          ImGui::EndCombo();
        }
        if (ImGui::IsItemHovered())
          ImGui::SetTooltip("a clip left out of every fit and still exported: its errors in the report are those of an "
                            "animation the export never saw");
      }
    }
    if (request_.format == ExportFormat::kGlb) {
      ImGui::TextUnformatted("");
      ImGui::SameLine(110);
      ImGui::Checkbox("reorder for the GPU##opt", &request_.options.optimize);
      if (ImGui::IsItemHovered())
        ImGui::SetTooltip("triangles in vertex cache order and vertices in fetch order (meshoptimizer); each vertex's source "
                          "index is written as _CAGEWRAP_SOURCE_INDEX");
      ImGui::TextUnformatted("");
      ImGui::SameLine(110);
      ImGui::Checkbox("quantize (KHR_mesh_quantization)##q", &request_.options.quantize);
      if (ImGui::IsItemHovered())
        ImGui::SetTooltip("16-bit positions and morph targets, 8-bit normals, 16-bit weights: about a third smaller; the "
                          "errors reported are measured on the quantized file");
    }
    if (request_.format == ExportFormat::kGlb && request_.options.mode == ExportMode::kBakedSkin) {
      int eight = request_.options.max_influences == 8 ? 1 : 0;
      ImGui::TextUnformatted("joints");
      ImGui::SameLine(110);
      ImGui::SetNextItemWidth(180);
      if (ImGui::Combo("per vertex##mi", &eight, "4 (every runtime)\0" "8 (JOINTS_1 too)\0")) request_.options.max_influences = eight ? 8 : 4;
      if (ImGui::IsItemHovered())
        ImGui::SetTooltip("the fitted skinning weights per vertex: 8 adds a second JOINTS/WEIGHTS set, for engines that read it "
                          "(three.js reads the first only)");
    }
    if (request_.format == ExportFormat::kGlb && request_.options.mode != ExportMode::kBakedAnimation) {
      ImGui::TextUnformatted("keyposes");
      ImGui::SameLine(110);
      ImGui::SetNextItemWidth(180);
      ImGui::SliderInt("poses per key##kp", &request_.options.keypose_steps, 0, 10);
      if (ImGui::IsItemHovered())
        ImGui::SetTooltip(
            "each keypose set swept from rest to each key: baked-skin fits its weights to these poses "
            "too, and the error there is reported");
    }
  }
  ImGui::TextUnformatted("output");
  ImGui::SameLine(110);
  ImGui::SetNextItemWidth(kFieldWidth);
  if (ImGui::InputText("##out", out_field_, sizeof out_field_)) request_.out = out_field_;
  if (ImGui::IsItemHovered() && ImGui::CalcTextSize(out_field_).x > kFieldWidth) ImGui::SetTooltip("%s", out_field_);
  if (ImGui::IsItemHovered() && !request_.out.empty()) ImGui::SetTooltip("%s", request_.out.c_str());
  ImGui::SameLine();
  if (ImGui::Button("Browse...", ImVec2(80, 0))) browse_requested_ = true;
  ImGui::EndDisabled();

  const ExportRequest request = shown_request();
  const std::vector<int32_t>& clips = request.options.clips;
  const bool need_clips = request.format != ExportFormat::kJson;
  const std::string path_problem = check_export_path(request);
  ImGui::Separator();
  if (job_) {
    const std::string stage = job_->stage();
    ImGui::ProgressBar(static_cast<float>(job_->progress()), ImVec2(kWindowWidth - 88, 0),
                       stage.empty() ? "starting" : stage.c_str());
    ImGui::SameLine();
    ImGui::BeginDisabled(job_->cancelling());
    if (ImGui::Button("Cancel", ImVec2(80, 0))) ws.run("export_cancel");
    ImGui::EndDisabled();
  } else {
    const bool ready = path_problem.empty() && (!need_clips || !clips.empty()) && scene.doc().cage;
    ImGui::BeginDisabled(!ready);
    if (ImGui::Button("Export", ImVec2(kWindowWidth, 0))) ws.start_export(request);
    ImGui::EndDisabled();
    const ImVec4 warn(1.0f, 0.6f, 0.3f, 1.0f);
    if (!scene.doc().cage)
      ImGui::TextColored(warn, "the document has no cage yet (Cage menu)");
    else if (need_clips && clips.empty())
      ImGui::TextColored(warn, "choose at least one clip");
    else if (!path_problem.empty())
      ImGui::TextColored(warn, "%s", path_problem.c_str());
  }
  ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + kWindowWidth);
  if (const auto& report = state.report) {
    ImGui::TextColored(ImVec4(0.5f, 0.9f, 0.5f, 1.0f), "exported %s in %.1f s", report->what.c_str(), state.seconds);
    ImGui::TextWrapped("%s", report->summary.c_str());
    if (report->keypose_poses) ImGui::Text("%zu keypose poses measured", report->keypose_poses);
    for (const std::string& line : report->error_lines) ImGui::TextUnformatted(line.c_str());
    for (const std::string& w : report->warnings) ImGui::TextColored(ImVec4(1, 0.8f, 0.3f, 1), "%s", w.c_str());
  } else if (!state.outcome.empty() && !job_) {
    ImGui::TextColored(ImVec4(1, 0.5f, 0.4f, 1), "%s", state.outcome.c_str());
  }
  ImGui::PopTextWrapPos();
  ImGui::End();
}

#else

void ExportPanel::draw(Workspace&) {}

#endif

}  // namespace cagewrap::app
