#include "core/deform/part_labels.h"

#include <algorithm>
#include <string>

#include <glm/geometric.hpp>

namespace cagewrap {

static_assert(PartLabels::kUnlabelled == kNoJointNode);

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
  labels.related = part_relation(character);
  {
    const Skeleton& s = character.skeleton;
    labels.head = bind_node_heads(character);
    labels.length.assign(nodes, 0.0f);
    for (size_t i = 0; i < nodes; ++i) {
      float longest = 0.0f;  // a bone runs from its head to its children's heads
      for (uint32_t c : s.children(static_cast<uint32_t>(i))) longest = std::max(longest, glm::length(labels.head[c] - labels.head[i]));
      const int32_t p = s.node(i).parent;
      labels.length[i] = longest > 0 ? longest : p >= 0 ? 0.5f * glm::length(labels.head[i] - labels.head[static_cast<size_t>(p)]) : 0.0f;
    }
  }
  if (attachment.point_shell.size() == labels.point.size() && attachment.vertex_shell.size() == attachment.joint.size()) {
    labels.point_shell = attachment.point_shell;
    labels.vertex_shell = attachment.vertex_shell;
  }
  const std::vector<uint32_t>& joint =
      attachment.label_joint.size() == attachment.joint.size() ? attachment.label_joint : attachment.joint;
  labels.cage_vertex.resize(joint.size());
  for (size_t v = 0; v < joint.size(); ++v) {
    if (joint[v] >= skin.joints.size())
      return make_error(ErrorCode::kIndexOutOfRange, "cage vertex " + std::to_string(v) + " follows joint " +
                                                         std::to_string(joint[v]) + " but the skin has " +
                                                         std::to_string(skin.joints.size()) + " joints");
    labels.cage_vertex[v] = skin.joints[joint[v]];
  }
  return labels;
}

}  // namespace cagewrap
