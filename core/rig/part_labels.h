// Part labels for automatic separation (BindParams::separate, PartLabels in core/deform/registration.h)
// from a character's skeleton: spatially close but unrelated parts (the two thighs, an arm hanging
// against the torso) should not pull on each other, which the paper leaves to the user (section 5,
// Figure 5). Labels are the skeleton's nodes, related through its hierarchy: each skin point takes
// its dominant joint (largest skin weight; a point of an unskinned primitive, the node that
// instances it), each cage vertex the joint it follows (core/rig/cage_attachment.h).
#pragma once

#include "core/rig/cage_attachment.h"
#include "core/rig/character.h"
#include "core/deform/registration.h"

namespace cagewrap {

// Which skeleton nodes count as one part beyond the hierarchy steps of BindParams::separation_steps:
// a node and one of its ancestors whose chain of bones (bind pose, head to head) is at most
// `reach` long (a tail, a spine or a finger of short bones: a cage element spans several of them;
// the two thighs, or a hand and the chest, are never related this way, however close). #N x #N,
// row-major, symmetric, 1 on the diagonal.
std::vector<uint8_t> chained_nodes(const Character& character, double reach);
// The reach chained_nodes is used with: 5% of the bind-pose skin's bounding-box diagonal.
double chain_reach(const Character& character);
// Pairs of nodes at most two hierarchy steps apart that the character's own skinning blends: both
// weigh at least `weight` on at least `points` skin points (the armpit, whose skin the chest and the
// upper arm share across the shoulder). #N x #N like chained_nodes.
std::vector<uint8_t> coskinned_nodes(const Character& character, float weight = 0.3f, size_t points = 3);
// The relation separation and the skin-weights attachment use beyond one hierarchy step: chained
// (chain_reach) or co-skinned nodes.
std::vector<uint8_t> part_relation(const Character& character);

// Whether skeleton nodes a and b are one part for separation: at most `steps` apart in the hierarchy,
// or chained (`chained` from chained_nodes; may be empty).
bool related_nodes(const Skeleton& skeleton, std::span<const uint8_t> chained, uint32_t a, uint32_t b, uint32_t steps);

// Points in skin_character order (#sum V), cage vertices as in `attachment` (#Vc). The labels'
// `related` relation is part_relation(character).
// Errors: a character without skeleton nodes, an attachment naming joints its skin does not have.
Result<PartLabels> skeleton_part_labels(const Character& character, const CageAttachment& attachment);

// The dominant joint of every skin point as a skeleton node (kUnlabelled for a point of a primitive
// with no weights and no node), skin_character order.
std::vector<uint32_t> dominant_joint_nodes(const Character& character);

}  // namespace cagewrap
