#include "core/io/gltf_writer.h"

#include "core/base/atomic_write.h"
#include "core/io/gltf_quantize.h"

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

constexpr int kByte = 5120, kUnsignedByte = 5121, kShort = 5122, kUnsignedShort = 5123, kUnsignedInt = 5125, kFloat = 5126;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;

class GlbBuilder {
 public:
  json doc;
  std::vector<uint8_t> bin;
  uint64_t* part = nullptr;  // the GlbPartSizes field the next views count towards (none: nullptr)

  int add_view(const void* data, size_t bytes, int target, size_t stride = 0) {
    while (bin.size() % 4) bin.push_back(0);
    size_t offset = bin.size();
    bin.resize(offset + bytes);
    if (bytes) std::memcpy(bin.data() + offset, data, bytes);
    if (part) *part += bytes;
    json v = {{"buffer", 0}, {"byteLength", bytes}};
    if (offset) v["byteOffset"] = offset;
    if (stride) v["byteStride"] = stride;
    if (target) v["target"] = target;
    doc["bufferViews"].push_back(v);
    return static_cast<int>(doc["bufferViews"].size()) - 1;
  }

  // An accessor of elements of `type` (nc components) over a new view; min/max over the components
  // when `bounds` (required for POSITION and animation inputs). `stride` > nc: each element is padded to
  // `stride` values in the buffer (the view's byteStride keeps vertex attributes 4-byte aligned).
  template <class T>
  int add_accessor(const std::vector<T>& values, const char* type, int nc, int component, int target,
                   bool bounds = false, bool normalized = false, int stride = 0) {
    if (stride <= nc) stride = 0;
    const size_t per = stride ? size_t(stride) : size_t(nc);
    int view = add_view(values.data(), values.size() * sizeof(T), target, stride ? per * sizeof(T) : 0);
    json a = {{"bufferView", view}, {"componentType", component}, {"count", values.size() / per}, {"type", type}};
    if (normalized) a["normalized"] = true;
    if (bounds && !values.empty()) {
      std::vector<double> lo(nc, 1e300), hi(nc, -1e300);
      for (size_t i = 0; i < values.size(); ++i) {
        const size_t c = i % per;
        if (c >= size_t(nc)) continue;
        lo[c] = std::min(lo[c], double(values[i]));
        hi[c] = std::max(hi[c], double(values[i]));
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

// SHORT xyz of each vector (padded to 4 for alignment), quantized with `step` around `offset`.
std::vector<int16_t> quantized_vec3(const std::vector<glm::vec3>& v, const glm::dvec3& offset, double step) {
  std::vector<int16_t> out(v.size() * 4, 0);
  for (size_t i = 0; i < v.size(); ++i)
    for (int k = 0; k < 3; ++k) out[4 * i + k] = quantize_short(double(v[i][k]) - offset[k], step);
  return out;
}

json primitive_json(GlbBuilder& b, const Primitive& p, size_t num_skin_joints, const GlbQuantization* q,
                    GlbPartSizes& sizes) {
  json attrs;
  b.part = &sizes.mesh;
  const GlbQuantization::Dequant* dq = q ? &q->positions_of(p) : nullptr;
  if (dq) {
    attrs["POSITION"] = b.add_accessor(quantized_vec3(p.positions, dq->offset, dq->step), "VEC3", 3, kShort, kArrayBuffer,
                                       true, false, 4);
    const std::vector<float> n = vertex_normals(p);
    std::vector<int8_t> n8(p.num_vertices() * 4, 0);
    for (size_t v = 0; v < p.num_vertices(); ++v)
      for (int k = 0; k < 3; ++k) n8[4 * v + k] = static_cast<int8_t>(std::lround(std::clamp(n[3 * v + k], -1.0f, 1.0f) * 127.0f));
    attrs["NORMAL"] = b.add_accessor(n8, "VEC3", 3, kByte, kArrayBuffer, false, true, 4);
  } else {
    attrs["POSITION"] = b.add_accessor(flatten(p.positions), "VEC3", 3, kFloat, kArrayBuffer, true);
    attrs["NORMAL"] = b.add_accessor(vertex_normals(p), "VEC3", 3, kFloat, kArrayBuffer);
  }
  if (p.skin >= 0 && !p.influence_start.empty()) {
    b.part = &sizes.skin;
    size_t max_inf = 1;
    for (size_t v = 0; v < p.num_vertices(); ++v) max_inf = std::max<size_t>(max_inf, p.num_influences(v));
    const size_t sets = (max_inf + 3) / 4;
    std::vector<uint16_t> joints(p.num_vertices() * 4 * sets, 0);
    std::vector<float> weights(p.num_vertices() * 4 * sets, 0.0f);
    std::vector<uint16_t> weights16(q ? weights.size() : 0, 0);
    for (size_t v = 0; v < p.num_vertices(); ++v) {
      const size_t n = p.num_influences(v), e0 = p.influence_start[v];
      // set s holds influences 4s .. 4s+3 of the vertex, at [s][v][k]
      auto at = [&](size_t i) { return (i / 4) * p.num_vertices() * 4 + 4 * v + i % 4; };
      for (size_t i = 0; i < n; ++i) {
        joints[at(i)] = p.influence_joint[e0 + i];
        weights[at(i)] = p.influence_weight[e0 + i];
      }
      if (q) {
        const std::vector<uint16_t> w16 = quantized_weights({p.influence_weight.data() + e0, n});
        for (size_t i = 0; i < n; ++i) {
          weights16[at(i)] = w16[i];
          if (w16[i] == 0) joints[at(i)] = 0;  // a weight rounded away: no joint (validators warn of one kept)
        }
      }
    }
    const size_t per_set = p.num_vertices() * 4;
    for (size_t s = 0; s < sets; ++s) {
      std::string js = "JOINTS_" + std::to_string(s), ws = "WEIGHTS_" + std::to_string(s);
      if (num_skin_joints <= 256) {
        std::vector<uint8_t> j8(joints.begin() + s * per_set, joints.begin() + (s + 1) * per_set);
        attrs[js] = b.add_accessor(j8, "VEC4", 4, kUnsignedByte, kArrayBuffer);
      } else {
        std::vector<uint16_t> j16(joints.begin() + s * per_set, joints.begin() + (s + 1) * per_set);
        attrs[js] = b.add_accessor(j16, "VEC4", 4, kUnsignedShort, kArrayBuffer);
      }
      if (q) {
        std::vector<uint16_t> w(weights16.begin() + s * per_set, weights16.begin() + (s + 1) * per_set);
        attrs[ws] = b.add_accessor(w, "VEC4", 4, kUnsignedShort, kArrayBuffer, false, true);
      } else {
        std::vector<float> w(weights.begin() + s * per_set, weights.begin() + (s + 1) * per_set);
        attrs[ws] = b.add_accessor(w, "VEC4", 4, kFloat, kArrayBuffer);
      }
    }
  }
  b.part = &sizes.mesh;
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
  b.part = &sizes.targets;
  for (size_t t = 0; t < p.morph_targets.size(); ++t) {
    const auto& target = p.morph_targets[t];
    if (dq) {
      const double step = q->target_step(p, t);
      prim["targets"].push_back(
          {{"POSITION", b.add_accessor(quantized_vec3(target, glm::dvec3(0.0), step), "VEC3", 3, kShort, kArrayBuffer, true, false, 4)}});
    } else {
      prim["targets"].push_back({{"POSITION", b.add_accessor(flatten(target), "VEC3", 3, kFloat, kArrayBuffer, true)}});
    }
  }
  b.part = nullptr;
  return prim;
}

}  // namespace

namespace {

// translate(offset) * scale(step)
glm::dmat4 dequant_matrix(const GlbQuantization::Dequant& d) {
  glm::dmat4 m(d.step);
  m[3] = glm::dvec4(d.offset, 1.0);
  return m;
}

std::vector<float> mat4_floats(const glm::dmat4& m) {
  std::vector<float> out(16);
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) out[4 * c + r] = float(m[c][r]);
  return out;
}

// The node `n` (its JSON, from trs_json) followed by the dequantization `d`: with a matrix, matrix * D;
// with TRS, T R S D = (T + R S offset) R (S step) since D's scale is uniform.
void fold_dequant(json& node, const SkeletonNode& n, const GlbQuantization::Dequant& d) {
  if (n.has_matrix) {
    node["matrix"] = mat4_floats(glm::dmat4(n.matrix) * dequant_matrix(d));
    return;
  }
  const glm::dquat r(n.rest.rotation);
  const glm::dvec3 s(n.rest.scale);
  const glm::dvec3 t = glm::dvec3(n.rest.translation) + r * (s * d.offset);
  node["translation"] = {t.x, t.y, t.z};
  node["scale"] = {s.x * d.step, s.y * d.step, s.z * d.step};
}

std::vector<uint8_t> encode(const Character& c, const std::string& generator, const GlbQuantization* q,
                            GlbPartSizes& sizes) {
  GlbBuilder b;
  b.doc["asset"] = {{"version", "2.0"}, {"generator", generator}};
  if (q) {
    b.doc["extensionsUsed"] = {"KHR_mesh_quantization"};
    b.doc["extensionsRequired"] = {"KHR_mesh_quantization"};
  }
  const Skeleton& sk = c.skeleton;
  json nodes = json::array();
  for (size_t i = 0; i < sk.size(); ++i) {
    json n = trs_json(sk.node(i));
    std::vector<uint32_t> ch = sk.children(static_cast<uint32_t>(i));
    if (!ch.empty()) n["children"] = ch;
    nodes.push_back(n);
  }
  // Quantized unskinned meshes: the dequantization goes into the node instancing the mesh when nothing else
  // sees that node's transform (no children, no animated translation, rotation or scale); otherwise into a
  // child node made to hold the mesh, and the node's weights channels follow the mesh there.
  std::map<uint32_t, uint32_t> mesh_holder;  // node -> the node that holds its mesh in the file
  if (q) {
    std::set<uint32_t> animated;
    for (const Clip& clip : c.clips)
      for (const AnimationChannel& ch : clip.channels)
        if (ch.path != ChannelPath::kWeights) animated.insert(ch.node);
    for (const auto& [node, d] : q->nodes) {
      if (node >= sk.size()) continue;
      if (sk.children(node).empty() && !animated.count(node)) {
        fold_dequant(nodes[node], sk.node(node), d);
        continue;
      }
      SkeletonNode holder;
      holder.name = sk.node(node).name + "_dequantized";
      json h = trs_json(holder);
      fold_dequant(h, holder, d);
      mesh_holder[node] = static_cast<uint32_t>(nodes.size());
      nodes[node]["children"].push_back(nodes.size());
      nodes.push_back(h);
    }
  }
  auto holder_of = [&](uint32_t node) {
    auto it = mesh_holder.find(node);
    return it == mesh_holder.end() ? node : it->second;
  };
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
      mesh["primitives"].push_back(primitive_json(b, p, nj, q, sizes));
    }
    if (!first.morph_targets.empty()) {
      std::vector<float> weights = first.morph_weights;
      const std::span<const double> scales = q ? q->target_scales(first.node) : std::span<const double>();
      for (size_t t = 0; t < weights.size() && t < scales.size(); ++t) weights[t] = float(weights[t] * scales[t]);
      mesh["weights"] = weights;
    }
    if (!first.mesh_extras.empty()) {
      json extras = json::parse(first.mesh_extras, nullptr, false);
      // quantized targets carry their weights times the target's step over the positions': a pose-driven
      // target is fully on at that weight
      if (q && extras.is_object() && extras.contains("cagewrap_pose_correctives")) {
        const std::span<const double> scales = q->target_scales(first.node);
        json& full = extras["cagewrap_pose_correctives"]["full"];
        for (size_t t = 0; t < full.size() && t < scales.size(); ++t) full[t] = scales[t];
      }
      if (!extras.is_discarded()) mesh["extras"] = extras;
    }
    json& node = nodes[holder_of(first.node)];
    node["mesh"] = meshes.size();
    if (first.skin >= 0) node["skin"] = first.skin;
    meshes.push_back(mesh);
    i = j;
  }
  b.doc["nodes"] = nodes;
  if (!meshes.empty()) b.doc["meshes"] = meshes;
  b.part = &sizes.skin;
  for (size_t k = 0; k < c.skins.size(); ++k) {
    const Skin& s = c.skins[k];
    std::vector<float> ibm;
    for (const glm::mat4& m : s.inverse_bind) {
      if (q && k < q->skins.size()) {
        const std::vector<float> folded = mat4_floats(glm::dmat4(m) * dequant_matrix(q->skins[k]));
        ibm.insert(ibm.end(), folded.begin(), folded.end());
      } else {
        ibm.insert(ibm.end(), glm::value_ptr(m), glm::value_ptr(m) + 16);
      }
      // an affine matrix: its last row exactly (0, 0, 0, 1), as glTF requires (products of matrices round it)
      float* last = ibm.data() + ibm.size() - 16;
      last[3] = last[7] = last[11] = 0.0f;
      last[15] = 1.0f;
    }
    json skin = {{"joints", s.joints}, {"inverseBindMatrices", b.add_accessor(ibm, "MAT4", 16, kFloat, 0)}};
    if (!s.name.empty()) skin["name"] = s.name;
    b.doc["skins"].push_back(skin);
  }
  // key times shared by samplers (every channel of a baked clip keys the same frames) are written once
  b.part = &sizes.animation;
  std::map<std::vector<float>, int> times_accessor;
  for (const Clip& clip : c.clips) {
    json anim = {{"name", clip.name}};
    std::vector<int> sampler_index(clip.samplers.size(), -1);
    for (const AnimationChannel& ch : clip.channels) {
      const bool weights = ch.path == ChannelPath::kWeights;
      if (sampler_index[ch.sampler] < 0) {
        const AnimationSampler& s = clip.samplers[ch.sampler];
        // Morph weights are SCALAR (#K x #targets of them); the TRS paths are VEC3 / VEC4.
        const char* type = weights ? "SCALAR" : s.components == 4 ? "VEC4" : "VEC3";
        int nc = weights ? 1 : int(s.components);
        auto [at, fresh] = times_accessor.try_emplace(s.times, -1);
        if (fresh) at->second = b.add_accessor(s.times, "SCALAR", 1, kFloat, 0, true);
        const int in = at->second;
        std::vector<float> values = s.values;
        if (weights && q) {  // quantized targets: each weight times the target's step over the positions'
          const std::span<const double> scales = q->target_scales(ch.node);
          for (size_t v = 0; !scales.empty() && v < values.size(); ++v) values[v] = float(values[v] * scales[v % scales.size()]);
        }
        int out = b.add_accessor(values, type, nc, kFloat, 0);
        sampler_index[ch.sampler] = static_cast<int>(anim["samplers"].size());
        anim["samplers"].push_back({{"input", in}, {"output", out}, {"interpolation", interpolation_name(s.interpolation)}});
      }
      const uint32_t target = weights ? holder_of(ch.node) : ch.node;
      anim["channels"].push_back(
          {{"sampler", sampler_index[ch.sampler]}, {"target", {{"node", target}, {"path", channel_path_name(ch.path)}}}});
    }
    if (!anim.contains("channels")) continue;  // glTF requires at least one channel
    b.doc["animations"].push_back(anim);
  }
  b.part = nullptr;
  std::vector<uint32_t> roots;
  for (size_t i = 0; i < sk.size(); ++i)
    if (sk.node(i).parent < 0) roots.push_back(static_cast<uint32_t>(i));
  b.doc["scenes"] = json::array({{{"nodes", roots}}});
  b.doc["scene"] = 0;
  while (b.bin.size() % 4) b.bin.push_back(0);
  if (!b.bin.empty()) b.doc["buffers"] = json::array({{{"byteLength", b.bin.size()}}});
  return glb_container(b.doc.dump(), std::move(b.bin));
}

}  // namespace

GlbPartSizes glb_part_sizes(const Character& c, const GlbQuantization* quantization) {
  GlbPartSizes sizes;
  encode(c, "", quantization, sizes);
  return sizes;
}

std::vector<uint8_t> encode_glb(const Character& c, const std::string& generator, const GlbQuantization* quantization) {
  GlbPartSizes sizes;
  return encode(c, generator, quantization, sizes);
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

Status write_glb(const std::string& path, const Character& c, const std::string& generator,
                 const GlbQuantization* quantization) {
  std::vector<uint8_t> bytes = encode_glb(c, generator, quantization);
  return write_file_atomic(path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

}  // namespace cagewrap
