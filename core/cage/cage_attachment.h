// The cage follows the skeleton (paper section 5, step 2): by default each cage vertex is attached
// rigidly to the Euclidean closest limb, the segment from a joint to its child in the bind pose
// (a leaf joint gets a short segment along its own axis), and follows that joint:
// v_posed = M_joint_posed * inverse(M_joint_bind) * v_rest.
//
// Three additions, set in a document's AttachmentSettings (saved, undoable):
// - **skin weights** (the default for new documents): a vertex takes the character's own skin
//   weights around it: the influences of its k = kTransferNeighbours nearest skin points in the bind
//   pose, of the part (core/deform/part_labels.h related_nodes) of the nearest one and, with several shells,
//   among the points of its own shell,
//   each point weighted 1 / (d + delta) (d its distance, delta = 1e-3 of the skin's bounding-box
//   diagonal), summed per joint, the heaviest kMaxAttachmentInfluences kept and normalized. The
//   cage then bends as the character's linear blend skinning does (measured on the demo over its
//   clips: RMS to that skinning 1.6 mm instead of 18.2 mm rigid, docs/algorithm-notes.md); a
//   vertex with no skinned point near it falls back to the closest limb.
// - **smooth** attachment near joints, for cages that should bend rather than hinge: a vertex is
//   attached to the joints of its nearest limbs with weights that sum to 1 and falls back to rigid
//   away from joints; its skinning matrix is the weighted sum of the joints' (linear blend).
//   Falloff: let d_j be the distance from the vertex to joint j's nearest limb and d_min the
//   smallest. Joint j gets the raw weight
//       f_j = 1 - smoothstep(0, 1, (d_j / d_min - 1) / width)
//   (1 for the nearest, 0 once d_j >= (1 + width) d_min), and the weights are f_j / sum f. On the
//   bisector between two limbs both weigh 1/2; the blend zone around an elbow reaches about
//   sqrt((1 + width)^2 - 1) times the cage's distance from the bone along each bone (1.1 for the
//   default width 0.5, 1.7 for width 1), so it scales with the limb's thickness. Where bones are
//   shorter than the body is thick (a torso of hips, spine and chest) nearly every vertex blends.
//   Every f_j is continuous in the position, so the weights are too, also where three joints meet
//   (the chest between neck and shoulders, where three joints can share a vertex); that is why
//   every joint within the falloff takes part rather than exactly the nearest two (the second
//   nearest would jump where it swaps with the third). At most kMaxAttachmentInfluences are kept.
// - **fitted** (the default for new documents): the skin-weights attachment, then, once the skin is
//   bound, weights refitted so that the rig reproduces the character's own skinning
//   (core/deform/attachment_fit.h; attach_cage alone gives the transferred weights).
// - **overrides**: chosen cage vertices follow a chosen joint rigidly, whatever the mode.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "core/character/character.h"
#include "core/geometry/selection.h"

namespace cagewrap {

inline constexpr size_t kMaxAttachmentInfluences = 4;

inline constexpr size_t kTransferNeighbours = 8;

enum class AttachmentMode { kRigid, kSmooth, kSkinWeights, kFitted };
const char* attachment_mode_name(AttachmentMode m);
bool parse_attachment_mode(const std::string& name, AttachmentMode& out);

struct AttachmentOverride {
  uint32_t vertex = 0;  // cage vertex
  uint32_t node = 0;    // skeleton node (must be a joint of the skin the cage follows)
  bool operator==(const AttachmentOverride&) const = default;
};

// How the document's cage follows the skeleton. Part of the Document.
struct AttachmentSettings {
  AttachmentMode mode = AttachmentMode::kFitted;
  double smooth_width = 0.5;  // the falloff above (> 0, dimensionless); used by kSmooth
  std::vector<AttachmentOverride> overrides;  // sorted by vertex, one per vertex
  bool operator==(const AttachmentSettings&) const = default;
};

// Assigns `vertices` to `node` (nullopt: back to automatic). Keeps `overrides` sorted and unique.
AttachmentSettings assign_vertices(const AttachmentSettings& settings, std::span<const uint32_t> vertices,
                                   std::optional<uint32_t> node);
// The node a vertex is assigned to, or nullopt when it is automatic.
std::optional<uint32_t> assigned_node(const AttachmentSettings& settings, uint32_t vertex);

// Per-vertex form of the overrides, for code that carries per-vertex data through topology
// changes: #Vc node per cage vertex, -1 = automatic (overrides beyond num_vertices are dropped).
std::vector<int32_t> overrides_per_vertex(const AttachmentSettings& settings, size_t num_vertices);
// The inverse: the settings with their overrides replaced by `per_vertex` (-1 = automatic).
AttachmentSettings with_overrides_per_vertex(const AttachmentSettings& settings,
                                             std::span<const int32_t> per_vertex);

struct MirroredAssignment {
  AttachmentSettings settings;
  std::vector<uint32_t> unmatched;  // given vertices no vertex took its assignment from
};
// Mirrors the assignment of `vertices` across x = 0: every cage vertex whose mirror image's
// nearest vertex (core/geometry/selection.h mirror_x_counterparts, on the rest cage, within `tolerance`) is
// one of `vertices` gets that vertex's assignment mirrored: the joint named for the other side
// (core/character/mirror_names.h), or automatic when that vertex is automatic. On a symmetric cage that is
// the pairwise counterpart; on a nearly symmetric one a tolerance of about an edge length leaves no
// holes. Fails, changing nothing, when an assigned node has no mirrored node; the error names it.
Result<MirroredAssignment> mirror_assignment(const AttachmentSettings& settings, const Skeleton& skeleton,
                                             std::span<const glm::vec3> cage_rest,
                                             std::span<const uint32_t> vertices, double tolerance);

struct Limb {
  uint32_t joint;  // skin joint index (into Skin::joints) that drives the limb
  glm::dvec3 a, b; // bind-pose segment
  bool operator==(const Limb&) const = default;
};

struct CageAttachment {
  uint32_t skin = 0;                  // the Character::skins entry whose joints drive the cage
  std::vector<uint32_t> joint;        // #Vc the joint with the largest weight (the only one when rigid)
  // #Vc the joint each vertex's separation label comes from (core/deform/part_labels.h): `joint` as
  // attach_cage made it, kept when fit_attachment (core/deform/attachment_fit.h) changes the weights, so
  // the bind the fit is made from and the bind after it see the same labels.
  std::vector<uint32_t> label_joint;
  // Influences in CSR form: vertex v follows influence_joint[i] (skin joint) with influence_weight[i]
  // for i in influence_start[v] .. influence_start[v+1]-1, heaviest first; weights sum to 1.
  std::vector<uint32_t> influence_start;  // #Vc + 1
  std::vector<uint32_t> influence_joint;
  std::vector<float> influence_weight;
  std::vector<Limb> limbs;            // the candidate segments, for display
  // With a cage of several shells (core/cage/cage_shells.h; empty otherwise): each cage vertex's shell,
  // and each skin point's (skin_character order) shell when one shell owns its whole skin piece
  // (kNoShell: none). The bind's separation lets an owned point use only its shell's elements.
  std::vector<uint32_t> vertex_shell;
  std::vector<uint32_t> point_shell;
  bool operator==(const CageAttachment&) const = default;
};

// Appends vertex v's influences (weight, skin joint; heaviest first, not empty) to `att`, normalized
// to sum to one, and sets its heaviest joint: the last step of every attachment rule.
void append_influences(CageAttachment& att, size_t v, std::span<const std::pair<double, uint32_t>> raw);

// Limbs of a skin in its bind pose (from the inverse bind matrices).
std::vector<Limb> skin_limbs(const Character& character, uint32_t skin);

// Rigid attachment of every cage vertex to the closest limb (mode kRigid, no overrides). Fails when
// the character has no skin.
Result<CageAttachment> attach_to_closest_limb(const Character& character, std::span<const glm::vec3> cage_rest);

// Attachment by the settings (mode, falloff, overrides). Fails when the character has no skin, or
// an override names a vertex outside the cage or a node that is not a joint of the skin (the
// error names the vertex and the node).
// `cage_elements` (the cage's control elements; may be empty): with a cage of several shells (its
// connected pieces), the skin-weights mode takes each vertex's weights only from the skin points its
// own shell owns (those deepest inside it, else nearest to it), so the shell around one finger does
// not follow the next finger where the two overlap. Every attachment of a document's cage passes them.
Result<CageAttachment> attach_cage(const Character& character, std::span<const glm::vec3> cage_rest,
                                   const AttachmentSettings& settings, std::span<const Tri> cage_elements = {});

// Posed cage vertices and, for the extended variant, each vertex's linear part from the skinning
// matrices of the attachment's skin (#J, joint_matrices()): M_v = sum_i w_i skinning[joint_i] (a
// linear blend; the rigid case is one joint with weight 1), out[v] = M_v * cage_rest[v],
// linear[v] = the 3x3 of M_v, vertex_skinning[v] = M_v (each optional: empty = not wanted).
void pose_cage(const CageAttachment& att, std::span<const glm::mat4> skinning, std::span<const glm::vec3> cage_rest,
               std::span<glm::vec3> out, std::span<glm::dmat3> linear = {},
               std::span<glm::mat4> vertex_skinning = {});

}  // namespace cagewrap
