// Exporting a rigged document for engines and other tools: the cage rig (skeleton -> cage ->
// skin, core/rig/rig.h) turned into something a plain glTF 2.0 runtime can play.
//
//   kBakedAnimation: the skin, unskinned, on a root node with identity transform, with one morph
//                    target per sampled frame of the chosen clips (rig skin - bind skin) and a
//                    "weights" channel per clip stepping through them (one-hot at each frame,
//                    LINEAR between frames). Exact at the frames; heavy.
//   kCage:           the driver cage as its own mesh, skinned to the joints it follows (the
//                    attachment's weights, at most kMaxAttachmentInfluences), with the character's
//                    skeleton, inverse bind matrices and clips. Exact (the rig poses the cage by
//                    this same linear blend) except for keyposes, which a skin cannot carry.
//   kBakedSkin:      linear blend skinning weights (<= 4 per vertex, or 8 with max_influences, >= 0, summing to 1 in float32)
//                    fitted so the skeleton alone reproduces the rig over the sampled frames, plus
//                    the residual of every sampled frame as a corrective morph target (in bind
//                    space: the blended joint's 3x3 inverse applied to the world residual, which
//                    LBS maps back exactly), animated per clip like kBakedAnimation.
//
// The fit samples the rest pose, every exported frame and a sweep of every keypose set (from rest
// to each key: keypose_sweep_poses), so the weights also see the keyposed shapes.
//
// The fit, per skin vertex p with rig positions x_s over the S sampled poses and candidate joints
// j (the original LBS joints of the vertex and the attachment joints of its 8 nearest cage
// vertices): minimise sum_s |sum_j w_j J_sj p - x_s|^2 + mu |w - w0|^2 over the simplex (w >= 0,
// sum w = 1), the prior pulling towards the character's own weights w0 (mu = 3e-3 of the normal matrix's
// mean diagonal: it decides the joints the sampled poses never move, and steadies ill-conditioned points), by
// accelerated projected gradient (FISTA, Beck and Teboulle 2009) on the k x k normal equations,
// projection onto the simplex by sorting (Duchi et al. 2008); the 4 largest are kept and refitted.
// This is the weight step of Le and Deng, "Smooth Skinning Decomposition with Rigid Bones"
// (SIGGRAPH Asia 2012), with the bones fixed to the character's skeleton.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/character/character.h"
#include "core/document/document.h"
#include "core/base/result.h"
#include "core/io/gltf_quantize.h"
#include "core/rig/rig.h"

namespace cagewrap {

enum class ExportMode { kBakedAnimation, kBakedSkin, kCage };
const char* export_mode_name(ExportMode m);
bool parse_export_mode(const std::string& name, ExportMode& out);

struct ExportOptions {
  ExportMode mode = ExportMode::kBakedAnimation;
  std::vector<int32_t> clips;  // clip indices of the character; empty = every clip
  double fps = 30.0;           // frames sampled per second of each clip (both ends included)
  // Poses per key in the keypose sweep (keypose_sweep_poses; 0 = none). kBakedSkin fits its weights
  // to them (unless fit_keyposes is false) and every mode but kBakedAnimation reports its error there.
  int keypose_steps = 3;
  bool fit_keyposes = true;
  // The corrective morph targets of the skin modes (issue 22). 0: one per sampled frame (exact at the
  // frames; heavy: the mannequin's 261 frames are 34.6 MB). N > 0: the residuals of every sampled frame
  // (and of the keypose sweep) reduced to at most N shapes, their principal components (an SVD of the
  // residuals through their Gram matrix, in double), each frame keyed with its own N weights per clip.
  // -1: the mode's default, kDefaultMaxTargets for baked-skin and 0 for baked-animation.
  int max_targets = -1;
  // > 0 (file units), with compressed targets: the fewest components (up to max_targets) whose largest
  // reconstruction error of a vertex over the frames is within it; a warning when max_targets cannot.
  double max_error = 0.0;
  // baked-skin: the fitted joints per vertex, 4 (JOINTS_0/WEIGHTS_0: every runtime) or 8 (also
  // JOINTS_1/WEIGHTS_1, for engines that read a second set; three.js reads the first only).
  int max_influences = 4;
  // glb: each primitive's triangles reordered for the GPU's vertex cache and its vertices for fetch order
  // (libmeshoptimizer: optimizeVertexCache, optimizeVertexFetchRemap); every vertex stream and target follows,
  // and each vertex's source index is written as _CAGEWRAP_SOURCE_INDEX. The errors are measured before: the
  // same mesh in another order.
  bool optimize = false;
  // glb: KHR_mesh_quantization (core/io/gltf_quantize.h): 16-bit positions and targets, 8-bit normals, 16-bit
  // weights, about a third smaller. The errors are measured on the quantized values.
  bool quantize = false;
  // baked-skin: how the corrective targets are weighted. kBaked: keyed per frame (compressed or one per frame,
  // above). kPoseDriven: each target driven by one joint angle (core/export/pose_correctives.h), at most
  // max_targets (the default 16), the drivers written in the mesh's extras (docs/pose-correctives.md) so an engine
  // corrects new animations; the clips key the weights the drivers give at each frame, so any runtime plays them.
  enum class Correctives { kBaked, kPoseDriven } correctives = Correctives::kBaked;
  // kPoseDriven: a clip index of the character (one of `clips`) left out of every fit (weights and correctives)
  // and still exported: its errors are those of an animation the export never saw. -1: none.
  int32_t hold_out = -1;
};
inline constexpr int kDefaultMaxTargets = 16;
// The number of corrective targets `options` asks for in its mode (max_targets resolved; 0 = per frame).
int corrective_targets(const ExportOptions& options);

// Progress of a long export, reported on the calling thread: the stage ("posing", "keyposes",
// "fitting", "correctives", "measuring", "writing"), items done of the stage's total (frames,
// poses or skin vertices) and the share of the whole export done, in [0, 1].
struct ExportProgress {
  std::function<void(const char* stage, size_t done, size_t total, double share)> on_progress;
  const std::atomic<bool>* cancel = nullptr;  // set to true to stop: the export returns kCancelled
  bool cancelled() const { return cancel && cancel->load(); }
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
  size_t keypose_poses = 0;  // poses of the keypose sweep (measured; fitted by kBakedSkin)
  // Against the live rig. kBakedSkin: `fitted` is the skeleton alone (no correctives) at the
  // frames; `at_frames` with the correctives at the frames; `between_frames` at the midpoints
  // between frames, the correctives' weights interpolated; `at_keyposes` at the keypose sweep's
  // poses, where no clip plays and so no corrective applies: the skeleton alone.
  // kBakedAnimation: at and between frames (no skeleton: poses outside the clips do not exist).
  // kCage: the cage at the frames against the posed driver cage, and at the keypose poses (the
  // skinned cage has no keyposes: this is what leaving them out costs).
  ExportError fitted, at_frames, between_frames, at_keyposes;
  // The exported skin at the frames against the character's own linear blend skinning there (what
  // the file made before the cage; the skin modes only), and the bind-pose skin's bounding-box
  // diagonal, in the file's units, that the report relates the errors to.
  ExportError vs_file;
  double diagonal = 0.0;
  // Per exported clip (the skin modes): its name, frames, and the errors at and between its frames.
  struct ClipErrors {
    std::string name;
    size_t frames = 0;
    ExportError at_frames, between_frames;
    ExportError fitted;     // baked-skin: the skeleton alone (no correctives) at the clip's frames
    bool held_out = false;  // left out of the fits (ExportOptions::hold_out)
  };
  std::vector<ClipErrors> clips;
  // Compressed correctives: how many components the residuals have (their rank, at most #frames +
  // #keypose poses) and the largest reconstruction error over the fitted residuals with the targets kept
  // (bind space, file units); 0 with per-frame targets.
  size_t influences = 0;  // baked-skin: the most joints any vertex's fitted weights use
  // With optimize: the vertex cache's average cache miss ratio (transformed vertices per triangle, 32-entry
  // cache; 0.5 is the best a grid reaches) over the triangles before and after.
  double acmr_before = 0.0, acmr_after = 0.0;
  size_t residual_rank = 0;
  double basis_error = 0.0;
  // Pose-driven correctives: the joint-angle ramps their weights are made of ("forearm.L rotation x+"); the
  // predicted residuals' rank is residual_rank.
  std::vector<std::string> pose_features;
  // What the exported character holds, by part, in bytes as written (float32 positions and normals,
  // uint16 joints or uint8 where they fit, float32 weights, keys): the meshes (positions, normals, indices),
  // the skin (joints, weights, inverse bind matrices), the morph targets, and the animation.
  struct Sizes {
    uint64_t mesh = 0, skin = 0, targets = 0, animation = 0;
  } sizes;
  // With quantize: what write_glb must be given to write the quantized file (the character is snapped to it).
  std::optional<GlbQuantization> quantization;
  std::vector<std::string> warnings;
};

// Builds the export. Fails when the document has no cage or the rig has no attachment (a
// character without a skin) for kCage / kBakedSkin, or a clip index is out of range; kCancelled
// when progress.cancel was set.
Result<ExportResult> export_rig(const Document& doc, Rig& rig, const ExportOptions& options,
                                const ExportProgress& progress = {});

// The frames of one exported clip.
struct ExportClipFrames {
  int32_t clip = 0;           // index in the character
  std::vector<double> times;  // export_frame_times(duration, fps)
  size_t first = 0;           // index of its first frame over all exported clips
};
// The chosen clips' frames (options.clips, empty = all), in order. Fails on a clip index out of
// range or a frame rate that is not a positive number.
Result<std::vector<ExportClipFrames>> export_clip_frames(const Character& character,
                                                         const ExportOptions& options);

// The rig's skin (or, for kCage, its posed driver cage, as polygons) at every sampled frame of the
// chosen clips as OBJ files, one per frame, at obj_sequence_paths. Exact: the live rig itself.
struct ObjSequence {
  std::vector<std::string> files;  // clip by clip, frame by frame
  size_t frames = 0;
  uint64_t bytes = 0;
};
Result<ObjSequence> export_obj_sequence(const Document& doc, Rig& rig, const ExportOptions& options,
                                        const std::string& out, const ExportProgress& progress = {});
// Where export_obj_sequence writes each frame. `out` ending in .obj: `<stem>_<clip>_<frame>.obj`
// beside it; otherwise `out` is a folder (made when missing) holding `<clip>_<frame>.obj`. <clip> is
// the clip's name with every character but letters, digits, '-', '_' and '.' replaced by '_'
// (`clip<index>` when that leaves nothing or repeats an earlier clip's); <frame> is the frame's
// index in its clip, zero-padded to 4 digits (more when a clip has more frames).
std::vector<std::string> obj_sequence_paths(const Character& character,
                                            std::span<const ExportClipFrames> frames, const std::string& out);

// The poses of the keypose sweep: for every active set (mute/solo) and every key not at the rest
// point, `steps` poses from the rest pose at the key's driver values times s / steps, s = 1 ..
// steps (the key itself last), set by pose_at_driver_values. Sets that fail validation are skipped.
std::vector<Pose> keypose_sweep_poses(const Character& character, std::span<const KeyposeSet> sets,
                                      int steps);

// The times sampled in a clip of `duration` seconds at `fps`: 0, ..., duration, evenly spaced
// no further apart than 1/fps (one time, 0, for a clip of no duration).
std::vector<double> export_frame_times(double duration, double fps);

}  // namespace cagewrap
