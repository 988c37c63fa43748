// The node hierarchy of a character: names, parents, rest transforms, forward kinematics.
// Every glTF node is kept under its file index (joints, the armature, mesh nodes), so messages and
// animation channels can name nodes as the file does; a skin lists which nodes are its joints.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "core/base/result.h"

namespace cagewrap {

// A local transform as glTF stores it: M = T * R * S.
struct Trs {
  glm::vec3 translation{0.0f};
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};  // (w, x, y, z), unit length
  glm::vec3 scale{1.0f};
  glm::mat4 matrix() const;
};

struct SkeletonNode {
  std::string name;
  int32_t parent = -1;  // -1 for a root
  Trs rest;             // the file's local transform (ignored when has_matrix)
  bool has_matrix = false;
  glm::mat4 matrix{1.0f};  // the file's local matrix when it gave one (such a node is never animated)
};

// The animated state of every node: its local TRS and its morph weights (empty = the mesh defaults).
struct Pose {
  std::vector<Trs> local;                        // #N
  std::vector<std::vector<float>> morph_weights;  // #N x #targets
};

class Skeleton {
 public:
  Skeleton() = default;
  // Checks the parents form a forest (index in range, no cycle) and orders nodes for FK;
  // `what` names the file in messages.
  static Result<Skeleton> create(std::vector<SkeletonNode> nodes, const std::string& what);

  size_t size() const { return nodes_.size(); }
  const SkeletonNode& node(size_t i) const { return nodes_[i]; }
  const std::vector<SkeletonNode>& nodes() const { return nodes_; }
  // Parents before children.
  const std::vector<uint32_t>& order() const { return order_; }
  std::vector<uint32_t> children(uint32_t node) const;
  // Index of the first node with this name, or -1.
  int32_t find(const std::string& name) const;

  Pose rest_pose() const;
  glm::mat4 local_matrix(const Pose& pose, uint32_t node) const;
  // Forward kinematics: out[i] = global transform of node i (#N).
  void global_transforms(const Pose& pose, std::span<glm::mat4> out) const;
  std::vector<glm::mat4> global_transforms(const Pose& pose) const;

 private:
  std::vector<SkeletonNode> nodes_;
  std::vector<uint32_t> order_;
};

}  // namespace cagewrap
