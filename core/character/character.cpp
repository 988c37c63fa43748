#include "core/character/character.h"

#include <algorithm>
#include <charconv>

namespace cagewrap {

std::string Primitive::label() const {
  return "mesh " + std::to_string(mesh) + (mesh_name.empty() ? "" : " ('" + mesh_name + "')") + " primitive " +
         std::to_string(primitive);
}

Status add_root_node(Character& c, const std::string& name, const Trs& t) {
  std::vector<SkeletonNode> nodes = c.skeleton.nodes();
  const int32_t root = static_cast<int32_t>(nodes.size());
  // a root that only holds skinned meshes stays a root: its transform does not move them (their joints' do), and
  // glTF wants such a node at the root
  std::vector<uint8_t> skinned_only(nodes.size(), 0), has_child(nodes.size(), 0);
  for (const Primitive& p : c.primitives)
    if (p.node < nodes.size() && p.skin >= 0 && skinned_only[p.node] != 2) skinned_only[p.node] = 1;
  for (const Primitive& p : c.primitives)
    if (p.node < nodes.size() && p.skin < 0) skinned_only[p.node] = 2;
  for (const SkeletonNode& n : nodes)
    if (n.parent >= 0) has_child[size_t(n.parent)] = 1;
  for (size_t i = 0; i < nodes.size(); ++i)
    if (nodes[i].parent < 0 && !(skinned_only[i] == 1 && !has_child[i])) nodes[i].parent = root;
  SkeletonNode top;
  top.name = name;
  top.rest = t;
  nodes.push_back(std::move(top));
  auto sk = Skeleton::create(std::move(nodes), c.source);
  if (!sk) return sk.error();
  c.skeleton = std::move(sk).value();
  return Ok{};
}

size_t Character::num_vertices() const {
  size_t n = 0;
  for (const Primitive& p : primitives) n += p.num_vertices();
  return n;
}

size_t Character::num_triangles() const {
  size_t n = 0;
  for (const Primitive& p : primitives) n += p.triangles.size();
  return n;
}

size_t Character::num_joints() const {
  std::vector<uint32_t> all;
  for (const Skin& s : skins) all.insert(all.end(), s.joints.begin(), s.joints.end());
  std::sort(all.begin(), all.end());
  return static_cast<size_t>(std::unique(all.begin(), all.end()) - all.begin());
}

int32_t Character::find_clip(const std::string& name_or_index) const {
  for (size_t i = 0; i < clips.size(); ++i)
    if (clips[i].name == name_or_index) return static_cast<int32_t>(i);
  int32_t index = -1;
  const char* end = name_or_index.data() + name_or_index.size();
  auto [ptr, ec] = std::from_chars(name_or_index.data(), end, index);
  if (ec == std::errc() && ptr == end && index >= 0 && index < static_cast<int32_t>(clips.size())) return index;
  return -1;
}

}  // namespace cagewrap
