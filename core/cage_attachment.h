// The cage follows the skeleton (paper section 5, step 2): by default each cage vertex is attached
// rigidly to the Euclidean closest limb, the segment from a joint to its child in the bind pose
// (a leaf joint gets a short segment along its own axis), and follows that joint:
// v_posed = M_joint_posed * inverse(M_joint_bind) * v_rest.
#pragma once

#include <span>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "core/character.h"

namespace cagewrap {

struct Limb {
  uint32_t joint;  // skin joint index (into Skin::joints) that drives the limb
  glm::dvec3 a, b; // bind-pose segment
};

struct CageAttachment {
  uint32_t skin = 0;                  // the Character::skins entry whose joints drive the cage
  std::vector<uint32_t> joint;        // #Vc skin joint each cage vertex follows
  std::vector<Limb> limbs;            // the candidate segments, for display
};

// Limbs of a skin in its bind pose (from the inverse bind matrices).
std::vector<Limb> skin_limbs(const Character& character, uint32_t skin);

// Rigid attachment of every cage vertex to the closest limb. Fails when the character has no skin.
Result<CageAttachment> attach_to_closest_limb(const Character& character, std::span<const glm::vec3> cage_rest);

// Posed cage vertices and, for the extended variant, each vertex's linear part (the joint's
// rotation and scale) from the skinning matrices of the attachment's skin (#J, joint_matrices()).
void pose_cage(const CageAttachment& att, std::span<const glm::mat4> skinning, std::span<const glm::vec3> cage_rest,
               std::span<glm::vec3> out, std::span<glm::dmat3> linear = {});

}  // namespace cagewrap
