// The workspace's fidelity to the file's skinning (app/workspace/workspace.h "fidelity"; core/rig/fidelity.h):
// the current frame's figures and heat map, and the check of every clip in the background. The
// Properties window's Fidelity section, the view's warning and the actions heatmap, fidelity_check,
// fidelity_cancel and fidelity_frame show and run these.
#include <algorithm>
#include <chrono>
#include <cstdio>

#include "app/workspace/workspace.h"
#include "core/character/skinning.h"

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

std::string Workspace::rig_key() const {
  if (!scene_) return {};
  return std::to_string(scene_->work().revision) + "/" + std::to_string(scene_->binding_revision) + "/" +
         std::to_string(scene_->attachment_revision);
}

std::string Workspace::joint_name(int32_t joint) const {
  if (!scene_) return "-";
  const Skeleton& sk = scene_->doc().character->skeleton;
  return joint >= 0 && size_t(joint) < sk.size() ? sk.node(size_t(joint)).name : std::string("-");
}

void Workspace::measure_fidelity() {
  FidelityState& f = fidelity_;
  const Playback& pb = view.playback;
  auto none = [&f] {
    f.frame.reset();
    f.colors.clear();
    f.key.clear();
  };
  if (!scene_) return none();
  Scene& scene = *scene_;
  const Document& doc = scene.doc();
  if (!scene.deformer || !scene.binding || !doc.cage || doc.character->skins.empty() || pb.show_file_skinning ||
      scene.skin_driven())
    return none();
  char t[64];
  std::snprintf(t, sizeof t, "/%d/%.6f/%zu", pb.clip, pb.player.time(), pb.pose_override.size());
  std::string key = rig_key() + t + (view.fidelity.heat_map ? "/h" : "");
  for (const auto& q : pb.pose_override) {
    char r[96];
    std::snprintf(r, sizeof r, "/%a,%a,%a,%a", q.x, q.y, q.z, q.w);  // exact: no two poses share a key
    key += r;
  }
  if (key == f.key) return;
  // while the frame keeps changing (playback, a drag) measure at most 4 times a second: the file's
  // skinning and, on the GPU path, a CPU copy of the rig's skin cost a frame's worth at 1M vertices
  const double now = std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  if (pb.player.playing() && now - f.measured_at < 0.25) return;
  f.measured_at = now;
  f.key = key;
  const Character& ch = *doc.character;
  if (f.character != &ch) {
    f.edges = skin_edges(ch);
    f.joints = heaviest_joints(ch);
    f.character = &ch;
  }
  const std::vector<glm::vec3>& rig = scene.skin_posed();
  const std::vector<glm::vec3> lbs = skin_character(ch, scene.current_pose(pb));
  if (rig.size() != lbs.size()) {
    f.frame.reset();
    f.colors.clear();
    return;
  }
  f.distance.resize(rig.size());
  FrameFidelity frame = compare_skins(rig, lbs, f.edges, f.joints, scene.skin_diagonal, FidelityOptions{}.min_edge, f.distance);
  frame.clip = pb.clip;
  frame.time = pb.player.time();
  f.frame = frame;
  f.colors.clear();
  if (view.fidelity.heat_map) {
    f.colors.resize(f.distance.size());
    for (size_t i = 0; i < f.distance.size(); ++i) f.colors[i] = fidelity_color(f.distance[i]);
  }
}

bool Workspace::start_fidelity_check(bool nowait) {
  FidelityState& f = fidelity_;
  if (!scene_) return false;
  if (f.job) {
    fail("fidelity: a check is running already: wait for it or cancel it");
    return false;
  }
  if (!scene_->doc().cage) {
    fail("fidelity: the document has no cage yet: build or import one first (Cage menu)");
    return false;
  }
  if (scene_->doc().character->skins.empty()) {
    report_error("fidelity: the character has no skin: there is no skinning to compare with");
    return false;
  }
  Document doc = scene_->work();  // every deformer
  FidelityOptions options;
  options.thresholds = view.fidelity.thresholds;
  f.report_key = rig_key();
  f.outcome.clear();
  f.nowait = nowait;
  std::shared_ptr<const Binding> bound = scene_->binding_for_jobs();
  log(std::string("checking the rig against the file's skinning on every clip") +
      (bound ? " (with the current binding)" : "") + " ...");
  f.job = std::make_unique<BackgroundTask<FidelityReport>>(
      "fidelity", [doc, options, bound](const BackgroundTask<FidelityReport>::Progress& progress,
                                        const std::atomic<bool>& cancel) -> Result<FidelityReport> {
        // a rig of its own (the editor's deformer is not shared across threads), from the scene's
        // binding when it is the document's, else bound here
        const double bind_share = bound ? 0.0 : 0.3;
        BindProgress bp;
        bp.cancel = &cancel;
        bp.on_progress = [&progress, bind_share](double s) { progress("binding", bind_share * s); };
        auto rig = bound ? Rig::create(doc, Binding(*bound)) : Rig::create(doc, bp);
        if (!rig) return rig.error();
        FidelityProgress fp;
        fp.cancel = &cancel;
        fp.on_progress = [&progress, bind_share](double s) { progress("posing", bind_share + (1.0 - bind_share) * s); };
        return check_fidelity(doc, *rig, options, fp);
      });
  return true;
}

void Workspace::cancel_fidelity_check() {
  if (fidelity_.job) fidelity_.job->cancel();
}

void Workspace::poll_fidelity() {
  FidelityState& f = fidelity_;
  if (!f.job || !f.job->done()) return;
  auto job = std::move(f.job);
  auto& r = job->result();
  if (!r.ok()) {
    f.outcome = r.error().code == ErrorCode::kCancelled ? "cancelled" : r.error().message;
    if (r.error().code == ErrorCode::kCancelled) log("fidelity check cancelled");
    else report_error("fidelity: " + r.error().message);
    return;
  }
  f.report = std::move(r).value();
  const FidelityReport& rep = *f.report;
  char buf[256];
  std::snprintf(buf, sizeof buf, "fidelity, every clip (%zu frames): worst %.2f%%, RMS %.2f%%, stretch %.2fx (%s)",
                rep.overall.frames, 100 * rep.overall.worst.worst, 100 * rep.overall.rms.rms, rep.overall.stretch.stretch,
                rep.passed() ? "within the thresholds" : "over the thresholds");
  log(buf);
  if (scene_)
    for (const std::string& line : rep.failures(scene_->doc().character->skeleton)) log("warning: fidelity: " + line);
}

void Workspace::reset_fidelity() {
  cancel_fidelity_check();
  fidelity_ = FidelityState{};  // joins the cancelled check; what was measured indexed the old skin
}

}  // namespace cagewrap::app
