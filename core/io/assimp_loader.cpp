#include "core/io/assimp_loader.h"

#include <algorithm>
#include <cctype>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <fstream>
#include <map>
#include <optional>
#include <regex>
#include <set>
#include <string_view>

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "core/io/gltf_writer.h"
#include "core/io/skin_weights.h"

namespace cagewrap {
namespace {

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
  return ext;
}

glm::mat4 to_glm(const aiMatrix4x4& m) {  // assimp is row-major (a1..a4 the first row), glm column-major
  glm::mat4 g;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) g[c][r] = m[r][c];
  return g;
}

// The node's local transform as TRS, or as a matrix when it does not decompose (shear).
void set_local(SkeletonNode& n, const aiMatrix4x4& m) {
  aiVector3D s, t;
  aiQuaternion q;
  m.Decompose(s, q, t);
  n.rest.translation = {t.x, t.y, t.z};
  n.rest.rotation = glm::normalize(glm::quat(q.w, q.x, q.y, q.z));
  n.rest.scale = {s.x, s.y, s.z};
  const glm::mat4 back = n.rest.matrix(), given = to_glm(m);
  float gap = 0.0f, size = 0.0f;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) {
      gap = std::max(gap, std::abs(back[c][r] - given[c][r]));
      size = std::max(size, std::abs(given[c][r]));
    }
  if (gap > 1e-5f * std::max(1.0f, size)) {
    n.has_matrix = true;
    n.matrix = given;
  }
}

template <class T>
bool metadata(const aiScene* s, const char* key, T& out) {
  return s->mMetaData && s->mMetaData->Get(key, out);
}

std::string short_number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", x);
  return text;
}

// The shortest turn of the axis `up` (0 X, 1 Y, 2 Z; sign) onto +Y.
glm::quat turn_to_y_up(int up, int sign) {
  const glm::vec3 file_up = float(sign < 0 ? -1 : 1) * glm::vec3(up == 0, up == 1, up == 2);
  return glm::quat(glm::normalize(file_up), glm::vec3(0, 1, 0));
}

// Character::to_metres of a file kept in its own units and axes (none when they are metres, Y up).
std::optional<Trs> kept_units_to_metres(const AssimpUnits& units) {
  const std::string& a = units.up_axis;  // "+Z"
  const int sign = !a.empty() && a[0] == '-' ? -1 : 1, up = a.size() == 2 ? std::clamp(a[1] - 'X', 0, 2) : 1;
  if (units.metres_per_unit == 1.0 && up == 1 && sign > 0) return std::nullopt;
  Trs t;
  t.rotation = turn_to_y_up(up, sign);
  t.scale = glm::vec3(float(units.metres_per_unit));
  return t;
}

std::string axis_name(int axis, int sign) { return std::string(sign < 0 ? "-" : "+") + "XYZ"[std::clamp(axis, 0, 2)]; }

// What a Collada file says of its units and up axis (<asset>: <unit meter="0.01"/>, <up_axis>Z_UP</up_axis>), which
// assimp applies itself (the unit as a scale of the root node) and does not report: read from the file's head.
struct ColladaAsset {
  double metres = 1.0;
  int up = 1;  // 0 X, 1 Y, 2 Z
};

ColladaAsset read_collada_asset(std::string_view head) {
  ColladaAsset a;
  static const std::regex kUnit(R"(<unit\b[^>]*\bmeter\s*=\s*["']\s*([0-9.eE+-]+)\s*["'])");
  static const std::regex kUp(R"(<up_axis>\s*([XYZ])_UP\s*</up_axis>)");
  std::match_results<std::string_view::const_iterator> m;
  if (std::regex_search(head.begin(), head.end(), m, kUnit)) {
    const double metres = std::strtod(m[1].str().c_str(), nullptr);
    if (std::isfinite(metres) && metres > 0.0) a.metres = metres;
  }
  if (std::regex_search(head.begin(), head.end(), m, kUp)) a.up = m[1].str()[0] - 'X';
  return a;
}

class Importer {
 public:
  // `collada`: the file is Collada, with that <asset> (assimp scaled its root node by the unit, which is undone
  // here: lengths are brought to metres like every format's).
  Importer(const aiScene* scene, const std::string& file, std::optional<ColladaAsset> collada)
      : s_(scene), file_(file), collada_(collada) {}

  Result<Character> run(const CharacterLoadOptions& options, AssimpUnits* units_out) {
    Character c;
    c.source = file_;
    if (!s_->mRootNode) return make_error(ErrorCode::kParse, file_ + ": the file has no node hierarchy");
    // nodes, parents before children
    std::vector<SkeletonNode> nodes;
    std::vector<const aiNode*> order;
    std::vector<std::pair<const aiNode*, int32_t>> stack{{s_->mRootNode, -1}};
    while (!stack.empty()) {
      auto [n, parent] = stack.back();
      stack.pop_back();
      const uint32_t index = uint32_t(nodes.size());
      SkeletonNode sn;
      sn.name = n->mName.C_Str();
      sn.parent = parent;
      aiMatrix4x4 local = n->mTransformation;
      if (n == s_->mRootNode && collada_ && collada_->metres != 1.0) {  // assimp's scale by the unit, undone
        aiMatrix4x4 undo;
        aiMatrix4x4::Scaling(aiVector3D(ai_real(1.0 / collada_->metres)), undo);
        local = local * undo;
      }
      set_local(sn, local);
      if (sn.has_matrix && animated(sn.name)) sn.has_matrix = false;  // an animated node is TRS (its keys replace it)
      nodes.push_back(sn);
      order.push_back(n);
      index_[n] = index;
      by_name_.emplace(sn.name, index);
      for (unsigned k = n->mNumChildren; k-- > 0;) stack.push_back({n->mChildren[k], int32_t(index)});
    }
    // units and axes
    AssimpUnits units;
    float unit_cm = 0.0f;
    double unit_cm_d = 0.0;
    if (metadata(s_, "UnitScaleFactor", unit_cm) && unit_cm > 0.0f) units.metres_per_unit = unit_cm / 100.0;
    else if (metadata(s_, "UnitScaleFactor", unit_cm_d) && unit_cm_d > 0.0) units.metres_per_unit = unit_cm_d / 100.0;
    int32_t up = 1, up_sign = 1;
    metadata(s_, "UpAxis", up);
    metadata(s_, "UpAxisSign", up_sign);
    if (collada_) {
      units.metres_per_unit = collada_->metres;
      up = collada_->up;
      up_sign = 1;
    }
    units.up_axis = axis_name(up, up_sign);
    glm::quat turn(1.0f, 0.0f, 0.0f, 0.0f);  // applied to the root nodes: the file's up to +Y
    if (!options.keep_units) {
      turn = turn_to_y_up(up, up_sign);
      units.converted = units.metres_per_unit != 1.0 || up != 1 || up_sign < 0;
    } else {
      c.to_metres = kept_units_to_metres(units);
    }
    scale_ = options.keep_units ? 1.0f : float(units.metres_per_unit);
    for (SkeletonNode& n : nodes) {
      if (n.has_matrix) {
        n.matrix[3] = glm::vec4(glm::vec3(n.matrix[3]) * scale_, 1.0f);
      } else {
        n.rest.translation *= scale_;
      }
      if (n.parent < 0 && turn != glm::quat(1, 0, 0, 0)) {
        if (n.has_matrix) {
          n.matrix = glm::mat4_cast(turn) * n.matrix;
        } else {
          n.rest.translation = turn * n.rest.translation;
          n.rest.rotation = glm::normalize(turn * n.rest.rotation);
        }
      }
    }
    auto sk = Skeleton::create(nodes, file_);
    if (!sk) return sk.error();
    c.skeleton = std::move(sk).value();
    rest_global_ = c.skeleton.global_transforms(c.skeleton.rest_pose());
    if (units.converted)
      c.warnings.push_back(file_ + ": brought to metres, Y up (the file: " + short_number(units.metres_per_unit) + " m a unit, " +
                           units.up_axis + " up); --keep-units leaves it as it is");
    // meshes, one primitive per (assimp mesh, instancing node); the primitives of one node form one mesh, as a
    // glTF node holds one mesh (the node's index is the mesh's)
    for (size_t k = 0; k < order.size(); ++k)
      for (unsigned m = 0; m < order[k]->mNumMeshes; ++m) {
        const unsigned mi = order[k]->mMeshes[m];
        if (mi >= s_->mNumMeshes) continue;
        if (auto st = add_mesh(c, mi, uint32_t(k)); !st) return st.error();
      }
    for (size_t k = 0, mesh = 0; k < c.primitives.size(); ++k) {
      if (k > 0 && c.primitives[k].node != c.primitives[k - 1].node) ++mesh;
      c.primitives[k].mesh = uint32_t(mesh);
    }
    if (c.primitives.empty()) return make_error(ErrorCode::kEmpty, file_ + ": the file has no triangle mesh");
    for (const SkeletonNode& n : nodes) parent_.push_back(n.parent);
    c.clips = build_clips(turn);
    c.warnings.insert(c.warnings.end(), warnings_.begin(), warnings_.end());
    if (units_out) *units_out = units;
    return c;
  }

 private:
  Status add_mesh(Character& c, unsigned mi, uint32_t node) {
    const aiMesh* m = s_->mMeshes[mi];
    const std::string label = file_ + ": mesh " + std::to_string(mi) + (m->mName.length ? " ('" + std::string(m->mName.C_Str()) + "')" : "");
    if (!(m->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) return Ok{};  // points and lines
    Primitive p;
    p.mesh_name = m->mName.C_Str();
    p.node = node;
    p.positions.reserve(m->mNumVertices);
    for (unsigned v = 0; v < m->mNumVertices; ++v) p.positions.emplace_back(m->mVertices[v].x * scale_, m->mVertices[v].y * scale_, m->mVertices[v].z * scale_);
    for (unsigned f = 0; f < m->mNumFaces; ++f) {
      const aiFace& face = m->mFaces[f];
      if (face.mNumIndices != 3) continue;
      Tri t{face.mIndices[0], face.mIndices[1], face.mIndices[2]};
      for (uint32_t i : t)
        if (i >= m->mNumVertices)
          return make_error(ErrorCode::kIndexOutOfRange, label + ": face " + std::to_string(f) + " uses vertex " + std::to_string(i) +
                                                             ", but the mesh has " + std::to_string(m->mNumVertices));
      if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) p.triangles.push_back(t);
    }
    if (m->mNumAnimMeshes) warnings_.push_back(label + ": " + std::to_string(m->mNumAnimMeshes) + " morph targets are not imported");
    if (m->mNumBones) {
      // a skinned mesh's vertices are in its node's frame, which the bones' offset matrices start from: they are
      // brought into the scene's frame at the node's rest transform (the offsets follow), so that the bind pose
      // is where the skinning puts the skin, as in glTF
      glm::mat4 to_skin;
      const int32_t skin = skin_of(c, mi, node, label, to_skin);
      const glm::mat4 g = to_skin * rest_global_[node];
      if (g != glm::mat4(1.0f))
        for (glm::vec3& x : p.positions) x = glm::vec3(g * glm::vec4(x, 1.0f));
      p.skin = skin;
      const std::vector<int32_t>& joint_of_bone = joint_of_bone_[{mi, node}];
      std::vector<std::vector<std::pair<uint32_t, double>>> entries(m->mNumVertices);
      for (unsigned b = 0; b < m->mNumBones; ++b) {
        const aiBone* bone = m->mBones[b];
        for (unsigned w = 0; w < bone->mNumWeights; ++w) {
          const aiVertexWeight& vw = bone->mWeights[w];
          if (vw.mVertexId >= m->mNumVertices)
            return make_error(ErrorCode::kIndexOutOfRange, label + ": bone '" + std::string(bone->mName.C_Str()) + "' weighs vertex " +
                                                               std::to_string(vw.mVertexId) + ", but the mesh has " +
                                                               std::to_string(m->mNumVertices));
          if (joint_of_bone[b] >= 0) entries[vw.mVertexId].emplace_back(uint32_t(joint_of_bone[b]), double(vw.mWeight));
        }
      }
      SkinWeightCleanup cleanup;
      for (unsigned v = 0; v < m->mNumVertices; ++v) cleanup.add_vertex(v, entries[v], p);
      for (std::string& w : cleanup.take_warnings(label, "skin " + std::to_string(skin) + " ('" + c.skins[size_t(skin)].name + "')")) warnings_.push_back(std::move(w));
    }
    c.primitives.push_back(std::move(p));
    return Ok{};
  }

  // The skin of mesh mi instanced at `node` (made once), and the transform `to_skin` its vertices (in the scene's
  // frame) take into that skin's bind pose. Every mesh whose bones were bound in one pose shares one skin, as a
  // glTF character's meshes do (the cage follows one skin): a mesh bound with the same skeleton pose in another
  // frame (its offsets differ from the skin's by one transform for every shared bone) is moved into the skin's
  // frame; a mesh bound in another pose of the skeleton keeps its own skin, with a warning. A bone's offset
  // matrix is its inverse bind matrix; a bone that names no node is left out with a warning (its weights go to
  // the vertices' other bones).
  int32_t skin_of(Character& c, unsigned mi, uint32_t node, const std::string& label, glm::mat4& to_skin) {
    if (auto it = skin_of_mesh_.find({mi, node}); it != skin_of_mesh_.end()) {
      to_skin = it->second.second;
      return it->second.first;
    }
    const glm::mat4 to_mesh = glm::inverse(rest_global_[node]);
    const aiMesh* m = s_->mMeshes[mi];
    std::vector<int32_t>& joint_of_bone = joint_of_bone_[{mi, node}];
    joint_of_bone.assign(m->mNumBones, -1);
    std::vector<std::pair<uint32_t, glm::mat4>> bones;  // (node, inverse bind in the scene's frame)
    std::vector<unsigned> bone_index;
    for (unsigned b = 0; b < m->mNumBones; ++b) {
      const aiBone* bone = m->mBones[b];
      auto it = by_name_.find(bone->mName.C_Str());
      if (it == by_name_.end()) {
        warnings_.push_back(label + ": bone " + std::to_string(b) + " ('" + std::string(bone->mName.C_Str()) + "') names no node of the file; its " +
                            std::to_string(bone->mNumWeights) + " weights are left out");
        continue;
      }
      glm::mat4 ibm = to_glm(bone->mOffsetMatrix);
      ibm[3] = glm::vec4(glm::vec3(ibm[3]) * scale_, 1.0f);  // lengths in metres; the linear part is scale-free
      bones.emplace_back(it->second, ibm * to_mesh);
      bone_index.push_back(b);
    }
    // the first skin made whose bind pose this mesh shares
    int32_t index = -1;
    to_skin = glm::mat4(1.0f);
    for (size_t k = 0; k < c.skins.size() && index < 0; ++k) {
      const Skin& skin = c.skins[k];
      std::optional<glm::mat4> found;  // inverse(skin's IBM) * this mesh's IBM, the same for every shared bone
      bool agrees = true;
      for (const auto& [joint_node, ibm] : bones) {
        const auto at = std::find(skin.joints.begin(), skin.joints.end(), joint_node);
        if (at == skin.joints.end()) continue;
        const glm::mat4 offset = glm::inverse(skin.inverse_bind[size_t(at - skin.joints.begin())]) * ibm;
        if (!found) found = offset;
        else if (!close(*found, offset)) agrees = false;
      }
      if (agrees) {  // (sharing no bone: both bound in the scene's frame, as tools bind a character's meshes)
        index = int32_t(k);
        to_skin = found ? *found : glm::mat4(1.0f);
      }
    }
    if (index < 0) {
      if (!c.skins.empty())
        warnings_.push_back(label + ": its bones were bound in another pose than skin 0's meshes; it keeps its own skin " +
                            std::to_string(c.skins.size()) + ", which the cage does not follow");
      Skin skin;
      skin.name = m->mName.C_Str();
      c.skins.push_back(std::move(skin));
      index = int32_t(c.skins.size() - 1);
    }
    Skin& skin = c.skins[size_t(index)];
    const glm::mat4 from_skin = glm::inverse(to_skin);
    for (size_t k = 0; k < bones.size(); ++k) {
      const auto at = std::find(skin.joints.begin(), skin.joints.end(), bones[k].first);
      if (at != skin.joints.end()) {
        joint_of_bone[bone_index[k]] = int32_t(at - skin.joints.begin());
        continue;
      }
      joint_of_bone[bone_index[k]] = int32_t(skin.joints.size());
      skin.joints.push_back(bones[k].first);
      glm::mat4 ibm = bones[k].second * from_skin;
      ibm[0][3] = ibm[1][3] = ibm[2][3] = 0.0f;  // affine: the products round its last row off (0, 0, 0, 1)
      ibm[3][3] = 1.0f;
      skin.inverse_bind.push_back(ibm);
    }
    skin_of_mesh_[{mi, node}] = {index, to_skin};
    return index;
  }

  // Two transforms equal within float rounding of the scene's size.
  static bool close(const glm::mat4& a, const glm::mat4& b) {
    float size = 1.0f;
    for (int r = 0; r < 3; ++r) size = std::max({size, std::abs(a[3][r]), std::abs(b[3][r])});
    for (int col = 0; col < 4; ++col)
      for (int r = 0; r < 3; ++r)
        if (std::abs(a[col][r] - b[col][r]) > (col == 3 ? 1e-4f * size : 1e-4f)) return false;
    return true;
  }

  std::vector<Clip> build_clips(const glm::quat& turn) {
    std::vector<Clip> clips;
    for (unsigned a = 0; a < s_->mNumAnimations; ++a) {
      const aiAnimation* anim = s_->mAnimations[a];
      const double tps = anim->mTicksPerSecond > 0.0 ? anim->mTicksPerSecond : 25.0;
      Clip clip;
      clip.name = anim->mName.length ? anim->mName.C_Str() : "animation_" + std::to_string(a);
      for (unsigned ci = 0; ci < anim->mNumChannels; ++ci) {
        const aiNodeAnim* ch = anim->mChannels[ci];
        auto it = by_name_.find(ch->mNodeName.C_Str());
        if (it == by_name_.end()) {
          warnings_.push_back(file_ + ": animation '" + clip.name + "' moves '" + std::string(ch->mNodeName.C_Str()) +
                              "', which is no node of the file; that channel is skipped");
          continue;
        }
        const uint32_t node = it->second;
        const bool root = node < parent_.size() && parent_[node] < 0;
        auto add = [&](ChannelPath path, AnimationSampler sampler) {
          if (sampler.times.empty()) return;
          for (float t : sampler.times) clip.duration = std::max(clip.duration, double(t));
          clip.samplers.push_back(std::move(sampler));
          clip.channels.push_back({node, path, uint32_t(clip.samplers.size() - 1)});
        };
        AnimationSampler tr{Interpolation::kLinear, {}, {}, 3}, rot{Interpolation::kLinear, {}, {}, 4}, sc{Interpolation::kLinear, {}, {}, 3};
        for (unsigned k = 0; k < ch->mNumPositionKeys; ++k) {
          glm::vec3 v(ch->mPositionKeys[k].mValue.x, ch->mPositionKeys[k].mValue.y, ch->mPositionKeys[k].mValue.z);
          v *= scale_;
          if (root) v = turn * v;
          if (!push_time(tr, ch->mPositionKeys[k].mTime / tps)) continue;
          tr.values.insert(tr.values.end(), {v.x, v.y, v.z});
        }
        for (unsigned k = 0; k < ch->mNumRotationKeys; ++k) {
          const aiQuaternion& q = ch->mRotationKeys[k].mValue;
          glm::quat g = glm::normalize(glm::quat(q.w, q.x, q.y, q.z));
          if (root) g = glm::normalize(turn * g);
          if (!push_time(rot, ch->mRotationKeys[k].mTime / tps)) continue;
          rot.values.insert(rot.values.end(), {g.x, g.y, g.z, g.w});
        }
        for (unsigned k = 0; k < ch->mNumScalingKeys; ++k) {
          const aiVector3D& v = ch->mScalingKeys[k].mValue;
          if (!push_time(sc, ch->mScalingKeys[k].mTime / tps)) continue;
          sc.values.insert(sc.values.end(), {v.x, v.y, v.z});
        }
        add(ChannelPath::kTranslation, std::move(tr));
        add(ChannelPath::kRotation, std::move(rot));
        add(ChannelPath::kScale, std::move(sc));
      }
      if (!clip.channels.empty()) clips.push_back(std::move(clip));
    }
    return clips;
  }

  // Whether an animation channel moves the node named `node` (the names collected once).
  bool animated(const std::string& node) {
    if (animated_.empty())
      for (unsigned a = 0; a < s_->mNumAnimations; ++a)
        for (unsigned ci = 0; ci < s_->mAnimations[a]->mNumChannels; ++ci) animated_.insert(s_->mAnimations[a]->mChannels[ci]->mNodeName.C_Str());
    return animated_.count(node) > 0;
  }

  // Keys at increasing times only (a repeated or earlier key is dropped).
  static bool push_time(AnimationSampler& s, double t) {
    if (!std::isfinite(t) || (!s.times.empty() && float(t) <= s.times.back())) return false;
    s.times.push_back(float(t));
    return true;
  }

  const aiScene* s_;
  std::string file_;
  std::optional<ColladaAsset> collada_;
  std::set<std::string> animated_;  // the nodes animation channels move
  float scale_ = 1.0f;
  std::map<const aiNode*, uint32_t> index_;
  std::vector<int32_t> parent_;
  std::multimap<std::string, uint32_t> by_name_;
  std::vector<glm::mat4> rest_global_;  // the nodes' global transforms at rest
  // by (mesh, the node instancing it): its skin and the transform into that skin's bind pose; each bone's joint
  std::map<std::pair<unsigned, uint32_t>, std::pair<int32_t, glm::mat4>> skin_of_mesh_;
  std::map<std::pair<unsigned, uint32_t>, std::vector<int32_t>> joint_of_bone_;
  std::vector<std::string> warnings_;
};

}  // namespace

const std::vector<std::string>& assimp_character_extensions() {
  static const std::vector<std::string> kExtensions{".fbx", ".dae", ".x", ".b3d", ".ms3d", ".smd", ".md5mesh"};
  return kExtensions;
}

bool is_assimp_character(const std::string& path) {
  const std::vector<std::string>& all = assimp_character_extensions();
  return std::find(all.begin(), all.end(), lower_extension(path)) != all.end();
}

namespace {

constexpr size_t kColladaHead = 1 << 16;  // where a Collada file's <asset> is looked for

// Reads the scene with `read` (from a file or from memory) and imports it; `name` stands for the file.
template <class Read>
Result<Character> import_scene(const std::string& name, const std::optional<ColladaAsset>& collada, const CharacterLoadOptions& options,
                               AssimpUnits* units, Read read) {
  Assimp::Importer importer;
  importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_PRESERVE_PIVOTS, false);  // pivots and pre-rotations folded into the nodes
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);  // turned here, as every format is
  const unsigned flags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_SortByPType;
  const aiScene* scene = nullptr;
  try {
    scene = read(importer, flags);
  } catch (const std::exception& e) {
    return make_error(ErrorCode::kParse, name + ": the importer stopped: " + e.what());
  }
  if (!scene) return make_error(ErrorCode::kParse, name + ": not a usable character file: " + importer.GetErrorString());
  if (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE)
    return make_error(ErrorCode::kParse, name + ": the importer read it only in part (" + importer.GetErrorString() + ")");
  try {
    return Importer(scene, name, collada).run(options, units);
  } catch (const std::bad_alloc&) {
    return make_error(ErrorCode::kParse, name + ": a size in it is too large to load");
  }
}


// ---- the importer in a child process
//
// Open Asset Import is not robust against malformed files: its readers crash on some (an MD5 file cut short,
// found by fuzz_assimp within a hundred inputs). A crash must not take the editor and its unsaved work down,
// so the import runs in a child process (fork) that sends the character back to this one as a .glb (the
// project's own writer and reader, which keep everything the loader fills) with its warnings and units; a
// child that crashes, is killed or does not answer becomes an error naming the file and the signal.

void put_u64(std::string& out, uint64_t v) { out.append(reinterpret_cast<const char*>(&v), sizeof v); }
void put_text(std::string& out, std::string_view text) {
  put_u64(out, text.size());
  out.append(text);
}
bool get_u64(std::string_view& in, uint64_t& v) {
  if (in.size() < sizeof v) return false;
  std::memcpy(&v, in.data(), sizeof v);
  in.remove_prefix(sizeof v);
  return true;
}
bool get_text(std::string_view& in, std::string& text) {
  uint64_t n = 0;
  if (!get_u64(in, n) || n > in.size()) return false;
  text.assign(in.data(), size_t(n));
  in.remove_prefix(size_t(n));
  return true;
}

// The child's answer: "ok" (units, warnings, the .glb) or "error" (the error's code and message).
std::string encode_outcome(const Result<Character>& r, const AssimpUnits& units) {
  std::string out;
  if (!r) {
    put_text(out, "error");
    put_u64(out, uint64_t(r.error().code));
    put_text(out, r.error().message);
    return out;
  }
  put_text(out, "ok");
  put_text(out, short_number(units.metres_per_unit));
  put_text(out, units.up_axis);
  put_u64(out, units.converted ? 1 : 0);
  put_u64(out, r->warnings.size());
  for (const std::string& w : r->warnings) put_text(out, w);
  const std::vector<uint8_t> glb = encode_glb(r.value());
  put_text(out, std::string_view(reinterpret_cast<const char*>(glb.data()), glb.size()));
  return out;
}

Result<Character> decode_outcome(std::string_view in, const std::string& name, bool keep_units, AssimpUnits* units_out) {
  const auto broken = [&] { return make_error(ErrorCode::kParse, name + ": the importer's answer was cut short"); };
  std::string kind;
  if (!get_text(in, kind)) return broken();
  if (kind == "error") {
    uint64_t code = 0;
    std::string message;
    if (!get_u64(in, code) || !get_text(in, message)) return broken();
    return make_error(ErrorCode(code), message);
  }
  AssimpUnits units;
  std::string metres, glb;
  uint64_t converted = 0, count = 0;
  if (kind != "ok" || !get_text(in, metres) || !get_text(in, units.up_axis) || !get_u64(in, converted) || !get_u64(in, count))
    return broken();
  units.metres_per_unit = std::strtod(metres.c_str(), nullptr);
  units.converted = converted != 0;
  std::vector<std::string> warnings;
  for (uint64_t k = 0; k < count; ++k) {
    std::string w;
    if (!get_text(in, w)) return broken();
    warnings.push_back(std::move(w));
  }
  if (!get_text(in, glb)) return broken();
  auto c = load_character_bytes(glb, name);
  if (!c) return make_error(c.error().code, name + ": the imported character did not read back: " + c.error().message);
  c->warnings = std::move(warnings);
  c->source = name;
  if (keep_units) c->to_metres = kept_units_to_metres(units);
  if (units_out) *units_out = units;
  return c;
}

// A child silent this long is stopped (an importer caught in a loop): 600 s, or $CAGEWRAP_IMPORT_SECONDS (the
// fuzzers give it seconds).
int import_seconds() {
  const char* env = std::getenv("CAGEWRAP_IMPORT_SECONDS");
  const long s = env && *env ? std::strtol(env, nullptr, 10) : 600;
  return int(std::clamp<long>(s, 1, 86400));
}

// Runs `import` in a child process and returns what it made; `name` stands for the file in messages.
template <class Import>
Result<Character> import_in_child(const std::string& name, bool keep_units, AssimpUnits* units, Import import) {
  int fds[2];
  if (::pipe(fds) != 0) return make_error(ErrorCode::kFileUnreadable, name + ": cannot start the importer (pipe: " + std::strerror(errno) + ")");
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    return make_error(ErrorCode::kFileUnreadable, name + ": cannot start the importer (fork: " + std::strerror(errno) + ")");
  }
  if (pid == 0) {  // the child: import, answer, leave without running this process's exit handlers
    ::close(fds[0]);
    // a crash ends the child quietly, by its signal (not through handlers this process installed: a sanitizer's
    // or a fuzzer's report of the importer's crash is the parent's business, as an error)
    for (int sig : {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT, SIGTRAP}) ::signal(sig, SIG_DFL);
    AssimpUnits u;
    std::string out;
    try {
      out = encode_outcome(import(&u), u);
    } catch (const std::exception& e) {
      out.clear();
      put_text(out, "error");
      put_u64(out, uint64_t(ErrorCode::kParse));
      put_text(out, name + ": the importer stopped: " + e.what());
    }
    std::string_view left(out);
    while (!left.empty()) {
      const ssize_t n = ::write(fds[1], left.data(), left.size());
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) ::_exit(3);
      left.remove_prefix(size_t(n));
    }
    ::_exit(0);
  }
  ::close(fds[1]);
  std::string answer;
  char buffer[1 << 16];
  bool timed_out = false;
  const int seconds = import_seconds();
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(seconds);
  for (;;) {
    pollfd p{fds[0], POLLIN, 0};
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()).count();
    const int ready = left <= 0 ? 0 : ::poll(&p, 1, int(std::min<long long>(left, 1 << 30)));
    if (ready < 0 && errno == EINTR) continue;
    if (ready == 0) {
      timed_out = true;
      ::kill(pid, SIGKILL);
      break;
    }
    const ssize_t n = ::read(fds[0], buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    answer.append(buffer, size_t(n));
  }
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (timed_out)
    return make_error(ErrorCode::kParse, name + ": the importer gave no answer in " + std::to_string(seconds) +
                                             " s and was stopped (a malformed file can make it loop)");
  if (WIFSIGNALED(status))
    return make_error(ErrorCode::kParse, name + ": the importer (Open Asset Import) crashed reading it (" + strsignal(WTERMSIG(status)) +
                                             "): the file is malformed or uses something the importer cannot read");
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    return make_error(ErrorCode::kParse, name + ": the importer (Open Asset Import) failed reading it (exit status " +
                                             std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + ")");
  return decode_outcome(answer, name, keep_units, units);
}

}  // namespace

Result<Character> load_character_assimp(const std::string& path, const CharacterLoadOptions& options, AssimpUnits* units) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return make_error(ErrorCode::kFileNotFound, path + ": no such file");
  if (std::filesystem::is_directory(path, ec)) return make_error(ErrorCode::kFileUnreadable, path + ": is a directory, not a character file");
  std::optional<ColladaAsset> collada;
  if (lower_extension(path) == ".dae") {
    std::ifstream in(path, std::ios::binary);
    std::string head(kColladaHead, '\0');
    in.read(head.data(), std::streamsize(head.size()));
    head.resize(size_t(std::max<std::streamsize>(0, in.gcount())));
    collada = read_collada_asset(head);
  }
  auto import = [&](AssimpUnits* u) {
    return import_scene(path, collada, options, u,
                        [&](Assimp::Importer& importer, unsigned flags) { return importer.ReadFile(path, flags); });
  };
  return options.in_process ? import(units) : import_in_child(path, options.keep_units, units, import);
}

Result<Character> load_character_assimp_bytes(const std::string& bytes, const std::string& name, const std::string& file_name,
                                              const CharacterLoadOptions& options, AssimpUnits* units) {
  if (bytes.empty()) return make_error(ErrorCode::kEmpty, name + ": is empty");
  if (bytes.size() > std::numeric_limits<unsigned int>::max()) return make_error(ErrorCode::kFileUnreadable, name + ": is larger than 4 GiB");
  const std::string ext = lower_extension(file_name), hint = ext.empty() ? ext : ext.substr(1);
  std::optional<ColladaAsset> collada;
  if (hint == "dae") collada = read_collada_asset(std::string_view(bytes).substr(0, kColladaHead));
  auto import = [&](AssimpUnits* u) {
    return import_scene(name, collada, options, u, [&](Assimp::Importer& importer, unsigned flags) {
      return importer.ReadFileFromMemory(bytes.data(), bytes.size(), flags, hint.c_str());
    });
  };
  return options.in_process ? import(units) : import_in_child(name, options.keep_units, units, import);
}

}  // namespace cagewrap
