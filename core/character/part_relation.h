// How a character's skeleton nodes relate as body parts: hierarchy steps, chains of short bones,
// co-skinned neighbours, and each skin point's dominant joint. Used by automatic separation
// (core/deform/part_labels.h) and the skin-weights cage attachment (core/cage/cage_attachment.h).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "core/character/character.h"

namespace cagewrap {

// No skeleton node (a point of a primitive with no weights and no node); PartLabels::kUnlabelled.
inline constexpr uint32_t kNoJointNode = UINT32_MAX;

// Every node's head in the bind pose: a joint's from its inverse bind matrix, any other node's from
// the rest pose.
std::vector<glm::vec3> bind_node_heads(const Character& character);

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

// The dominant joint of every skin point as a skeleton node (kNoJointNode for a point of a primitive
// with no weights and no node), skin_character order.
std::vector<uint32_t> dominant_joint_nodes(const Character& character);

}  // namespace cagewrap
