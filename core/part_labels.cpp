#include "core/part_labels.h"

#include <string>

namespace cagewrap {

std::vector<uint32_t> dominant_joint_nodes(const Character& character) {
  std::vector<uint32_t> out;
  out.reserve(character.num_vertices());
  for (const Primitive& prim : character.primitives) {
    const bool skinned = prim.skin >= 0 && size_t(prim.skin) < character.skins.size() &&
                         prim.influence_start.size() == prim.num_vertices() + 1;
    for (size_t v = 0; v < prim.num_vertices(); ++v) {
      if (!skinned) {
        out.push_back(prim.node < character.skeleton.size() ? prim.node : PartLabels::kUnlabelled);
        continue;
      }
      const Skin& skin = character.skins[static_cast<size_t>(prim.skin)];
      uint32_t best = PartLabels::kUnlabelled;
      float best_w = -1.f;
      for (uint32_t i = prim.influence_start[v]; i < prim.influence_start[v + 1]; ++i)
        if (prim.influence_weight[i] > best_w && prim.influence_joint[i] < skin.joints.size()) {
          best_w = prim.influence_weight[i];
          best = skin.joints[prim.influence_joint[i]];
        }
      out.push_back(best);
    }
  }
  return out;
}

Result<PartLabels> skeleton_part_labels(const Character& character, const CageAttachment& attachment) {
  const size_t nodes = character.skeleton.size();
  if (nodes == 0)
    return make_error(ErrorCode::kInvalidArgument,
                      character.source + ": has no skeleton to label parts with");
  if (attachment.skin >= character.skins.size())
    return make_error(ErrorCode::kInvalidArgument,
                      "the cage attachment names skin " + std::to_string(attachment.skin) +
                          " but the character has " + std::to_string(character.skins.size()));
  const Skin& skin = character.skins[attachment.skin];
  PartLabels labels;
  labels.parent.resize(nodes);
  for (size_t n = 0; n < nodes; ++n) labels.parent[n] = character.skeleton.node(n).parent;
  labels.point = dominant_joint_nodes(character);
  labels.cage_vertex.resize(attachment.joint.size());
  for (size_t v = 0; v < attachment.joint.size(); ++v) {
    if (attachment.joint[v] >= skin.joints.size())
      return make_error(ErrorCode::kIndexOutOfRange, "cage vertex " + std::to_string(v) + " follows joint " +
                                                         std::to_string(attachment.joint[v]) +
                                                         " but the skin has " +
                                                         std::to_string(skin.joints.size()) + " joints");
    labels.cage_vertex[v] = skin.joints[attachment.joint[v]];
  }
  return labels;
}

}  // namespace cagewrap
