#include "core/character/skinning.h"

#include <tbb/parallel_for.h>

namespace cagewrap {

void joint_matrices(const Skin& skin, std::span<const glm::mat4> globals, std::span<glm::mat4> out) {
  for (size_t j = 0; j < skin.joints.size(); ++j) out[j] = globals[skin.joints[j]] * skin.inverse_bind[j];
}

void skin_primitive(const Primitive& prim, std::span<const glm::mat4> joints, const glm::mat4& node_global,
                    std::span<const float> morph_weights, std::span<glm::vec3> out) {
  std::span<const float> mw = morph_weights.empty() ? std::span<const float>(prim.morph_weights) : morph_weights;
  const size_t targets = std::min(mw.size(), prim.morph_targets.size());
  const bool skinned = prim.skin >= 0 && !prim.influence_start.empty();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, prim.num_vertices(), 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t v = r.begin(); v != r.end(); ++v) {
      glm::vec3 p = prim.positions[v];
      for (size_t t = 0; t < targets; ++t)
        if (mw[t] != 0.0f) p += mw[t] * prim.morph_targets[t][v];
      glm::vec4 h(p, 1.0f);
      if (skinned) {
        glm::vec3 acc(0.0f);
        for (uint32_t k = prim.influence_start[v]; k < prim.influence_start[v + 1]; ++k)
          acc += prim.influence_weight[k] * glm::vec3(joints[prim.influence_joint[k]] * h);
        out[v] = acc;
      } else {
        out[v] = glm::vec3(node_global * h);
      }
    }
  });
}

std::vector<glm::vec3> skin_character(const Character& c, const Pose& pose) {
  std::vector<glm::mat4> globals = c.skeleton.global_transforms(pose);
  std::vector<std::vector<glm::mat4>> joints(c.skins.size());
  for (size_t s = 0; s < c.skins.size(); ++s) {
    joints[s].resize(c.skins[s].joints.size());
    joint_matrices(c.skins[s], globals, joints[s]);
  }
  std::vector<glm::vec3> out(c.num_vertices());
  size_t offset = 0;
  for (const Primitive& p : c.primitives) {
    std::span<const glm::mat4> jm = p.skin >= 0 ? std::span<const glm::mat4>(joints[p.skin]) : std::span<const glm::mat4>();
    std::span<const float> mw;
    if (p.node < pose.morph_weights.size()) mw = pose.morph_weights[p.node];
    skin_primitive(p, jm, globals[p.node], mw, std::span(out).subspan(offset, p.num_vertices()));
    offset += p.num_vertices();
  }
  return out;
}

Pose sample_pose(const Character& c, int32_t clip, double t, bool loop) {
  Pose pose = c.skeleton.rest_pose();
  if (clip >= 0 && clip < static_cast<int32_t>(c.clips.size())) {
    const Clip& k = c.clips[clip];
    apply_clip(k, clip_time(t, k.duration, loop), pose);
  }
  return pose;
}

PolyMesh combined_topology(const Character& c) {
  PolyMesh m;
  m.positions.reserve(c.num_vertices());
  uint32_t offset = 0;
  for (const Primitive& p : c.primitives) {
    m.positions.insert(m.positions.end(), p.positions.begin(), p.positions.end());
    for (const Tri& t : p.triangles) m.add_face({t[0] + offset, t[1] + offset, t[2] + offset});
    offset += static_cast<uint32_t>(p.num_vertices());
  }
  return m;
}

PointJoints point_joint_nodes(const Character& character) {
  PointJoints out;
  out.start.reserve(character.num_vertices() + 1);
  for (const Primitive& prim : character.primitives) {
    const bool skinned = prim.skin >= 0 && size_t(prim.skin) < character.skins.size() &&
                         prim.influence_start.size() == prim.num_vertices() + 1;
    for (size_t v = 0; v < prim.num_vertices(); ++v) {
      if (skinned) {
        const Skin& skin = character.skins[static_cast<size_t>(prim.skin)];
        for (uint32_t i = prim.influence_start[v]; i < prim.influence_start[v + 1]; ++i)
          if (prim.influence_weight[i] > 0.f && prim.influence_joint[i] < skin.joints.size()) {
            out.node.push_back(skin.joints[prim.influence_joint[i]]);
            out.weight.push_back(prim.influence_weight[i]);
          }
      } else if (prim.node < character.skeleton.size()) {
        out.node.push_back(prim.node);
        out.weight.push_back(1.f);
      }
      out.start.push_back(static_cast<uint32_t>(out.node.size()));
    }
  }
  return out;
}

}  // namespace cagewrap
