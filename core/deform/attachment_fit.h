// The fitted attachment (AttachmentMode::kFitted, the default for new documents): the cage vertices'
// joint weights chosen so that the rig reproduces the character's own skinning.
//
// Why it can: with the extended variant and the attachment's frames (core/rig/rig.h), a skin point
// deforms as P' = sum_j W_pj (L_j (P - v_j) + v'_j), where W_pj is the binding's stencil over cage
// vertices and, for a cage posed by linear blend skinning, v'_j = M_j v_j and L_j is the 3x3 of M_j
// = sum_b w_jb S_b (S_b the joints' skinning matrices). So P' = sum_b (sum_j W_pj w_jb) S_b P: the
// rig *is* linear blend skinning of the skin with the weights W w. The fit picks the cage weights w
// (#Vc x #J) that make W w closest to the file's weights T (#P x #J) in least squares, pulled toward
// the transferred weights w0 where few points decide them:
//     (W^T W + gamma W^T L W + lambda I) w = W^T T + gamma W^T L T + lambda w0,
// lambda = kFitRegularization x mean diag(W^T W), L the skin's edge Laplacian with weights
// (mean edge / edge)^2 (so that W w also changes along every skin edge as T does: where W changes
// faster than T, in a concave armpit, the rig would stretch the edge), gamma = kFitGradient; one
// sparse Cholesky factorization for all joints. Then each vertex keeps its
// kMaxAttachmentInfluences largest positive weights on one chain of the skeleton (the heaviest
// joint's ancestors and descendants: no vertex follows a joint of another limb), normalized (a cage
// is skinned with at most four). Where the cage cannot express the file's weights (a crease sharper than the cage's
// resolution) the rig is the least-squares closest it can be; elsewhere it equals the file's
// skinning. Other variants use the same weights (their rig is close to, not equal to, LBS).
#pragma once

#include <optional>

#include "core/deform/binding.h"
#include "core/cage/cage_attachment.h"
#include "core/character/character.h"
#include "core/base/result.h"

namespace cagewrap {

inline constexpr double kFitRegularization = 1e-3;
// Weight of the fit's term along the skin's edges (below): measured on the automatic cages of the
// demo, the mannequin, arms-down and the tail character (10 fps): the largest edge stretch
// 11.4 / 5.9 / 20.3 / 12.4x without it, 10.1 / 3.6 / 17.7 / 10.6x at 1, with the worst vertex within
// 0.1% of the diagonal; at 3 and 10 the RMS grows (mannequin 0.18% -> 0.25%, 0.35%).
inline constexpr double kFitGradient = 1.0;

// Points the fit reads at most (a larger skin is sampled evenly, with the edges of the sampled points).
inline constexpr size_t kFitMaxPoints = 200000;

struct FitOptions {
  double regularization = kFitRegularization;
  double gradient = kFitGradient;  // 0: the weights alone
};

// Refits `att` (made by attach_cage for the binding's cage) from `binding` (of the character's skin,
// skin_character order, extended variant; other variants are fitted through their elements'
// corners, a third each). Overrides keep their joint. Fails on mismatched sizes.
Status fit_attachment(const Character& character, const Binding& binding, const AttachmentSettings& settings,
                      CageAttachment& att, const FitOptions& options = {});

// Rounds of (fit the cage weights to the re-weighted rows, re-weight the rows) after the first
// re-weighting in fit_rig. Measured (10 fps, docs/algorithm-notes.md): 0 rounds leave the mannequin
// at 2.5x and arms-down + tail at 2.45x; 2 rounds bring every test character under 1.7x.
inline constexpr int kRigFitRounds = 2;
// The default rig's fit (Rig and the editor share it): fit_attachment; then, where the rig's skin
// weights E change across the skin's edges faster than the file's (core/deform/stencil_smooth.h,
// rig_weight_excess: the edges a posed rig would stretch), the registration's stencil is smoothed
// along the skin in a copy; then every row of the copy is re-weighted over its own cage vertices
// toward the file's weights (reweight_rows: a cage vertex shared by the chest and the upper arm can
// only split the difference in the fit, but each point can lean on the vertices that move as it
// should); then kRigFitRounds rounds of fitting the attachment to the re-weighted rows and
// re-weighting them again. (Fitting again to the smoothed rows alone, without re-weighting, undid
// part of the smoothing's gain: mannequin worst 1.44% -> 2.12%, stretch 3.5x -> 6.3x.) Returns that
// copy (what the deformer reads), or nothing when the
// registration is used as it is (not extended, a skin of another size). Skins over kSmoothMaxPoints
// are re-weighted but not smoothed. The registration itself (its sets, the cache, live edits) is not
// changed.
Result<std::optional<Binding>> fit_rig(const Character& character, const Binding& registration,
                                       const AttachmentSettings& settings, CageAttachment& att);

}  // namespace cagewrap
