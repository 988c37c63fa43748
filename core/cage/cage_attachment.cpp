#include "core/cage/cage_attachment.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "core/cage/cage_shells.h"
#include "core/geometry/geometry.h"
#include "core/character/mirror_names.h"
#include "core/character/part_relation.h"
#include "core/geometry/point_grid.h"
#include "core/character/skinning.h"

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

const char* attachment_mode_name(AttachmentMode m) {
  switch (m) {
    case AttachmentMode::kSmooth: return "smooth";
    case AttachmentMode::kSkinWeights: return "skin_weights";
    case AttachmentMode::kFitted: return "fitted";
    case AttachmentMode::kRigid: break;
  }
  return "rigid";
}

bool parse_attachment_mode(const std::string& name, AttachmentMode& out) {
  if (name == "rigid") out = AttachmentMode::kRigid;
  else if (name == "smooth") out = AttachmentMode::kSmooth;
  else if (name == "skin_weights") out = AttachmentMode::kSkinWeights;
  else if (name == "fitted") out = AttachmentMode::kFitted;
  else return false;
  return true;
}

AttachmentSettings assign_vertices(const AttachmentSettings& settings, std::span<const uint32_t> vertices,
                                   std::optional<uint32_t> node) {
  std::vector<uint32_t> sorted(vertices.begin(), vertices.end());
  std::sort(sorted.begin(), sorted.end());
  sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
  AttachmentSettings out = settings;
  out.overrides.clear();
  size_t i = 0;
  for (const AttachmentOverride& o : settings.overrides) {
    while (i < sorted.size() && sorted[i] < o.vertex) {
      if (node) out.overrides.push_back({sorted[i], *node});
      ++i;
    }
    if (i < sorted.size() && sorted[i] == o.vertex) {
      if (node) out.overrides.push_back({o.vertex, *node});
      ++i;
    } else {
      out.overrides.push_back(o);
    }
  }
  for (; i < sorted.size(); ++i)
    if (node) out.overrides.push_back({sorted[i], *node});
  return out;
}

std::optional<uint32_t> assigned_node(const AttachmentSettings& settings, uint32_t vertex) {
  auto it = std::lower_bound(settings.overrides.begin(), settings.overrides.end(), vertex,
                             [](const AttachmentOverride& o, uint32_t v) { return o.vertex < v; });
  if (it == settings.overrides.end() || it->vertex != vertex) return std::nullopt;
  return it->node;
}

std::vector<int32_t> overrides_per_vertex(const AttachmentSettings& settings, size_t num_vertices) {
  std::vector<int32_t> out(num_vertices, -1);
  for (const AttachmentOverride& o : settings.overrides)
    if (o.vertex < num_vertices) out[o.vertex] = static_cast<int32_t>(o.node);
  return out;
}

AttachmentSettings with_overrides_per_vertex(const AttachmentSettings& settings,
                                             std::span<const int32_t> per_vertex) {
  AttachmentSettings out = settings;
  out.overrides.clear();
  for (size_t v = 0; v < per_vertex.size(); ++v)
    if (per_vertex[v] >= 0)
      out.overrides.push_back({static_cast<uint32_t>(v), static_cast<uint32_t>(per_vertex[v])});
  return out;
}

Result<MirroredAssignment> mirror_assignment(const AttachmentSettings& settings, const Skeleton& skeleton,
                                             std::span<const glm::vec3> cage_rest,
                                             std::span<const uint32_t> vertices, double tolerance) {
  const size_t nv = cage_rest.size();
  std::vector<uint8_t> given(nv, 0), used(nv, 0);
  for (uint32_t v : vertices)
    if (v < nv) given[v] = 1;
  std::vector<uint32_t> all(nv);
  for (size_t v = 0; v < nv; ++v) all[v] = static_cast<uint32_t>(v);
  const std::vector<int32_t> source = mirror_x_counterparts(all, cage_rest, tolerance);
  std::vector<int32_t> per_vertex = overrides_per_vertex(settings, nv);
  std::vector<int32_t> result = per_vertex;
  for (size_t t = 0; t < nv; ++t) {
    const int32_t src = source[t];
    if (src < 0 || !given[src]) continue;
    used[src] = 1;
    const int32_t node = per_vertex[src];
    if (node < 0) {
      result[t] = -1;
      continue;
    }
    const int32_t m = mirror_node(skeleton, static_cast<uint32_t>(node));
    if (m < 0) {
      const std::string& name =
          static_cast<size_t>(node) < skeleton.size() ? skeleton.node(node).name : std::string("?");
      return make_error(ErrorCode::kInvalidArgument,
                        "cage vertex " + std::to_string(src) + " follows node '" + name +
                            "', which has no mirror: no node is named '" + mirror_name(name) + "'");
    }
    result[t] = m;
  }
  MirroredAssignment out;
  out.settings = with_overrides_per_vertex(settings, result);
  // overrides beyond the cage (none in a valid document) are kept as they were
  for (const AttachmentOverride& o : settings.overrides)
    if (o.vertex >= nv) out.settings.overrides.push_back(o);
  for (uint32_t v : vertices)
    if (v >= nv || !used[v]) out.unmatched.push_back(v);
  return out;
}

namespace {
double segment_dist2(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
  glm::dvec3 ab = b - a;
  double len2 = glm::dot(ab, ab);
  double t = len2 > 0 ? glm::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  glm::dvec3 d = p - (a + t * ab);
  return glm::dot(d, d);
}

double smoothstep01(double t) {
  t = std::clamp(t, 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}
}  // namespace

void append_influences(CageAttachment& att, size_t v, std::span<const std::pair<double, uint32_t>> raw) {
  double sum = 0;
  for (const auto& r : raw) sum += r.first;
  for (const auto& r : raw) {
    att.influence_joint.push_back(r.second);
    att.influence_weight.push_back(static_cast<float>(r.first / sum));
  }
  att.joint[v] = raw.front().second;
  att.influence_start.push_back(static_cast<uint32_t>(att.influence_joint.size()));
}

Result<CageAttachment> attach_to_closest_limb(const Character& character, std::span<const glm::vec3> cage_rest) {
  AttachmentSettings rigid;
  rigid.mode = AttachmentMode::kRigid;
  return attach_cage(character, cage_rest, rigid);
}

namespace {

// Sorts (weight, joint) pairs heaviest first and keeps at most kMaxAttachmentInfluences.
void keep_heaviest(std::vector<std::pair<double, uint32_t>>& raw) {
  std::stable_sort(raw.begin(), raw.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  if (raw.size() > kMaxAttachmentInfluences) raw.resize(kMaxAttachmentInfluences);
}

// The skin-weights attachment's source: the rest skin in a grid, and every point's influences as
// joints of the attachment's skin.
struct SkinWeightsSource {
  std::vector<glm::vec3> rest;
  PointGrid grid;
  std::vector<uint32_t> start, joint;
  std::vector<float> weight;
  // With a cage of several shells (closed pieces, core/rig/auto_cage.h wraps a character of separate
  // segments per piece): the shell of each cage vertex and one grid per shell over the skin points
  // it owns (the shell the point is deepest inside, else the nearest one), with their indices.
  std::vector<uint32_t> vertex_shell;  // #Vc, UINT32_MAX: the whole skin
  std::vector<PointGrid> shell_grid;
  std::vector<std::vector<uint32_t>> shell_points;
  std::vector<uint32_t> dominant;  // #P heaviest joint of each point (UINT32_MAX: none)
  std::vector<uint8_t> related;    // #J x #J: joints of one part (core/character/part_relation.h related_nodes, 1 step)
  size_t nj = 0;
  double delta = 0.0;
};

// The shells' points (see SkinWeightsSource) from the ownership.
void own_points_by_shell(SkinWeightsSource& s, const ShellOwnership& own) {
  if (own.shells <= 1) return;
  s.vertex_shell = own.vertex_shell;
  s.shell_points.assign(own.shells, {});
  for (uint32_t i = 0; i < own.point_shell.size(); ++i)
    if (own.point_shell[i] != kNoShell) s.shell_points[own.point_shell[i]].push_back(i);
  s.shell_grid.resize(own.shells);
  std::vector<glm::vec3> pts;
  for (uint32_t sh = 0; sh < own.shells; ++sh) {
    pts.clear();
    for (uint32_t i : s.shell_points[sh]) pts.push_back(s.rest[i]);
    if (!pts.empty()) s.shell_grid[sh] = PointGrid(pts);
  }
}

SkinWeightsSource skin_weights_source(const Character& character, std::span<const int32_t> joint_of) {
  SkinWeightsSource s;
  // The bind pose (the raw POSITION data), the space the cage is built and bound in: the node rest
  // pose may differ from it (the shared mannequin rests cross-legged over a T-pose bind), and
  // matching a bind-pose cage against the rest-posed skin attached right-leg cage vertices to
  // left-leg joints.
  for (const Primitive& p : character.primitives) s.rest.insert(s.rest.end(), p.positions.begin(), p.positions.end());
  const PointJoints pj = point_joint_nodes(character);
  s.start.assign(1, 0);
  for (size_t p = 0; p + 1 < pj.start.size(); ++p) {
    for (uint32_t i = pj.start[p]; i < pj.start[p + 1]; ++i)
      if (pj.node[i] < joint_of.size() && joint_of[pj.node[i]] >= 0) {
        s.joint.push_back(static_cast<uint32_t>(joint_of[pj.node[i]]));
        s.weight.push_back(pj.weight[i]);
      }
    s.start.push_back(static_cast<uint32_t>(s.joint.size()));
  }
  s.dominant.assign(s.start.size() - 1, UINT32_MAX);
  for (size_t p = 0; p + 1 < s.start.size(); ++p) {
    float best = 0.f;
    for (uint32_t k = s.start[p]; k < s.start[p + 1]; ++k)
      if (s.weight[k] > best) best = s.weight[k], s.dominant[p] = s.joint[k];
  }
  const Skin& skin = character.skins[0];
  s.nj = skin.joints.size();
  const std::vector<uint8_t> chained = part_relation(character);
  s.related.assign(s.nj * s.nj, 0);
  for (size_t a = 0; a < s.nj; ++a)
    for (size_t b = 0; b < s.nj; ++b)
      s.related[a * s.nj + b] = related_nodes(character.skeleton, chained, skin.joints[a], skin.joints[b], 1);
  s.grid = PointGrid(s.rest);
  const Aabb box = bounding_box(s.rest);
  s.delta = 1e-3 * glm::length(box.hi - box.lo);
  return s;
}

// (weight, joint) of the influences around p, heaviest first, at most kMaxAttachmentInfluences;
// empty when no skinned point is near.
void transferred_weights(const SkinWeightsSource& s, size_t v, const glm::dvec3& p, size_t nj,
                         std::vector<std::pair<double, uint32_t>>& raw) {
  thread_local std::vector<std::pair<double, uint32_t>> near;
  thread_local std::vector<double> acc;
  acc.assign(nj, 0.0);
  const uint32_t shell = v < s.vertex_shell.size() ? s.vertex_shell[v] : UINT32_MAX;
  if (shell != UINT32_MAX && !s.shell_points[shell].empty()) {
    s.shell_grid[shell].nearest(p, kTransferNeighbours, near);
    for (auto& n : near) n.second = s.shell_points[shell][n.second];
  } else {
    s.grid.nearest(p, kTransferNeighbours, near);
  }
  // only the part of the nearest point: a cage vertex where the hand touches the thigh (or one leg
  // the other) takes the weights of one of them, never a blend of two unrelated limbs
  const uint32_t part = near.empty() ? UINT32_MAX : s.dominant[near.front().second];
  for (const auto& [d2, i] : near) {
    const uint32_t d = s.dominant[i];
    if (part != UINT32_MAX && d != UINT32_MAX && !s.related[size_t(part) * s.nj + d]) continue;
    const double w = 1.0 / (std::sqrt(d2) + s.delta);
    for (uint32_t k = s.start[i]; k < s.start[i + 1]; ++k) acc[s.joint[k]] += w * s.weight[k];
  }
  for (size_t j = 0; j < nj; ++j)
    if (acc[j] > 0) raw.emplace_back(acc[j], static_cast<uint32_t>(j));
  keep_heaviest(raw);
}

}  // namespace

Result<CageAttachment> attach_cage(const Character& character, std::span<const glm::vec3> cage_rest,
                                   const AttachmentSettings& settings, std::span<const Tri> cage_elements) {
  if (character.skins.empty())
    return make_error(ErrorCode::kInvalidArgument, character.source + ": has no skin (no skeleton to attach the cage to)");
  CageAttachment att;
  att.skin = 0;
  att.limbs = skin_limbs(character, 0);
  if (att.limbs.empty())
    return make_error(ErrorCode::kInvalidArgument, character.source + ": its skin has no joints");
  const Skin& skin = character.skins[att.skin];
  const size_t nj = skin.joints.size();
  std::vector<int32_t> joint_of(character.skeleton.size(), -1);
  for (size_t j = 0; j < nj; ++j)
    if (skin.joints[j] < joint_of.size()) joint_of[skin.joints[j]] = static_cast<int32_t>(j);
  for (const AttachmentOverride& o : settings.overrides) {
    if (o.vertex >= cage_rest.size())
      return make_error(ErrorCode::kIndexOutOfRange, "the attachment assigns cage vertex " +
                                                         std::to_string(o.vertex) + ", but the cage has " +
                                                         std::to_string(cage_rest.size()) + " vertices");
    if (o.node >= joint_of.size() || joint_of[o.node] < 0) {
      std::string name = o.node < character.skeleton.size() ? "'" + character.skeleton.node(o.node).name + "'"
                                                            : std::to_string(o.node);
      return make_error(ErrorCode::kInvalidArgument,
                        "cage vertex " + std::to_string(o.vertex) + " is assigned to node " + name +
                            ", which is not a joint of skin '" + skin.name + "'");
    }
  }
  const bool smooth = settings.mode == AttachmentMode::kSmooth;
  std::optional<SkinWeightsSource> transfer;
  ShellOwnership own;
  if (!cage_elements.empty()) {
    std::vector<glm::vec3> skin;
    std::vector<Tri> tris;
    for (const Primitive& p : character.primitives) {
      const uint32_t base = static_cast<uint32_t>(skin.size());
      skin.insert(skin.end(), p.positions.begin(), p.positions.end());
      for (const Tri& t : p.triangles) tris.push_back({t[0] + base, t[1] + base, t[2] + base});
    }
    own = cage_shell_ownership(cage_rest, cage_elements, skin, tris);
    if (own.shells > 1) {
      att.vertex_shell = own.vertex_shell;
      att.point_shell = own.piece_shell;
    }
  }
  if (settings.mode == AttachmentMode::kSkinWeights || settings.mode == AttachmentMode::kFitted) {
    transfer = skin_weights_source(character, joint_of);
    own_points_by_shell(*transfer, own);
  }
  const double width = settings.smooth_width > 0 && std::isfinite(settings.smooth_width)
                           ? settings.smooth_width
                           : AttachmentSettings{}.smooth_width;
  const size_t nv = cage_rest.size();
  att.joint.resize(nv);
  att.influence_start.assign(1, 0);
  std::vector<double> joint_dist(nj);
  std::vector<std::pair<double, uint32_t>> raw;  // (weight, joint)
  size_t next_override = 0;
  for (size_t v = 0; v < nv; ++v) {
    while (next_override < settings.overrides.size() && settings.overrides[next_override].vertex < v)
      ++next_override;
    raw.clear();
    if (next_override < settings.overrides.size() && settings.overrides[next_override].vertex == v) {
      raw.emplace_back(1.0, static_cast<uint32_t>(joint_of[settings.overrides[next_override].node]));
    } else if (transfer) {
      transferred_weights(*transfer, v, glm::dvec3(cage_rest[v]), nj, raw);
    }
    if (raw.empty()) {
      glm::dvec3 p(cage_rest[v]);
      double best = 1e300;
      uint32_t best_joint = att.limbs.front().joint;
      std::fill(joint_dist.begin(), joint_dist.end(), 1e300);
      for (const Limb& l : att.limbs) {
        double d2 = segment_dist2(p, l.a, l.b);
        if (d2 < best) {
          best = d2;
          best_joint = l.joint;
        }
        joint_dist[l.joint] = std::min(joint_dist[l.joint], d2);
      }
      if (!smooth) {
        raw.emplace_back(1.0, best_joint);
      } else {
        const double d_min = std::sqrt(best);
        raw.emplace_back(1.0, best_joint);
        for (size_t j = 0; j < nj; ++j) {
          if (j == best_joint || joint_dist[j] >= 1e300) continue;
          const double d = std::sqrt(joint_dist[j]);
          double f;
          if (d_min > 0) f = 1.0 - smoothstep01((d / d_min - 1.0) / width);
          else f = d == 0 ? 1.0 : 0.0;
          if (f > 0) raw.emplace_back(f, static_cast<uint32_t>(j));
        }
        keep_heaviest(raw);
      }
    }
    append_influences(att, v, raw);
  }
  att.label_joint = att.joint;
  return att;
}

void pose_cage(const CageAttachment& att, std::span<const glm::mat4> skinning, std::span<const glm::vec3> cage_rest,
               std::span<glm::vec3> out, std::span<glm::dmat3> linear, std::span<glm::mat4> vertex_skinning) {
  const bool csr = att.influence_start.size() == cage_rest.size() + 1;
  for (size_t v = 0; v < cage_rest.size(); ++v) {
    glm::mat4 m;
    if (!csr || att.influence_start[v + 1] - att.influence_start[v] == 1) {
      m = skinning[csr ? att.influence_joint[att.influence_start[v]] : att.joint[v]];
    } else {
      m = glm::mat4(0.0f);
      for (uint32_t i = att.influence_start[v]; i < att.influence_start[v + 1]; ++i)
        m += att.influence_weight[i] * skinning[att.influence_joint[i]];
    }
    out[v] = glm::vec3(m * glm::vec4(cage_rest[v], 1.0f));
    if (!linear.empty()) linear[v] = glm::dmat3(glm::mat3(m));
    if (!vertex_skinning.empty()) vertex_skinning[v] = m;
  }
}

}  // namespace cagewrap
