// Fidelity of a rig to the character's own skinning: the rig (the skin deformed through the cage,
// core/rig/rig.h) against the file's linear blend skinning (core/character/skinning.h) at the same pose, on every
// clip, judged where an artist looks: the worst vertex and the worst edge stretch of the worst frame,
// not a mean. Used by `cagewrap check`, the editor's Fidelity panel and heat map, and the export
// report.
//
// Figures per frame (d = |rig(p) - lbs(p)|, D = the bounding-box diagonal of the bind-pose skin):
//   worst  = max_p d / D, with its vertex and that vertex's heaviest joint
//   rms    = sqrt(mean_p d^2) / D
//   stretch = max over skin edges (a, b) with |lbs(a) - lbs(b)| >= min_edge * D of
//             |rig(a) - rig(b)| / |lbs(a) - lbs(b)|      (1 = as long as the file makes it)
//   squash  = the same with the ratio inverted (an edge the rig shortens)
// A clip is sampled at `fractions` of its length and every 1/fps seconds (both ends included).
#pragma once

#include <atomic>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "core/document/document.h"
#include "core/base/result.h"
#include "core/rig/rig.h"

namespace cagewrap {

struct FidelityThresholds {
  double worst = 0.05;   // share of the diagonal at the worst vertex of any frame
  double rms = 0.01;     // share of the diagonal, RMS over the skin, at the worst frame
  double stretch = 2.0;  // largest edge length ratio rig / file skinning
};

struct FidelityOptions {
  double fps = 30.0;  // frames per second sampled along each clip (0: only the fractions)
  std::vector<double> fractions{0.1, 0.3, 0.5, 0.7, 0.9};
  double min_edge = 1e-3;  // edges shorter than this share of the diagonal are not judged
  bool rest = true;        // judge the rest pose too
  // clips to judge (indices); empty = every clip
  std::vector<int32_t> clips;
  FidelityThresholds thresholds;
  // Judge only these skin points (#P weights, e.g. core/character/skin_mask.h joint_region_mask: the
  // points weighing more than 0.5, and the edges between two of them); empty = every point.
  std::vector<float> region;
};

struct FrameFidelity {
  int32_t clip = -1;  // -1: the rest pose
  double time = 0.0;
  double worst = 0.0, rms = 0.0;  // shares of the diagonal
  uint32_t worst_vertex = 0;
  int32_t worst_joint = -1;  // skeleton node: the worst vertex's heaviest joint (-1: none)
  double stretch = 1.0, squash = 1.0;
  uint32_t stretch_edge[2] = {0, 0};
  int32_t stretch_joint = -1;  // heaviest joint of the stretched edge's first vertex
};

// One clip (or the rest pose): its frames' worst figures, each with the frame it came from.
struct ClipFidelity {
  int32_t clip = -1;
  std::string name;  // "rest" for the rest pose
  size_t frames = 0;
  FrameFidelity worst;    // the frame with the worst vertex
  FrameFidelity rms;      // the frame with the largest RMS
  FrameFidelity stretch;  // the frame with the largest edge stretch
  double rms_all = 0.0;   // RMS over every sampled frame and vertex
};

struct FidelityReport {
  double diagonal = 0.0;  // bounding-box diagonal of the bind-pose skin, scene units
  std::string units;      // "m", or "scene units" when the file is clearly not in metres
  size_t vertices = 0, edges_judged = 0;
  std::vector<ClipFidelity> clips;  // the rest pose first (when judged), then the clips in order
  ClipFidelity overall;             // the worst of everything (name "all")
  FidelityThresholds thresholds;
  bool passed() const;
  // The reasons it does not pass, one line each ("worst vertex 12.3% of the diagonal > 5% (clip 'run'
  // at 0.44 s, vertex 812, joint 'calf.r')"); empty when it passes.
  std::vector<std::string> failures(const Skeleton& skeleton) const;
};

// "m" for a character of plausible human size in metres (diagonal 0.05 .. 50), else "scene units".
std::string scene_units(double diagonal);
// A length in those units with 3 significant digits ("0.0123 m", "2.54 scene units").
std::string format_length(double value, const std::string& units);

// Skin edges of a character (combined_topology order), each once, a < b.
std::vector<std::pair<uint32_t, uint32_t>> skin_edges(const Character& character);
// Every skin point's heaviest joint as a skeleton node (-1: none), combined order.
std::vector<int32_t> heaviest_joints(const Character& character);

// Compares two skins at one pose (`ref`: the file's skinning). `edges` and `joints` as above;
// `per_vertex` (optional, #P) receives d / D.
FrameFidelity compare_skins(std::span<const glm::vec3> rig, std::span<const glm::vec3> ref,
                            std::span<const std::pair<uint32_t, uint32_t>> edges, std::span<const int32_t> joints,
                            double diagonal, double min_edge, std::span<float> per_vertex = {});

struct FidelityProgress {
  std::function<void(double)> on_progress;  // 0..1
  const std::atomic<bool>* cancel = nullptr;
};

// Poses `rig` (made for `doc`) at every sampled frame of the chosen clips and compares it with the
// character's skinning. Fails when cancelled or a pose fails.
Result<FidelityReport> check_fidelity(const Document& doc, Rig& rig, const FidelityOptions& options,
                                      const FidelityProgress& progress = {});

// The sample times of a clip of this duration (sorted, unique, within [0, duration]).
std::vector<double> fidelity_sample_times(double duration, const FidelityOptions& options);

}  // namespace cagewrap
