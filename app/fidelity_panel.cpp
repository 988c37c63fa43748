#include "app/fidelity_panel.h"
#include "app/ui_text.h"

// The panel lives in the editor only (a build without the GUI has none).
#if CAGEWRAP_GUI
#include <imgui/imgui.h>

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "core/rig/skinning.h"

namespace cagewrap::app {

glm::vec4 fidelity_color(float share) {
  // grey up to 0.5%, yellow at 1%, orange at 2.5%, red from 5%
  const glm::vec4 grey(0.78f, 0.78f, 0.80f, 1), yellow(1.0f, 0.92f, 0.25f, 1), orange(1.0f, 0.55f, 0.1f, 1),
      red(0.9f, 0.1f, 0.1f, 1);
  auto mix = [](const glm::vec4& a, const glm::vec4& b, float t) { return a + (b - a) * std::clamp(t, 0.0f, 1.0f); };
  if (share <= 0.005f) return grey;
  if (share <= 0.01f) return mix(grey, yellow, (share - 0.005f) / 0.005f);
  if (share <= 0.025f) return mix(yellow, orange, (share - 0.01f) / 0.015f);
  return mix(orange, red, (share - 0.025f) / 0.025f);
}

namespace {
std::string joint_label(const Scene& scene, int32_t j) {
  const Skeleton& sk = scene.doc().character->skeleton;
  return j >= 0 && size_t(j) < sk.size() ? sk.node(j).name : std::string("-");
}
std::string doc_key(const Scene& scene) {
  return std::to_string(scene.doc().revision) + "/" + std::to_string(scene.binding_revision) + "/" +
         std::to_string(scene.attachment_revision);
}
}  // namespace

void FidelityPanel::update(Scene& scene, const Playback& pb) {
  const Document& doc = scene.doc();
  if (!scene.deformer || !scene.binding || !doc.cage || doc.character->skins.empty() || pb.show_file_skinning ||
      scene.skin_driven()) {
    frame_.reset();
    colors_.clear();
    key_.clear();
    return;
  }
  char t[64];
  std::snprintf(t, sizeof t, "/%d/%.6f/%zu", pb.clip, pb.player.time(), pb.pose_override.size());
  std::string key = doc_key(scene) + t + (heat_map ? "/h" : "");
  for (const auto& q : pb.pose_override) {
    char r[96];
    std::snprintf(r, sizeof r, "/%a,%a,%a,%a", q.x, q.y, q.z, q.w);  // exact: no two poses share a key
    key += r;
  }
  if (key == key_) return;
  // while the frame keeps changing (playback, a drag) measure at most 4 times a second: the file's
  // skinning and, on the GPU path, a CPU copy of the rig's skin cost a frame's worth at 1M vertices
  const double now = std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  if (pb.player.playing() && now - measured_at_ < 0.25) return;
  measured_at_ = now;
  key_ = key;
  const Character& ch = *doc.character;
  if (character_ != &ch) {
    edges_ = skin_edges(ch);
    joints_ = heaviest_joints(ch);
    character_ = &ch;
    diagonal_ = scene.skin_diagonal;
  }
  const std::vector<glm::vec3>& rig = scene.skin_posed();
  const std::vector<glm::vec3> lbs = skin_character(ch, scene.current_pose(pb));
  if (rig.size() != lbs.size()) {
    frame_.reset();
    colors_.clear();
    return;
  }
  distance_.resize(rig.size());
  FrameFidelity f = compare_skins(rig, lbs, edges_, joints_, diagonal_, FidelityOptions{}.min_edge, distance_);
  f.clip = pb.clip;
  f.time = pb.player.time();
  frame_ = f;
  colors_.clear();
  if (heat_map) {
    colors_.resize(distance_.size());
    for (size_t i = 0; i < distance_.size(); ++i) colors_[i] = fidelity_color(distance_[i]);
  }
}

void FidelityPanel::start_check(const Scene& scene, const EditorHooks& hooks) {
  if (job_ || !scene.doc().cage) return;
  if (scene.doc().character->skins.empty()) {
    hooks.show_error("fidelity: the character has no skin: there is no skinning to compare with");
    return;
  }
  Document doc = with_params(scene.doc(), scene.doc().params);
  FidelityOptions options;
  options.thresholds = thresholds;
  report_key_ = doc_key(scene);
  last_outcome_.clear();
  hooks.log("checking the rig against the file's skinning on every clip ...", false);
  job_ = std::make_unique<BackgroundTask<FidelityReport>>(
      "fidelity", [doc, options](const BackgroundTask<FidelityReport>::Progress& progress,
                                 const std::atomic<bool>& cancel) -> Result<FidelityReport> {
        // a rig of its own: the editor's deformer is not shared across threads
        BindProgress bp;
        bp.cancel = &cancel;
        bp.on_progress = [&progress](double s) { progress("binding", 0.3 * s); };
        auto rig = Rig::create(doc, bp);
        if (!rig) return rig.error();
        FidelityProgress fp;
        fp.cancel = &cancel;
        fp.on_progress = [&progress](double s) { progress("posing", 0.3 + 0.7 * s); };
        return check_fidelity(doc, *rig, options, fp);
      });
}

void FidelityPanel::cancel() {
  if (job_) job_->cancel();
}

void FidelityPanel::scene_changed() {
  cancel();
  job_.reset();  // joins the cancelled check
  frame_.reset();
  distance_.clear();
  colors_.clear();
  edges_.clear();
  joints_.clear();
  character_ = nullptr;
  key_.clear();
  measured_at_ = -1e9;
  report_.reset();
  report_key_.clear();
  last_outcome_.clear();
}

void FidelityPanel::poll(const Scene& scene, const EditorHooks& hooks) {
  if (!job_ || !job_->done()) return;
  auto& r = job_->result();
  if (!r.ok()) {
    last_outcome_ = r.error().code == ErrorCode::kCancelled ? "cancelled" : r.error().message;
    if (r.error().code == ErrorCode::kCancelled) hooks.log("fidelity check cancelled", false);
    else hooks.show_error("fidelity: " + r.error().message);
    job_.reset();
    return;
  }
  report_ = std::move(r).value();
  job_.reset();
  const FidelityReport& rep = *report_;
  char buf[256];
  std::snprintf(buf, sizeof buf, "fidelity, every clip (%zu frames): worst %.2f%%, RMS %.2f%%, stretch %.2fx (%s)",
                rep.overall.frames, 100 * rep.overall.worst.worst, 100 * rep.overall.rms.rms, rep.overall.stretch.stretch,
                rep.passed() ? "within the thresholds" : "over the thresholds");
  hooks.log(buf, false);
  for (const std::string& f : rep.failures(scene.doc().character->skeleton)) hooks.log("warning: fidelity: " + f, false);
}

void FidelityPanel::draw_warning(const Scene& scene, float x, float y) {
  if (!frame_) return;
  const FrameFidelity& f = *frame_;
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
                       100 * f.worst, joint_label(scene, f.worst_joint).c_str(), 100 * f.rms);
  if (stretch)
    ImGui::TextColored(bad, "A skin edge stretched %.1fx the file's skinning near joint '%s'", f.stretch,
                       joint_label(scene, f.stretch_joint).c_str());
  hint("Properties > Fidelity: heat map, check all clips; L shows the file's skinning");
  ImGui::End();
}

void FidelityPanel::draw(Scene& scene, const Playback& pb, const EditorHooks& hooks) {
  if (!scene.doc().cage || scene.doc().character->skins.empty()) return;
  ImGui::Spacing();
  ImGui::TextUnformatted("Fidelity to the file's skinning");
  ImGui::Separator();
  const ImVec4 bad(1.0f, 0.45f, 0.3f, 1), good(0.55f, 0.85f, 0.55f, 1);
  if (frame_) {
    const FrameFidelity& f = *frame_;
    const bool over = f.worst > thresholds.worst || f.rms > thresholds.rms || f.stretch > thresholds.stretch;
    ImGui::Text("this frame: worst %.2f%%, RMS %.2f%%", 100 * f.worst, 100 * f.rms);
    ImGui::Text("edge stretch %.2fx", f.stretch);
    if (over) {
      const bool by_edge = f.stretch > thresholds.stretch && !(f.worst > thresholds.worst);
      ImGui::PushTextWrapPos(0);
      ImGui::TextColored(bad, "Warning: the rig leaves the file's skinning near joint '%s' (%s)",
                         joint_label(scene, by_edge ? f.stretch_joint : f.worst_joint).c_str(),
                         by_edge ? "a skin edge stretched" : "worst vertex");
      ImGui::PopTextWrapPos();
    } else {
      ImGui::TextColored(good, "within the thresholds");
    }
  } else {
    hint(pb.show_file_skinning ? "showing the file's skinning (L)" : "not bound yet");
  }
  ImGui::Checkbox("heat map (distance to the file's skinning)", &heat_map);
  if (job_) {
    ImGui::ProgressBar(static_cast<float>(job_->progress()), ImVec2(-70, 0), job_->stage().c_str());
    ImGui::SameLine();
    if (ImGui::Button("Cancel##fidelity")) job_->cancel();
  } else if (ImGui::Button("Check all clips", ImVec2(-1, 0))) {
    start_check(scene, hooks);
  }
  if (report_) {
    const FidelityReport& r = *report_;
    if (report_key_ != doc_key(scene)) hint("(of an earlier rig: check again)");
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
                            joint_label(scene, c.worst.worst_joint).c_str());
        ImGui::TableNextColumn();
        ImGui::TextColored(c.rms.rms > r.thresholds.rms ? bad : good, "%.2f", 100 * c.rms.rms);
        ImGui::TableNextColumn();
        ImGui::TextColored(c.stretch.stretch > r.thresholds.stretch ? bad : good, "%.2f", c.stretch.stretch);
        if (ImGui::IsItemHovered())
          ImGui::SetTooltip("at %.3f s, joint '%s'", c.stretch.time, joint_label(scene, c.stretch.stretch_joint).c_str());
      };
      for (const ClipFidelity& c : r.clips) row(c);
      row(r.overall);
      ImGui::EndTable();
    }
    ImGui::PushTextWrapPos(0);
    for (const std::string& f : r.failures(scene.doc().character->skeleton)) ImGui::TextColored(bad, "%s", f.c_str());
    ImGui::PopTextWrapPos();
  } else if (!last_outcome_.empty()) {
    hint("last check: %s", last_outcome_.c_str());
  }
}

}  // namespace cagewrap::app

#endif  // CAGEWRAP_GUI
