// Linear blend skinning of an imported character: the reference the artist compares the cage
// deformation against, and what `cagewrap skin` writes. Morph targets apply before skinning.
#pragma once

#include <span>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "core/character/character.h"

namespace cagewrap {

// For each joint j of the skin: globals[joint node] * inverse_bind[j] (#J).
void joint_matrices(const Skin& skin, std::span<const glm::mat4> globals, std::span<glm::mat4> out);

// Positions of one primitive (morphs, then LBS with `joints`, or the rigid `node_global` when
// unskinned) into out (#V x 3). `morph_weights` may be empty (use the primitive's defaults).
// Parallel over vertices.
void skin_primitive(const Primitive& prim, std::span<const glm::mat4> joints, const glm::mat4& node_global,
                    std::span<const float> morph_weights, std::span<glm::vec3> out);

// Every primitive of the character at a pose, concatenated in Character::primitives order
// (#sum V x 3).
std::vector<glm::vec3> skin_character(const Character& character, const Pose& pose);

// The rest pose with clip `clip` (-1: none) applied at time t (clamped, or wrapped when `loop`).
Pose sample_pose(const Character& character, int32_t clip, double t, bool loop = false);

// All primitives' triangles as one mesh, indices offset like skin_character's output.
PolyMesh combined_topology(const Character& character);

// Every skin point's joints as skeleton nodes with their skin weights (> 0), skin_character order,
// in CSR form: point p owns [start[p], start[p+1]). A point of an unskinned primitive has the node
// that instances it with weight 1 (or nothing when no node does).
struct PointJoints {
  std::vector<uint32_t> start{0}, node;
  std::vector<float> weight;
};
PointJoints point_joint_nodes(const Character& character);

}  // namespace cagewrap
