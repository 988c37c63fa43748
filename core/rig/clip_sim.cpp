#include "core/rig/clip_sim.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "core/base/check.h"
#include "core/character/skinning.h"

namespace cagewrap {

ClipSimulation::ClipSimulation() = default;
ClipSimulation::ClipSimulation(ClipSimulation&&) noexcept = default;
ClipSimulation& ClipSimulation::operator=(ClipSimulation&&) noexcept = default;
ClipSimulation::~ClipSimulation() = default;

Result<ClipSimulation> ClipSimulation::create(const Document& doc, const CageAttachment* attachment, int32_t clip) {
  if (!doc.cage || !doc.character)
    return make_error(ErrorCode::kInvalidArgument, "simulation: the document has no cage to simulate");
  const Character& ch = *doc.character;
  if (clip < 0 || static_cast<size_t>(clip) >= ch.clips.size())
    return make_error(ErrorCode::kIndexOutOfRange, "simulation: clip " + std::to_string(clip) +
                                                       " is out of range (the character has " +
                                                       std::to_string(ch.clips.size()) + " clips)");
  if (auto s = validate_sim_settings(doc.sim, doc.cage->num_vertices(), ch.skeleton.size()); !s) return s.error();
  auto sim = CageSim::create(doc.cage->polygons, doc.cage_positions(), doc.sim);
  if (!sim) return sim.error();
  ClipSimulation out;
  out.doc_ = doc;
  if (attachment) out.attachment_ = *attachment;
  out.clip_ = clip;
  out.sim_ = std::make_unique<CageSim>(std::move(sim).value());
  const double duration = ch.clips[clip].duration, fr = doc.sim.params.frame_rate;
  const size_t last = static_cast<size_t>(std::ceil(duration * fr - 1e-9));
  for (size_t k = 0; k <= last; ++k) out.times_.push_back(std::min(static_cast<double>(k) / fr, duration));
  if (doc.sim.params.skeleton_colliders && out.attachment_)
    out.capsules_ = skeleton_capsules(ch, out.attachment_->skin, doc.sim.params.skeleton_radius_scale);
  out.rest_globals_ = ch.skeleton.global_transforms(ch.skeleton.rest_pose());
  // the free vertices' frames are refitted from the one-rings of the valid elements
  const auto rest = doc.cage_positions();
  const std::vector<ElementStatus> status = classify_elements(*doc.cage, rest);
  std::vector<Tri> valid;
  for (size_t e = 0; e < status.size(); ++e)
    if (status[e] == ElementStatus::kValid) valid.push_back(doc.cage->elements[e]);
  out.fit_ = std::make_unique<OneRingFit>(rest, valid);
  out.fitted_.resize(rest.size());
  return out;
}

bool ClipSimulation::fits(const Document& doc) const { return same_cage_motion(doc_, doc); }

void ClipSimulation::targets_at(double t) {
  const Character& ch = *doc_.character;
  pose_document_cage(doc_, attachment_ ? &*attachment_ : nullptr, compose_pose(ch, clip_, t, false), posed_);
  joints_.clear();
  if (!capsules_.empty()) {
    joints_.resize(ch.skins[attachment_->skin].joints.size());
    joint_matrices(ch.skins[attachment_->skin], posed_.globals, joints_);
  }
  pose_colliders(doc_.sim.colliders, capsules_, posed_.globals, rest_globals_, joints_, shapes_);
}

size_t ClipSimulation::advance(size_t max_frames, double budget_ms) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  size_t made = 0;
  const size_t nv = sim_->num_vertices();
  while (made < max_frames && !done()) {
    const size_t f = offsets_.size();
    targets_at(times_[f]);
    const auto t0 = Clock::now();
    if (!started_) {
      sim_->reset(posed_.positions, shapes_);
      const auto hold = static_cast<size_t>(std::llround(doc_.sim.params.preroll * doc_.sim.params.frame_rate));
      for (size_t i = 0; i < hold; ++i) sim_->step_frame(posed_.positions, shapes_);
      started_ = true;
    } else {
      sim_->step_frame(posed_.positions, shapes_);
    }
    SimFrameStats st;
    st.ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    std::vector<glm::vec3> off(nv);
    const auto x = sim_->positions();
    for (size_t v = 0; v < nv; ++v) {
      // a pinned vertex sits on its target exactly: its displacement is exactly zero
      off[v] = sim_->pinned(v) ? glm::vec3(0.0f) : glm::vec3(x[v] - glm::dvec3(posed_.positions[v]));
      st.max_offset = std::max(st.max_offset, static_cast<double>(glm::length(off[v])));
    }
    st.energy = sim_->energy();
    st.edge_strain = sim_->max_edge_strain();
    offsets_.push_back(std::move(off));
    stats_.push_back(st);
    ++made;
    if (budget_ms > 0.0 && std::chrono::duration<double, std::milli>(Clock::now() - start).count() >= budget_ms) break;
  }
  return made;
}

size_t ClipSimulation::frames_needed(double t) const {
  const double f = std::clamp(t * doc_.sim.params.frame_rate, 0.0, static_cast<double>(frames_total() - 1));
  return std::min(static_cast<size_t>(std::ceil(f)), frames_total() - 1) + 1;
}

void ClipSimulation::apply(double t, PosedCage& cage) {
  CAGEWRAP_CHECK(frames_done() >= frames_needed(t), "ClipSimulation::apply: the frames at t are not simulated yet");
  CAGEWRAP_CHECK(cage.positions.size() == sim_->num_vertices(), "ClipSimulation::apply: a cage of another size");
  const double f = std::clamp(t * doc_.sim.params.frame_rate, 0.0, static_cast<double>(frames_total() - 1));
  const size_t f0 = static_cast<size_t>(std::floor(f));
  const size_t f1 = std::min(f0 + 1, frames_total() - 1);
  const float s = static_cast<float>(f - static_cast<double>(f0));
  const std::span<const glm::vec3> a = offsets_[f0];
  const size_t nv = cage.positions.size();
  if (s == 0.0f || f1 == f0) {  // on a frame: frame f0 + 1 may not be simulated yet
    for (size_t v = 0; v < nv; ++v) cage.positions[v] += a[v];
  } else {
    const std::span<const glm::vec3> b = offsets_[f1];
    for (size_t v = 0; v < nv; ++v) cage.positions[v] += a[v] + (b[v] - a[v]) * s;
  }
  if (sim_->num_free() == 0 || !cage.attached) return;
  fit_->fit(cage.positions, fitted_);
  for (size_t v = 0; v < nv; ++v)
    if (!sim_->pinned(v)) cage.linear[v] = fitted_[v];
}

Result<ClipSimulation*> SimCache::get(const Document& doc, const CageAttachment* attachment, int32_t clip) {
  auto it = clips_.find(clip);
  if (it != clips_.end() && it->second->fits(doc)) return it->second.get();
  auto made = ClipSimulation::create(doc, attachment, clip);
  if (!made) {
    clips_.erase(clip);
    return made.error();
  }
  auto& slot = clips_[clip];
  slot = std::make_unique<ClipSimulation>(std::move(made).value());
  return slot.get();
}

Status pose_simulated_cage(SimCache& cache, const Document& doc, const CageAttachment* attachment, int32_t clip,
                           double t, const Pose& pose, PosedCage& out) {
  pose_document_cage(doc, attachment, pose, out);
  if (!doc.sim.enabled || clip < 0) return Ok{};
  auto sim = cache.get(doc, attachment, clip);
  if (!sim) return sim.error();
  ClipSimulation& s = **sim;
  const size_t need = s.frames_needed(t);
  if (s.frames_done() < need) s.advance(need - s.frames_done());
  s.apply(t, out);
  return Ok{};
}

}  // namespace cagewrap
