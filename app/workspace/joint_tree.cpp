#include "app/workspace/joint_tree.h"

namespace cagewrap::app {

JointTree joint_tree(const Character& ch) {
  JointTree t;
  const size_t n = ch.skeleton.size();
  std::vector<uint8_t> joint(n, 0);
  t.mesh_node.assign(n, 0);
  t.children.assign(n, {});
  for (const Skin& s : ch.skins)
    for (uint32_t j : s.joints)
      if (j < n) joint[j] = 1;
  for (const Primitive& p : ch.primitives)
    if (p.node < n) t.mesh_node[p.node] = 1;
  for (uint32_t i = 0; i < n; ++i) {
    if (!joint[i]) {
      t.other_nodes.push_back(i);
      continue;
    }
    ++t.joints;
    int32_t p = ch.skeleton.node(i).parent;
    for (size_t guard = 0; p >= 0 && !joint[static_cast<size_t>(p)] && guard < n; ++guard)
      p = ch.skeleton.node(static_cast<size_t>(p)).parent;
    if (p < 0 || !joint[static_cast<size_t>(p)]) t.roots.push_back(i);
    else t.children[static_cast<size_t>(p)].push_back(i);
  }
  return t;
}

}  // namespace cagewrap::app
