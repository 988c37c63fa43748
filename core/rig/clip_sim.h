// The simulated cage of one clip, cached: core/cage/cage_sim.h run over a clip's frames, frame by frame,
// with the document's posed cage (core/rig/rig.h pose_document_cage) as the targets and its colliders
// (plus the skeleton's capsules) posed with the skeleton. Each frame stores the displacement of
// every cage vertex from its target (#Vc, world space; exactly zero for a pinned vertex), so that
// at any clip time
//   D_v(t) = target_v(t) + interpolate(displacement_v, frames around t)
// and a pinned vertex is its skinned position exactly, between frames too.
//
// Frames sit at k / frame_rate for k = 0 .. ceil(duration * frame_rate), the last at the clip's
// end; the simulation starts at rest on frame 0's pose, held for `preroll` seconds first. A clip
// time past the end (a looping player wraps) reads the last frame. The vertex frames of the
// extended variant are refitted from the one-rings for the free vertices (their cage moves
// unlike any bone); pinned vertices keep the skeleton's.
//
// SimCache keeps one ClipSimulation per clip and drops it when anything it depends on changed: the
// character, the cage, the offsets, the attachment, the keyposes or the simulation settings.
// Filling is incremental (advance a few frames at a time), so the editor keeps drawing while it runs.
#pragma once

#include <atomic>
#include <chrono>
#include <map>
#include <optional>
#include <memory>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "core/cage/cage_sim.h"
#include "core/document/document.h"
#include "core/rig/rig.h"
#include "core/deform/vertex_frames.h"

namespace cagewrap {

struct SimFrameStats {
  double ms = 0.0;             // wall time of the frame's solve (the substeps only, not the posing)
  double max_offset = 0.0;     // largest |displacement| from the skinned position (m)
  double energy = 0.0;         // CageSim::energy after the frame
  double edge_strain = 0.0;    // CageSim::max_edge_strain after the frame
};

class ClipSimulation {
 public:
  // Fails when the document has no cage, the clip index is out of range or the simulation settings
  // are invalid (the message names the vertex or collider).
  static Result<ClipSimulation> create(const Document& doc, const CageAttachment* attachment, int32_t clip);

  // Simulates up to `max_frames` more frames (the first call also runs the pre-roll), stopping early
  // when `budget_ms` > 0 of wall time is spent; returns how many it made.
  size_t advance(size_t max_frames, double budget_ms = 0.0);
  // Simulates every remaining frame.
  void complete() { advance(frames_total()); }

  size_t frames_total() const { return times_.size(); }
  size_t frames_done() const { return offsets_.size(); }
  bool done() const { return frames_done() == frames_total(); }
  double frame_time(size_t f) const { return times_[f]; }
  // The frames a clip time needs (the two around it), clamped to the clip.
  size_t frames_needed(double t) const;
  // #Vc displacements of frame f (< frames_done()).
  std::span<const glm::vec3> offsets(size_t f) const { return offsets_[f]; }
  std::span<const SimFrameStats> stats() const { return stats_; }
  const CageSim& solver() const { return *sim_; }

  // Adds the displacement at clip time t to a cage posed at that time (frames_needed(t) must be
  // done: checked) and refits the free vertices' linear parts.
  void apply(double t, PosedCage& cage);

  // Whether it was made from this document's inputs (see the file comment).
  bool fits(const Document& doc) const;
  int32_t clip() const { return clip_; }

  ClipSimulation(ClipSimulation&&) noexcept;
  ClipSimulation& operator=(ClipSimulation&&) noexcept;
  ~ClipSimulation();

 private:
  ClipSimulation();
  void targets_at(double t);  // poses the cage and the colliders into posed_ / shapes_

  Document doc_;
  std::optional<CageAttachment> attachment_;  // a copy: the caller's may be replaced meanwhile
  int32_t clip_ = -1;
  std::vector<double> times_;
  std::unique_ptr<CageSim> sim_;
  std::vector<BoneCapsule> capsules_;
  std::vector<glm::mat4> rest_globals_, joints_;
  PosedCage posed_;
  std::vector<ColliderShape> shapes_;
  bool started_ = false;
  std::vector<std::vector<glm::vec3>> offsets_;  // #F x #Vc
  std::vector<SimFrameStats> stats_;
  std::unique_ptr<OneRingFit> fit_;
  std::vector<glm::dmat3> fitted_;
};

// Per-clip simulations of one document, made and filled on demand.
class SimCache {
 public:
  // The clip's simulation for this document (a new one when the document's inputs changed), or the
  // error ClipSimulation::create gives. Not filled: advance or complete it.
  Result<ClipSimulation*> get(const Document& doc, const CageAttachment* attachment, int32_t clip);
  void clear() { clips_.clear(); }

 private:
  std::map<int32_t, std::unique_ptr<ClipSimulation>> clips_;
};

// Poses `doc` at clip time t with its simulation applied when it is enabled and a clip plays (the
// clip's frames filled first, as far as t needs): pose_document_cage, then ClipSimulation::apply.
// The one path the export and `cagewrap pose` take (the editor fills the cache a little each frame
// instead).
Status pose_simulated_cage(SimCache& cache, const Document& doc, const CageAttachment* attachment, int32_t clip,
                           double t, const Pose& pose, PosedCage& out);

}  // namespace cagewrap
