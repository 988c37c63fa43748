#include "core/io/gltf_writer.h"

#include "core/base/atomic_write.h"

#include <map>
#include <set>
#include <algorithm>
#include <cmath>
#include <cstring>

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <nlohmann/json.hpp>

namespace cagewrap {
namespace {

using nlohmann::json;

constexpr int kUnsignedByte = 5121, kUnsignedShort = 5123, kUnsignedInt = 5125, kFloat = 5126;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;

class GlbBuilder {
 public:
  json doc;
  std::vector<uint8_t> bin;

  int add_view(const void* data, size_t bytes, int target) {
    while (bin.size() % 4) bin.push_back(0);
    size_t offset = bin.size();
    bin.resize(offset + bytes);
    if (bytes) std::memcpy(bin.data() + offset, data, bytes);
    json v = {{"buffer", 0}, {"byteLength", bytes}};
    if (offset) v["byteOffset"] = offset;
    if (target) v["target"] = target;
    doc["bufferViews"].push_back(v);
    return static_cast<int>(doc["bufferViews"].size()) - 1;
  }

  // An accessor of `count` elements of `type` over a new view; min/max over float components
  // when `bounds` (required for POSITION and animation inputs).
  template <class T>
  int add_accessor(const std::vector<T>& values, const char* type, int nc, int component, int target,
                   bool bounds = false, bool normalized = false) {
    int view = add_view(values.data(), values.size() * sizeof(T), target);
    json a = {{"bufferView", view}, {"componentType", component}, {"count", values.size() / nc}, {"type", type}};
    if (normalized) a["normalized"] = true;
    if (bounds && !values.empty()) {
      std::vector<double> lo(nc, 1e300), hi(nc, -1e300);
      for (size_t i = 0; i < values.size(); ++i) {
        lo[i % nc] = std::min(lo[i % nc], double(values[i]));
        hi[i % nc] = std::max(hi[i % nc], double(values[i]));
      }
      a["min"] = lo;
      a["max"] = hi;
    }
    doc["accessors"].push_back(a);
    return static_cast<int>(doc["accessors"].size()) - 1;
  }
};

std::vector<float> flatten(const std::vector<glm::vec3>& v) {
  std::vector<float> out(v.size() * 3);
  for (size_t i = 0; i < v.size(); ++i) {
    out[3 * i] = v[i].x;
    out[3 * i + 1] = v[i].y;
    out[3 * i + 2] = v[i].z;
  }
  return out;
}

std::vector<float> vertex_normals(const Primitive& p) {
  std::vector<glm::dvec3> n(p.num_vertices(), glm::dvec3(0.0));
  for (const Tri& t : p.triangles) {
    glm::dvec3 a(p.positions[t[0]]), b(p.positions[t[1]]), c(p.positions[t[2]]);
    glm::dvec3 fn = glm::cross(b - a, c - a);  // length = twice the area
    for (uint32_t v : t) n[v] += fn;
  }
  std::vector<float> out(p.num_vertices() * 3);
  for (size_t v = 0; v < n.size(); ++v) {
    double len = glm::length(n[v]);
    glm::dvec3 u = len > 0 ? n[v] / len : glm::dvec3(0, 1, 0);
    out[3 * v] = float(u.x);
    out[3 * v + 1] = float(u.y);
    out[3 * v + 2] = float(u.z);
    // Renormalize in float so validators see unit length.
    glm::vec3 f(out[3 * v], out[3 * v + 1], out[3 * v + 2]);
    f /= glm::length(f);
    out[3 * v] = f.x;
    out[3 * v + 1] = f.y;
    out[3 * v + 2] = f.z;
  }
  return out;
}

json trs_json(const SkeletonNode& n) {
  json j;
  if (!n.name.empty()) j["name"] = n.name;
  if (n.has_matrix) {
    std::vector<float> m(glm::value_ptr(n.matrix), glm::value_ptr(n.matrix) + 16);
    j["matrix"] = m;
    return j;
  }
  const Trs& r = n.rest;
  if (r.translation != glm::vec3(0.0f)) j["translation"] = {r.translation.x, r.translation.y, r.translation.z};
  if (r.rotation != glm::quat(1.0f, 0.0f, 0.0f, 0.0f))
    j["rotation"] = {r.rotation.x, r.rotation.y, r.rotation.z, r.rotation.w};
  if (r.scale != glm::vec3(1.0f)) j["scale"] = {r.scale.x, r.scale.y, r.scale.z};
  return j;
}

json primitive_json(GlbBuilder& b, const Primitive& p, size_t num_skin_joints) {
  json attrs;
  attrs["POSITION"] = b.add_accessor(flatten(p.positions), "VEC3", 3, kFloat, kArrayBuffer, true);
  attrs["NORMAL"] = b.add_accessor(vertex_normals(p), "VEC3", 3, kFloat, kArrayBuffer);
  if (p.skin >= 0 && !p.influence_start.empty()) {
    size_t max_inf = 1;
    for (size_t v = 0; v < p.num_vertices(); ++v) max_inf = std::max<size_t>(max_inf, p.num_influences(v));
    const size_t sets = (max_inf + 3) / 4;
    for (size_t s = 0; s < sets; ++s) {
      std::vector<uint16_t> joints(p.num_vertices() * 4, 0);
      std::vector<float> weights(p.num_vertices() * 4, 0.0f);
      for (size_t v = 0; v < p.num_vertices(); ++v) {
        for (size_t k = 0; k < 4; ++k) {
          size_t e = p.influence_start[v] + s * 4 + k;
          if (e >= p.influence_start[v + 1]) break;
          joints[4 * v + k] = p.influence_joint[e];
          weights[4 * v + k] = p.influence_weight[e];
        }
      }
      std::string js = "JOINTS_" + std::to_string(s), ws = "WEIGHTS_" + std::to_string(s);
      if (num_skin_joints <= 256) {
        std::vector<uint8_t> j8(joints.begin(), joints.end());
        attrs[js] = b.add_accessor(j8, "VEC4", 4, kUnsignedByte, kArrayBuffer);
      } else {
        attrs[js] = b.add_accessor(joints, "VEC4", 4, kUnsignedShort, kArrayBuffer);
      }
      attrs[ws] = b.add_accessor(weights, "VEC4", 4, kFloat, kArrayBuffer);
    }
  }
  if (!p.source_index.empty()) {  // exact in float below 2^24 vertices (checked by the exporter)
    std::vector<float> index(p.source_index.begin(), p.source_index.end());
    attrs["_CAGEWRAP_SOURCE_INDEX"] = b.add_accessor(index, "SCALAR", 1, kFloat, kArrayBuffer);
  }
  json prim = {{"attributes", attrs}, {"mode", 4}};
  if (!p.triangles.empty()) {
    std::vector<uint32_t> idx;
    idx.reserve(p.triangles.size() * 3);
    for (const Tri& t : p.triangles) idx.insert(idx.end(), t.begin(), t.end());
    if (p.num_vertices() <= 65535) {
      std::vector<uint16_t> i16(idx.begin(), idx.end());
      prim["indices"] = b.add_accessor(i16, "SCALAR", 1, kUnsignedShort, kElementArrayBuffer);
    } else {
      prim["indices"] = b.add_accessor(idx, "SCALAR", 1, kUnsignedInt, kElementArrayBuffer);
    }
  } else {
    prim["mode"] = 0;  // points: the vertices without faces
  }
  for (const auto& target : p.morph_targets)
    prim["targets"].push_back({{"POSITION", b.add_accessor(flatten(target), "VEC3", 3, kFloat, kArrayBuffer, true)}});
  return prim;
}

}  // namespace

GlbPartSizes glb_part_sizes(const Character& c) {
  GlbPartSizes s;
  for (const Primitive& p : c.primitives) {
    const uint64_t nv = p.num_vertices();
    s.mesh += nv * 24 + p.triangles.size() * 3 * (nv <= 65535 ? 2 : 4) + p.source_index.size() * 4;  // POSITION + NORMAL, indices
    if (p.skin >= 0 && !p.influence_start.empty()) {
      size_t max_inf = 1;
      for (size_t v = 0; v < p.num_vertices(); ++v) max_inf = std::max<size_t>(max_inf, p.num_influences(v));
      const uint64_t sets = (max_inf + 3) / 4;
      const uint64_t joint_bytes = size_t(p.skin) < c.skins.size() && c.skins[p.skin].joints.size() <= 256 ? 1 : 2;
      s.skin += sets * nv * (4 * joint_bytes + 16);
    }
    s.targets += p.morph_targets.size() * nv * 12;
  }
  for (const Skin& k : c.skins) s.skin += k.inverse_bind.size() * 64;
  std::set<std::vector<float>> times;  // written once each (encode_glb shares them)
  for (const Clip& clip : c.clips) {
    std::vector<bool> counted(clip.samplers.size(), false);
    for (const AnimationChannel& ch : clip.channels)
      if (ch.sampler < clip.samplers.size() && !counted[ch.sampler]) {
        counted[ch.sampler] = true;
        const AnimationSampler& sampler = clip.samplers[ch.sampler];
        s.animation += sampler.values.size() * 4 + (times.insert(sampler.times).second ? sampler.times.size() * 4 : 0);
      }
  }
  return s;
}

std::vector<uint8_t> encode_glb(const Character& c, const std::string& generator) {
  GlbBuilder b;
  b.doc["asset"] = {{"version", "2.0"}, {"generator", generator}};
  const Skeleton& sk = c.skeleton;
  json nodes = json::array();
  for (size_t i = 0; i < sk.size(); ++i) {
    json n = trs_json(sk.node(i));
    std::vector<uint32_t> ch = sk.children(static_cast<uint32_t>(i));
    if (!ch.empty()) n["children"] = ch;
    nodes.push_back(n);
  }
  // Meshes: consecutive primitives of the same (mesh, node) form one glTF mesh.
  json meshes = json::array();
  for (size_t i = 0; i < c.primitives.size();) {
    const Primitive& first = c.primitives[i];
    json mesh;
    if (!first.mesh_name.empty()) mesh["name"] = first.mesh_name;
    size_t j = i;
    for (; j < c.primitives.size() && c.primitives[j].mesh == first.mesh && c.primitives[j].node == first.node; ++j) {
      const Primitive& p = c.primitives[j];
      size_t nj = p.skin >= 0 ? c.skins[p.skin].joints.size() : 0;
      mesh["primitives"].push_back(primitive_json(b, p, nj));
    }
    if (!first.morph_targets.empty()) mesh["weights"] = first.morph_weights;
    json& node = nodes[first.node];
    node["mesh"] = meshes.size();
    if (first.skin >= 0) node["skin"] = first.skin;
    meshes.push_back(mesh);
    i = j;
  }
  b.doc["nodes"] = nodes;
  if (!meshes.empty()) b.doc["meshes"] = meshes;
  for (const Skin& s : c.skins) {
    std::vector<float> ibm;
    for (const glm::mat4& m : s.inverse_bind) ibm.insert(ibm.end(), glm::value_ptr(m), glm::value_ptr(m) + 16);
    json skin = {{"joints", s.joints}, {"inverseBindMatrices", b.add_accessor(ibm, "MAT4", 16, kFloat, 0)}};
    if (!s.name.empty()) skin["name"] = s.name;
    b.doc["skins"].push_back(skin);
  }
  // key times shared by samplers (every channel of a baked clip keys the same frames) are written once
  std::map<std::vector<float>, int> times_accessor;
  for (const Clip& clip : c.clips) {
    json anim = {{"name", clip.name}};
    std::vector<int> sampler_index(clip.samplers.size(), -1);
    for (const AnimationChannel& ch : clip.channels) {
      if (sampler_index[ch.sampler] < 0) {
        const AnimationSampler& s = clip.samplers[ch.sampler];
        // Morph weights are SCALAR (#K x #targets of them); the TRS paths are VEC3 / VEC4.
        const bool weights = ch.path == ChannelPath::kWeights;
        const char* type = weights ? "SCALAR" : s.components == 4 ? "VEC4" : "VEC3";
        int nc = weights ? 1 : int(s.components);
        auto [at, fresh] = times_accessor.try_emplace(s.times, -1);
        if (fresh) at->second = b.add_accessor(s.times, "SCALAR", 1, kFloat, 0, true);
        const int in = at->second;
        int out = b.add_accessor(s.values, type, nc, kFloat, 0);
        sampler_index[ch.sampler] = static_cast<int>(anim["samplers"].size());
        anim["samplers"].push_back({{"input", in}, {"output", out}, {"interpolation", interpolation_name(s.interpolation)}});
      }
      anim["channels"].push_back(
          {{"sampler", sampler_index[ch.sampler]}, {"target", {{"node", ch.node}, {"path", channel_path_name(ch.path)}}}});
    }
    if (!anim.contains("channels")) continue;  // glTF requires at least one channel
    b.doc["animations"].push_back(anim);
  }
  std::vector<uint32_t> roots;
  for (size_t i = 0; i < sk.size(); ++i)
    if (sk.node(i).parent < 0) roots.push_back(static_cast<uint32_t>(i));
  b.doc["scenes"] = json::array({{{"nodes", roots}}});
  b.doc["scene"] = 0;
  while (b.bin.size() % 4) b.bin.push_back(0);
  if (!b.bin.empty()) b.doc["buffers"] = json::array({{{"byteLength", b.bin.size()}}});
  return glb_container(b.doc.dump(), std::move(b.bin));
}

std::vector<uint8_t> glb_container(std::string text, std::vector<uint8_t> bin) {
  while (text.size() % 4) text += ' ';
  while (bin.size() % 4) bin.push_back(0);
  std::vector<uint8_t> out;
  auto u32 = [&](uint32_t v) {
    for (int k = 0; k < 4; ++k) out.push_back(static_cast<uint8_t>(v >> (8 * k)));
  };
  uint32_t total = 12 + 8 + static_cast<uint32_t>(text.size()) + (bin.empty() ? 0 : 8 + static_cast<uint32_t>(bin.size()));
  out.reserve(total);
  u32(0x46546C67);  // "glTF"
  u32(2);
  u32(total);
  u32(static_cast<uint32_t>(text.size()));
  u32(0x4E4F534A);  // "JSON"
  out.insert(out.end(), text.begin(), text.end());
  if (!bin.empty()) {
    u32(static_cast<uint32_t>(bin.size()));
    u32(0x004E4942);  // "BIN\0"
    out.insert(out.end(), bin.begin(), bin.end());
  }
  return out;
}

Result<std::string> glb_json_chunk(const std::string& bytes, const std::string& file) {
  auto u32 = [&](size_t at) {
    uint32_t v = 0;
    for (int k = 0; k < 4; ++k) v |= uint32_t(static_cast<uint8_t>(bytes[at + k])) << (8 * k);
    return v;
  };
  if (bytes.size() < 20 || u32(0) != 0x46546C67)
    return make_error(ErrorCode::kParse, file + ": not a binary glTF file (the 12-byte header or the first chunk is missing)");
  const uint32_t length = u32(12);
  if (u32(16) != 0x4E4F534A)
    return make_error(ErrorCode::kParse, file + ": the first chunk of the binary glTF file is not its JSON");
  if (size_t(length) > bytes.size() - 20)
    return make_error(ErrorCode::kParse, file + ": the binary glTF file's JSON chunk says " + std::to_string(length) +
                                             " bytes but the file ends " + std::to_string(bytes.size() - 20) +
                                             " bytes after its start");
  return bytes.substr(20, length);
}

Status write_glb(const std::string& path, const Character& c, const std::string& generator) {
  std::vector<uint8_t> bytes = encode_glb(c, generator);
  return write_file_atomic(path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

}  // namespace cagewrap
