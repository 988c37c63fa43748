// The skeleton as the outliner shows it: joints under their nearest joint ancestor, whatever order
// the file lists them in, and the nodes that are no skin's joint (meshes, cameras, lights, groups)
// apart, so that a camera is never shown as a bone.
#pragma once

#include <cstdint>
#include <vector>

#include "core/character/character.h"

namespace cagewrap::app {

struct JointTree {
  std::vector<uint32_t> roots;                  // joints with no joint above them, in file order
  std::vector<std::vector<uint32_t>> children;  // per node: its joint children, in file order
  std::vector<uint32_t> other_nodes;            // nodes that are no skin's joint, in file order
  std::vector<uint8_t> mesh_node;               // per node: 1 when it instances a mesh
  size_t joints = 0;
};

JointTree joint_tree(const Character& ch);

}  // namespace cagewrap::app
