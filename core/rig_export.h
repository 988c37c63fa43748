// Exporting a rigged document for engines and other tools: the cage rig (skeleton -> cage ->
// skin, core/rig.h) turned into something a plain glTF 2.0 runtime can play.
//
//   kBakedAnimation: the skin, unskinned, on a root node with identity transform, with one morph
//                    target per sampled frame of the chosen clips (rig skin - bind skin) and a
//                    "weights" channel per clip stepping through them (one-hot at each frame,
//                    LINEAR between frames). Exact at the frames; heavy.
//   kCage:           the driver cage as its own mesh, skinned to the joints it follows (the
//                    attachment's weights, at most kMaxAttachmentInfluences), with the character's
//                    skeleton, inverse bind matrices and clips. Exact (the rig poses the cage by
//                    this same linear blend) except for keyposes, which a skin cannot carry.
//   kBakedSkin:      linear blend skinning weights (<= 4 per vertex, >= 0, summing to 1 in float32)
//                    fitted so the skeleton alone reproduces the rig over the sampled frames, plus
//                    the residual of every sampled frame as a corrective morph target (in bind
//                    space: the blended joint's 3x3 inverse applied to the world residual, which
//                    LBS maps back exactly), animated per clip like kBakedAnimation.
//
// The fit, per skin vertex p with rig positions x_s over the S sampled poses and candidate joints
// j (the original LBS joints of the vertex and the attachment joints of its 8 nearest cage
// vertices): minimise sum_s |sum_j w_j J_sj p - x_s|^2 over the simplex (w >= 0, sum w = 1) by
// accelerated projected gradient (FISTA, Beck and Teboulle 2009) on the k x k normal equations,
// projection onto the simplex by sorting (Duchi et al. 2008); the 4 largest are kept and refitted.
// This is the weight step of Le and Deng, "Smooth Skinning Decomposition with Rigid Bones"
// (SIGGRAPH Asia 2012), with the bones fixed to the character's skeleton.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/character.h"
#include "core/document.h"
#include "core/result.h"
#include "core/rig.h"

namespace cagewrap {

enum class ExportMode { kBakedAnimation, kBakedSkin, kCage };
const char* export_mode_name(ExportMode m);
bool parse_export_mode(const std::string& name, ExportMode& out);

struct ExportOptions {
  ExportMode mode = ExportMode::kBakedAnimation;
  std::vector<int32_t> clips;  // clip indices of the character; empty = every clip
  double fps = 30.0;           // frames sampled per second of each clip (both ends included)
};

// Distances between exported and rig skin positions over vertices and frames.
struct ExportError {
  double mean = 0.0;
  double max = 0.0;
  size_t samples = 0;  // vertex-frames measured
};

struct ExportResult {
  Character character;  // what write_glb writes
  size_t frames = 0;    // sampled frames over the chosen clips
  size_t morph_targets = 0;
  // Against the live rig. kBakedSkin: `fitted` is the skeleton alone (no correctives) at the
  // frames; `at_frames` with the correctives at the frames; `between_frames` at the midpoints
  // between frames, the correctives' weights interpolated. kBakedAnimation: at and between frames.
  // kCage: the cage at the frames against the posed driver cage.
  ExportError fitted, at_frames, between_frames;
  std::vector<std::string> warnings;
};

// Builds the export. Fails when the document has no cage or the rig has no attachment (a
// character without a skin) for kCage / kBakedSkin, or a clip index is out of range.
Result<ExportResult> export_rig(const Document& doc, Rig& rig, const ExportOptions& options);

// The times sampled in a clip of `duration` seconds at `fps`: 0, ..., duration, evenly spaced
// no further apart than 1/fps (one time, 0, for a clip of no duration).
std::vector<double> export_frame_times(double duration, double fps);

}  // namespace cagewrap
