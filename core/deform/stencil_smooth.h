// Smoothing the extended stencil along the skin (beyond the paper; docs/algorithm-notes.md).
//
// The extended variant deforms a point as P' = sum_v a_v T_v(P), with a_v its stencil over cage
// vertices (rows sum to one) and T_v the vertex's affine map (the identity at rest). Any row that
// sums to one keeps the rest skin exactly where it is and carries any map shared by every vertex
// exactly, so a row may be replaced by a blend of its neighbours' rows without giving up either
// property. In a concave region (an armpit, the inside of a bent elbow) two skin points a few
// millimetres apart project onto quite different points of the same cage elements: their rows
// differ much more than the points do, and a posed cage pulls them apart (a stretched skin edge).
// Blending each row with its skin neighbours' (a few Jacobi steps of the uniform graph Laplacian)
// makes the rows change along the skin as smoothly as the skin itself.
//
// The skin graph is built on welded positions: vertices at the same place (a UV seam, a normal
// split) are one node, so both sides of a seam keep one row and the seam does not open.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "core/deform/binding.h"
#include "core/geometry/mesh.h"

namespace cagewrap {

struct CageAttachment;
struct Character;

using Influences = std::vector<std::pair<uint32_t, float>>;  // (skeleton node, weight)

// The skin's adjacency over welded positions: vertices at the same position are one node; nodes are
// joined by the triangles' edges (CSR).
struct SkinGraph {
  std::vector<uint32_t> node;        // #P the node of each vertex
  std::vector<uint32_t> offsets;     // #nodes+1
  std::vector<uint32_t> neighbours;  // node ids
  std::vector<float> weights;        // per neighbour entry, in [0, 1]: how much the rows are blended across it
  std::vector<glm::vec3> positions;  // #nodes
  std::vector<Influences> influence; // #nodes (empty without influences): the file's weights (skeleton nodes)
  size_t num_nodes() const { return offsets.empty() ? 0 : offsets.size() - 1; }
  bool empty() const { return num_nodes() == 0; }
};
// `triangles` index `positions` (#P, the concatenated skin). `influences` (optional, #P lists of
// (skeleton node, weight)): the file's skinning. With it, vertices weld only when their influences
// agree too, and an edge blends the rows by (1 - |T_a - T_b|_1 / kSmoothWeightJump)^2, 0 beyond: rows
// are not blended across a jump in the file's weights (two parts that touch, a rigid segment's
// border), where the file itself does not blend. Without it every edge weighs 1.
inline constexpr double kSmoothWeightJump = 1.0;
SkinGraph build_skin_graph(std::span<const glm::vec3> positions, std::span<const Tri> triangles,
                           std::span<const Influences> influences = {});
// The graph of a character's skin (every primitive concatenated, skin_character order) with its
// skinning: a rigid primitive counts as weight 1 on the node instancing it.
SkinGraph character_skin_graph(const Character& character);

// Measured on the automatic cages of the demo, the mannequin and the generated hard characters
// (docs/algorithm-notes.md, "Smoothing the stencil"): 32 steps, the excess thresholds 0.5 .. 1.
struct StencilSmoothing {
  uint32_t iterations = 32;    // Jacobi steps (each reaches one ring further)
  double blend = 0.5;          // share of the neighbours' mean taken at each step
  uint32_t max_entries = 16;   // a row keeps at most this many cage vertices (the heaviest), renormalized
  // With a per-node figure g (rig_weight_excess), a node is smoothed by smoothstep(jump_low,
  // jump_high, g), spread over `iterations` rings around it (fading by `spread` a ring).
  double jump_low = 0.5, jump_high = 1.0, spread = 0.8;
  // Skin edges longer than h / edge_scale blend less (by (h / (edge_scale x length))^2). 0: no limit.
  double edge_scale = 3.0;
};
// Skins with more points are not smoothed (the smoothing's cost grows with points x steps; a skin
// that dense has edges far shorter than the cage's, where 32 rings reach almost nothing).
inline constexpr size_t kSmoothMaxPoints = 200000;
// Nodes whose spread figure falls below this are not blended at all.
inline constexpr float kSmoothMinNeed = 0.05f;

// Smooths the rows of an extended binding in place (other variants, an empty graph or 0 iterations:
// unchanged). Rows of fallback points (empty rows) are neither read nor written. `jump` (#nodes,
// optional): the figure g the options' thresholds read; empty: every node is smoothed.
// `allowed` (optional): whether a node's row may take a cage vertex its own row does not hold (the
// rig keeps limbs apart: a vertex of the other leg must not enter a thigh's row through the crotch).
void smooth_stencil(Binding& binding, const SkinGraph& graph, const StencilSmoothing& options,
                    std::span<const float> jump = {},
                    const std::function<bool(uint32_t node, uint32_t cage_vertex)>& allowed = {});

// The `allowed` rule of the fitted rig: a cage vertex may join a node's row when the joint its
// attachment labels it with (CageAttachment::label_joint) is a joint of the node's file weights or
// the parent of one (not a child: the hips' child on the other side is the other thigh).
std::function<bool(uint32_t, uint32_t)> related_to_file_weights(const SkinGraph& graph, const Character& character,
                                                               const CageAttachment& attachment);

// Re-weights each point's row (extended variant) over the cage vertices it already holds so that
// the rig's skin weights E_p = sum_v a_pv w_v (w_v: cage vertex v's joint weights) come closer to the
// file's T_p: the row a_p minimizes
//     |sum_v a_pv w_v - T_p|^2 + lambda |a_p - a0_p|^2   over rows a_p >= 0 that sum to one,
// a0_p the row as it was (solved exactly, a small strictly convex problem per point: the row changes
// continuously with T and a0, and stays itself where E already equals T). The rows still sum to one,
// so the rest skin and any map every vertex shares are kept exactly. Points without a row or whose
// file weights no vertex of the row carries, a skin of another size, other variants: unchanged.
// lambda; the scale of w_v . w_u is 1. Smaller follows the file's weights more closely but makes the
// skin's response to moving a cage vertex rougher (measured: 0.01 made the mannequin's 3.2 against
// the registration's own 2.4; 0.05 with the fit rounds of fit_rig keeps every test character at or
// below its registration)
inline constexpr double kRowReweight = 0.05;
void reweight_rows(Binding& binding, const Character& character, const CageAttachment& attachment,
                   double lambda = kRowReweight);

// Per node of `graph`: how much faster the rig's skin weights (E = the stencil times the cage
// vertices' joint weights: the rig is linear blend skinning with E) change across the node's edges
// than the file's do: max over edges of (|E_a - E_b|_1 - |T_a - T_b|_1) / length x h. Where it is
// large the posed rig stretches the edge against the file's skinning.
std::vector<float> rig_weight_excess(const Binding& binding, const SkinGraph& graph, const Character& character,
                                     const CageAttachment& attachment);

}  // namespace cagewrap
