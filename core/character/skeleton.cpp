#include "core/character/skeleton.h"

#include <algorithm>

#include <glm/gtc/matrix_transform.hpp>

namespace cagewrap {

glm::mat4 Trs::matrix() const {
  glm::mat4 m = glm::mat4_cast(rotation);
  m[0] *= scale.x;
  m[1] *= scale.y;
  m[2] *= scale.z;
  m[3] = glm::vec4(translation, 1.0f);
  return m;
}

static std::string node_label(const std::vector<SkeletonNode>& nodes, size_t i) {
  return "node " + std::to_string(i) + (nodes[i].name.empty() ? "" : " ('" + nodes[i].name + "')");
}

Result<Skeleton> Skeleton::create(std::vector<SkeletonNode> nodes, const std::string& what) {
  const size_t n = nodes.size();
  for (size_t i = 0; i < n; ++i) {
    int32_t p = nodes[i].parent;
    if (p < -1 || p >= static_cast<int32_t>(n))
      return make_error(ErrorCode::kIndexOutOfRange, what + ": " + node_label(nodes, i) + " has parent " +
                                                         std::to_string(p) + ", but there are " +
                                                         std::to_string(n) + " nodes");
  }
  // Depth of each node by walking up; a walk longer than n steps means a cycle.
  std::vector<int32_t> depth(n, -1);
  for (size_t i = 0; i < n; ++i) {
    std::vector<uint32_t> path;
    int32_t cur = static_cast<int32_t>(i);
    while (cur >= 0 && depth[cur] < 0) {
      path.push_back(static_cast<uint32_t>(cur));
      if (path.size() > n) {
        std::string cycle;
        // The last n+1 steps contain the cycle; print it from its first repeat.
        uint32_t start = path.back();
        size_t first = 0;
        while (path[first] != start) ++first;
        for (size_t k = first; k < path.size(); ++k) cycle += (k > first ? " -> " : "") + std::to_string(path[k]);
        return make_error(ErrorCode::kParse, what + ": " + node_label(nodes, start) +
                                                 " is its own ancestor (cycle " + cycle +
                                                 "); the node hierarchy must be a tree");
      }
      cur = nodes[cur].parent;
    }
    int32_t d = cur < 0 ? -1 : depth[cur];
    for (auto it = path.rbegin(); it != path.rend(); ++it) depth[*it] = ++d;
  }
  Skeleton s;
  s.order_.resize(n);
  for (size_t i = 0; i < n; ++i) s.order_[i] = static_cast<uint32_t>(i);
  std::stable_sort(s.order_.begin(), s.order_.end(), [&](uint32_t a, uint32_t b) { return depth[a] < depth[b]; });
  s.nodes_ = std::move(nodes);
  return s;
}

std::vector<uint32_t> Skeleton::children(uint32_t node) const {
  std::vector<uint32_t> out;
  for (size_t i = 0; i < nodes_.size(); ++i)
    if (nodes_[i].parent == static_cast<int32_t>(node)) out.push_back(static_cast<uint32_t>(i));
  return out;
}

int32_t Skeleton::find(const std::string& name) const {
  for (size_t i = 0; i < nodes_.size(); ++i)
    if (nodes_[i].name == name) return static_cast<int32_t>(i);
  return -1;
}

Pose Skeleton::rest_pose() const {
  Pose p;
  p.local.resize(nodes_.size());
  for (size_t i = 0; i < nodes_.size(); ++i) p.local[i] = nodes_[i].rest;
  p.morph_weights.resize(nodes_.size());
  return p;
}

glm::mat4 Skeleton::local_matrix(const Pose& pose, uint32_t node) const {
  return nodes_[node].has_matrix ? nodes_[node].matrix : pose.local[node].matrix();
}

void Skeleton::global_transforms(const Pose& pose, std::span<glm::mat4> out) const {
  for (uint32_t i : order_) {
    glm::mat4 local = local_matrix(pose, i);
    out[i] = nodes_[i].parent < 0 ? local : out[nodes_[i].parent] * local;
  }
}

std::vector<glm::mat4> Skeleton::global_transforms(const Pose& pose) const {
  std::vector<glm::mat4> out(nodes_.size());
  global_transforms(pose, out);
  return out;
}

}  // namespace cagewrap
