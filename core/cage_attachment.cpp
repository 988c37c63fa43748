#include "core/cage_attachment.h"

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "core/geometry.h"

namespace cagewrap {

std::vector<Limb> skin_limbs(const Character& character, uint32_t skin_index) {
  const Skin& skin = character.skins[skin_index];
  const size_t nj = skin.joints.size();
  std::vector<glm::dvec3> head(nj);
  std::vector<glm::dmat4> bind(nj);
  for (size_t j = 0; j < nj; ++j) {
    bind[j] = glm::inverse(glm::dmat4(skin.inverse_bind[j]));
    head[j] = glm::dvec3(bind[j][3]);
  }
  // skin joint of each skeleton node, to find children within the skin
  std::vector<int32_t> joint_of(character.skeleton.size(), -1);
  for (size_t j = 0; j < nj; ++j) joint_of[skin.joints[j]] = static_cast<int32_t>(j);
  std::vector<Limb> limbs;
  std::vector<double> parent_len(nj, 0.0);
  std::vector<uint8_t> has_child(nj, 0);
  for (size_t j = 0; j < nj; ++j) {
    for (uint32_t child : character.skeleton.children(skin.joints[j])) {
      int32_t c = joint_of[child];
      if (c < 0) continue;
      double len = glm::length(head[static_cast<size_t>(c)] - head[j]);
      if (len <= 0) continue;
      limbs.push_back({static_cast<uint32_t>(j), head[j], head[static_cast<size_t>(c)]});
      has_child[j] = 1;
      parent_len[static_cast<size_t>(c)] = len;
    }
  }
  for (size_t j = 0; j < nj; ++j) {
    if (has_child[j]) continue;
    // a leaf: half its parent bone's length along its own Y axis (the glTF/Blender bone axis)
    glm::dvec3 axis = glm::dvec3(bind[j][1]);
    double axis_len = glm::length(axis);
    double len = parent_len[j] > 0 ? 0.5 * parent_len[j] : 0.05;
    glm::dvec3 dir = axis_len > 0 ? axis / axis_len : glm::dvec3(0, 1, 0);
    limbs.push_back({static_cast<uint32_t>(j), head[j], head[j] + len * dir});
  }
  return limbs;
}

namespace {
double segment_dist2(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
  glm::dvec3 ab = b - a;
  double len2 = glm::dot(ab, ab);
  double t = len2 > 0 ? glm::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  glm::dvec3 d = p - (a + t * ab);
  return glm::dot(d, d);
}
}  // namespace

Result<CageAttachment> attach_to_closest_limb(const Character& character, std::span<const glm::vec3> cage_rest) {
  if (character.skins.empty())
    return make_error(ErrorCode::kInvalidArgument, character.source + ": has no skin (no skeleton to attach the cage to)");
  CageAttachment att;
  att.skin = 0;
  att.limbs = skin_limbs(character, 0);
  if (att.limbs.empty())
    return make_error(ErrorCode::kInvalidArgument, character.source + ": its skin has no joints");
  att.joint.resize(cage_rest.size());
  for (size_t v = 0; v < cage_rest.size(); ++v) {
    glm::dvec3 p(cage_rest[v]);
    double best = 1e300;
    for (const Limb& l : att.limbs) {
      double d2 = segment_dist2(p, l.a, l.b);
      if (d2 < best) {
        best = d2;
        att.joint[v] = l.joint;
      }
    }
  }
  return att;
}

void pose_cage(const CageAttachment& att, std::span<const glm::mat4> skinning, std::span<const glm::vec3> cage_rest,
               std::span<glm::vec3> out, std::span<glm::dmat3> linear) {
  for (size_t v = 0; v < cage_rest.size(); ++v) {
    const glm::mat4& m = skinning[att.joint[v]];
    out[v] = glm::vec3(m * glm::vec4(cage_rest[v], 1.0f));
    if (!linear.empty()) linear[v] = glm::dmat3(glm::mat3(m));
  }
}

}  // namespace cagewrap
