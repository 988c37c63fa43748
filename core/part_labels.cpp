#include "core/part_labels.h"

#include <string>

#include "core/skinning.h"

namespace cagewrap {

std::vector<uint32_t> dominant_joint_nodes(const Character& character) {
  const PointJoints pj = point_joint_nodes(character);
  std::vector<uint32_t> out(pj.start.size() - 1, PartLabels::kUnlabelled);
  for (size_t p = 0; p < out.size(); ++p) {
    float best = -1.f;
    for (uint32_t i = pj.start[p]; i < pj.start[p + 1]; ++i)
      if (pj.weight[i] > best) {
        best = pj.weight[i];
        out[p] = pj.node[i];
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
