#include "core/character/part_relation.h"

#include <string>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "core/geometry/mesh.h"

#include "core/character/skinning.h"

namespace cagewrap {

std::vector<uint32_t> dominant_joint_nodes(const Character& character) {
  const PointJoints pj = point_joint_nodes(character);
  std::vector<uint32_t> out(pj.start.size() - 1, kNoJointNode);
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

std::vector<glm::vec3> bind_node_heads(const Character& character) {
  const Skeleton& sk = character.skeleton;
  const std::vector<glm::mat4> rest = sk.global_transforms(sk.rest_pose());
  std::vector<glm::vec3> head(sk.size());
  for (size_t i = 0; i < head.size(); ++i) head[i] = glm::vec3(rest[i][3]);
  for (const Skin& skin : character.skins)
    for (size_t j = 0; j < skin.joints.size(); ++j)
      if (skin.joints[j] < head.size()) head[skin.joints[j]] = glm::vec3(glm::inverse(glm::dmat4(skin.inverse_bind[j]))[3]);
  return head;
}

std::vector<uint8_t> chained_nodes(const Character& character, double reach) {
  const Skeleton& sk = character.skeleton;
  const size_t n = sk.size();
  const std::vector<glm::vec3> head = bind_node_heads(character);
  std::vector<uint8_t> out(n * n, 0);
  for (size_t a = 0; a < n; ++a) {
    out[a * n + a] = 1;
    double length = 0.0;
    size_t steps = 0;
    for (int32_t x = static_cast<int32_t>(a), p = sk.node(a).parent; p >= 0 && steps < n;
         x = p, p = sk.node(static_cast<size_t>(p)).parent, ++steps) {
      length += glm::length(glm::dvec3(head[static_cast<size_t>(x)]) - glm::dvec3(head[static_cast<size_t>(p)]));
      if (!(length <= reach)) break;
      out[a * n + size_t(p)] = out[size_t(p) * n + a] = 1;
    }
  }
  return out;
}

std::vector<uint8_t> coskinned_nodes(const Character& character, float weight, size_t points) {
  const size_t n = character.skeleton.size();
  std::vector<uint32_t> count(n * n, 0);
  const PointJoints pj = point_joint_nodes(character);
  for (size_t p = 0; p + 1 < pj.start.size(); ++p)
    for (uint32_t i = pj.start[p]; i < pj.start[p + 1]; ++i)
      for (uint32_t k = i + 1; k < pj.start[p + 1]; ++k)
        if (pj.weight[i] >= weight && pj.weight[k] >= weight && pj.node[i] < n && pj.node[k] < n) {
          ++count[size_t(pj.node[i]) * n + pj.node[k]];
          ++count[size_t(pj.node[k]) * n + pj.node[i]];
        }
  std::vector<uint8_t> out(n * n, 0);
  // only across one bone in between (the chest and the upper arm, over the shoulder): limbs that
  // merely touch (a hand resting on the thigh, whose weights a smoothing pass blended) stay apart
  for (size_t a = 0; a < n; ++a)
    for (size_t b = 0; b < n; ++b)
      out[a * n + b] = a == b || (count[a * n + b] >= points &&
                                  related_nodes(character.skeleton, {}, uint32_t(a), uint32_t(b), 2));
  return out;
}

std::vector<uint8_t> part_relation(const Character& character) {
  std::vector<uint8_t> r = chained_nodes(character, chain_reach(character));
  const std::vector<uint8_t> c = coskinned_nodes(character);
  for (size_t i = 0; i < r.size() && i < c.size(); ++i) r[i] |= c[i];
  return r;
}

double chain_reach(const Character& character) {
  Aabb box;
  for (const Primitive& p : character.primitives)
    for (const glm::vec3& q : p.positions) box.extend(glm::dvec3(q));
  return box.empty() ? 0.0 : 0.05 * box.diagonal();
}

bool related_nodes(const Skeleton& skeleton, std::span<const uint8_t> chained, uint32_t a, uint32_t b, uint32_t steps) {
  const size_t n = skeleton.size();
  if (a >= n || b >= n) return false;
  if (chained.size() == n * n && chained[size_t(a) * n + b]) return true;
  // within `steps` edges of the hierarchy: through their nearest common ancestor
  std::vector<uint32_t> up;
  for (int32_t x = static_cast<int32_t>(a); x >= 0 && up.size() <= steps; x = skeleton.node(static_cast<size_t>(x)).parent)
    up.push_back(static_cast<uint32_t>(x));
  uint32_t j = 0;
  for (int32_t y = static_cast<int32_t>(b); y >= 0 && j <= steps; y = skeleton.node(static_cast<size_t>(y)).parent, ++j)
    for (size_t i = 0; i < up.size() && i + j <= steps; ++i)
      if (up[i] == static_cast<uint32_t>(y)) return true;
  return false;
}

}  // namespace cagewrap
