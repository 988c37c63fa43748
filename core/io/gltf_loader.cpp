// glTF 2.0 import through tinygltf (its implementation is compiled here, once, with images left
// undecoded: a character needs geometry, skins and animation, not textures).
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>

#include "core/io/gltf_loader.h"
#include "core/io/assimp_loader.h"
#include "core/io/skin_weights.h"
#include "core/base/digits.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <numeric>

#include <glm/gtc/type_ptr.hpp>
#include <nlohmann/json.hpp>

namespace cagewrap {
namespace {

bool ignore_image(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int,
                  void*) {
  return true;
}

std::string named(const char* kind, size_t index, const std::string& name) {
  return std::string(kind) + " " + std::to_string(index) + (name.empty() ? "" : " ('" + name + "')");
}

double read_component(const uint8_t* p, int type, bool normalized) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      int8_t v;
      std::memcpy(&v, p, 1);
      return normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
      uint8_t v = *p;
      return normalized ? v / 255.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? v / 65535.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return normalized ? v / 4294967295.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
  }
  return 0.0;
}

int component_size(int type) {
  int s = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(type));
  return type == TINYGLTF_COMPONENT_TYPE_DOUBLE ? -1 : s;  // glTF has no doubles
}

// Indices and joints must be of an unsigned integer type (a signed one could hold negative indices).
bool unsigned_integer_type(int type) {
  return type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE || type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
         type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
}

// Reads accessors into flat arrays, checking every index and byte range against the file.
class AccessorReader {
 public:
  AccessorReader(const tinygltf::Model& model, const std::string& file) : m_(model), file_(file) {}

  Error fail(ErrorCode code, const std::string& msg) const { return make_error(code, file_ + ": " + msg); }

  // Accessor `index` used as `what`, with `components` per element (0 = any), as doubles.
  Result<std::vector<double>> read(int index, const std::string& what, int components, bool allow_float = true,
                                   bool allow_int = true) {
    if (index < 0 || index >= static_cast<int>(m_.accessors.size()))
      return fail(ErrorCode::kIndexOutOfRange, what + " refers to accessor " + std::to_string(index) +
                                                   ", but the file has " + std::to_string(m_.accessors.size()) +
                                                   " accessors");
    const tinygltf::Accessor& a = m_.accessors[index];
    const std::string label = named("accessor", index, a.name) + " (" + what + ")";
    const int nc = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(a.type));
    const int cs = component_size(a.componentType);
    if (nc <= 0 || cs <= 0) return fail(ErrorCode::kParse, label + " has an unknown type or component type");
    if (components > 0 && nc != components)
      return fail(ErrorCode::kParse, label + " has " + std::to_string(nc) + " components per element, expected " +
                                         std::to_string(components));
    const bool is_float = a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT;
    if ((is_float && !allow_float) || (!is_float && !allow_int) || (!allow_float && !unsigned_integer_type(a.componentType)))
      return fail(ErrorCode::kParse, label + " has component type " + std::to_string(a.componentType) +
                                         (allow_float ? ", expected FLOAT" : ", expected an unsigned integer type"));
    if (nc > 4 && !is_float)
      return fail(ErrorCode::kParse, label + ": integer matrices are not supported (use FLOAT)");
    const size_t count = a.count;
    const size_t elem = static_cast<size_t>(nc) * cs;
    // Every size is checked against the file's bytes before anything is allocated: a small file may
    // claim a billion elements.
    const uint8_t* data = nullptr;
    size_t stride = elem;
    if (a.bufferView >= 0) {
      auto view = view_bytes(a.bufferView, label);
      if (!view) return view.error();
      const auto [bytes, length, declared_stride] = *view;
      data = bytes;
      stride = declared_stride ? declared_stride : elem;
      if (declared_stride && declared_stride < elem)
        return fail(ErrorCode::kParse, label + ": bufferView " + std::to_string(a.bufferView) + " has byteStride " +
                                           std::to_string(declared_stride) + ", smaller than one element (" +
                                           std::to_string(elem) + " bytes)");
      if (count > 0) {
        const unsigned __int128 need =
            (unsigned __int128)a.byteOffset + (unsigned __int128)stride * (count - 1) + elem;
        if (need > length)
          return fail(ErrorCode::kIndexOutOfRange,
                      label + " needs " + group_digits(need) + " bytes but bufferView " +
                          std::to_string(a.bufferView) + " holds " + group_digits(length) + " (count " +
                          group_digits(count) + ", " + std::to_string(stride) + " bytes apart from byteOffset " +
                          group_digits(a.byteOffset) + ")");
      }
    } else if (count > zero_filled_limit()) {
      // no bufferView: the elements start as zeros (a sparse accessor's base). A real one is as long as
      // the data it goes with (a morph target's positions), so its count is bounded by the buffers' size.
      return fail(ErrorCode::kIndexOutOfRange,
                  label + " has no bufferView and claims " + group_digits(count) + " elements (" +
                      group_digits((unsigned __int128)count * nc * sizeof(double)) +
                      " bytes to read), more than the file's buffers (" + group_digits(buffer_bytes()) +
                      " bytes) could go with");
    }
    std::vector<double> out(count * nc, 0.0);
    if (data) {
      for (size_t i = 0; i < count; ++i) {
        const uint8_t* p = data + a.byteOffset + i * stride;
        for (int c = 0; c < nc; ++c) out[i * nc + c] = read_component(p + c * cs, a.componentType, a.normalized);
      }
    }
    if (a.sparse.isSparse) {
      const auto& sp = a.sparse;
      const std::string slabel = label + " sparse";
      if (sp.count < 0 || size_t(sp.count) > count)
        return fail(ErrorCode::kIndexOutOfRange, slabel + " count " + std::to_string(sp.count) +
                                                     " exceeds the accessor count " + group_digits(count));
      const int ics = component_size(sp.indices.componentType);
      if (ics <= 0 || !unsigned_integer_type(sp.indices.componentType))
        return fail(ErrorCode::kParse, slabel + " indices have component type " +
                                           std::to_string(sp.indices.componentType) + ", expected an unsigned integer type");
      auto iview = view_bytes(sp.indices.bufferView, slabel + " indices");
      if (!iview) return iview.error();
      auto vview = view_bytes(sp.values.bufferView, slabel + " values");
      if (!vview) return vview.error();
      const unsigned __int128 ineed = (unsigned __int128)sp.indices.byteOffset + (unsigned __int128)ics * sp.count;
      const unsigned __int128 vneed = (unsigned __int128)sp.values.byteOffset + (unsigned __int128)elem * sp.count;
      if (sp.indices.byteOffset < 0 || ineed > std::get<1>(*iview))
        return fail(ErrorCode::kIndexOutOfRange, slabel + " indices reach byte " + group_digits(ineed) +
                                                     " of bufferView " + std::to_string(sp.indices.bufferView) +
                                                     ", which is only " + std::to_string(std::get<1>(*iview)) +
                                                     " bytes long");
      if (sp.values.byteOffset < 0 || vneed > std::get<1>(*vview))
        return fail(ErrorCode::kIndexOutOfRange, slabel + " values reach byte " + group_digits(vneed) +
                                                     " of bufferView " + std::to_string(sp.values.bufferView) +
                                                     ", which is only " + std::to_string(std::get<1>(*vview)) +
                                                     " bytes long");
      const uint8_t* ip = std::get<0>(*iview) + sp.indices.byteOffset;
      const uint8_t* vp = std::get<0>(*vview) + sp.values.byteOffset;
      for (int k = 0; k < sp.count; ++k) {
        double target = read_component(ip + size_t(k) * ics, sp.indices.componentType, false);
        if (target >= double(count))
          return fail(ErrorCode::kIndexOutOfRange, slabel + " index " + std::to_string(k) + " targets element " +
                                                       std::to_string(uint64_t(target)) + ", but the accessor has " +
                                                       std::to_string(count));
        size_t t = static_cast<size_t>(target);
        for (int c = 0; c < nc; ++c)
          out[t * nc + c] = read_component(vp + size_t(k) * elem + c * cs, a.componentType, a.normalized);
      }
    }
    for (size_t i = 0; i < out.size(); ++i)
      if (!std::isfinite(out[i]))
        return fail(ErrorCode::kNonFinite, label + " element " + std::to_string(i / nc) + " is not finite");
    return out;
  }

  size_t count(int index) const { return m_.accessors[index].count; }

 private:
  // The most elements an accessor without a bufferView may claim: one per 4 bytes of the file's buffers
  // (a float each), and at least 65,536 (8 MB of doubles for a 16-component element).
  size_t zero_filled_limit() const { return std::max<size_t>(size_t(1) << 16, buffer_bytes() / 4); }
  size_t buffer_bytes() const {
    size_t total = 0;
    for (const auto& b : m_.buffers) total += b.data.size();
    return total;
  }

  // Pointer, byte length and byteStride of a buffer view, after checking it lies in its buffer.
  Result<std::tuple<const uint8_t*, size_t, size_t>> view_bytes(int view, const std::string& label) const {
    if (view < 0 || view >= static_cast<int>(m_.bufferViews.size()))
      return fail(ErrorCode::kIndexOutOfRange, label + " refers to bufferView " + std::to_string(view) +
                                                   ", but the file has " + std::to_string(m_.bufferViews.size()) +
                                                   " buffer views");
    const tinygltf::BufferView& bv = m_.bufferViews[view];
    const std::string vlabel = named("bufferView", view, bv.name);
    if (bv.buffer < 0 || bv.buffer >= static_cast<int>(m_.buffers.size()))
      return fail(ErrorCode::kIndexOutOfRange, vlabel + " refers to buffer " + std::to_string(bv.buffer) +
                                                   ", but the file has " + std::to_string(m_.buffers.size()) +
                                                   " buffers");
    const tinygltf::Buffer& b = m_.buffers[bv.buffer];
    // in 128 bits: a byteOffset near 2^64 must not wrap round to a small end
    const unsigned __int128 end = (unsigned __int128)bv.byteOffset + bv.byteLength;
    if (end > b.data.size())
      return fail(ErrorCode::kIndexOutOfRange, vlabel + " spans bytes " + group_digits(bv.byteOffset) + ".." +
                                                   group_digits(end) + " of " + named("buffer", bv.buffer, b.name) +
                                                   ", which holds only " + group_digits(b.data.size()) + " bytes");
    return std::tuple<const uint8_t*, size_t, size_t>{b.data.data() + bv.byteOffset, bv.byteLength, bv.byteStride};
  }

  const tinygltf::Model& m_;
  const std::string& file_;
};

// "a%20b.bin" -> "a b.bin" (URIs in glTF are percent-encoded).
std::string percent_decode(const std::string& uri) {
  std::string out;
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(uint8_t(uri[i + 1])) && std::isxdigit(uint8_t(uri[i + 2]))) {
      out += static_cast<char>(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

// After tinygltf refused a file, find which buffer could not be read, so the message names it.
// `bytes` is the whole file; `dir` the folder its relative URIs start from, or nullptr when the
// file came from memory and may refer to no other file.
std::string diagnose_buffers(const std::string& bytes, bool binary, const std::filesystem::path* dir) {
  std::string json_text = bytes;
  if (binary) {
    if (bytes.size() < 20) return "";
    uint32_t len;
    std::memcpy(&len, bytes.data() + 12, 4);
    if (20 + uint64_t(len) > bytes.size()) return "";
    json_text = bytes.substr(20, len);
  }
  auto j = nlohmann::json::parse(json_text, nullptr, false);
  if (j.is_discarded() || !j.is_object() || !j.contains("buffers") || !j["buffers"].is_array()) return "";
  for (size_t i = 0; i < j["buffers"].size(); ++i) {
    const auto& b = j["buffers"][i];
    if (!b.is_object()) return named("buffer", i, "") + " is not a JSON object";
    std::string name = b.contains("name") && b["name"].is_string() ? b["name"].get<std::string>() : "";
    if (!b.contains("byteLength") || !b["byteLength"].is_number_unsigned() || b["byteLength"].get<uint64_t>() == 0)
      return named("buffer", i, name) + " has no usable byteLength (it must be a whole number above 0)";
    if (b.contains("uri") && !b["uri"].is_string()) return named("buffer", i, name) + " has a 'uri' that is not a string";
    if (!b.contains("uri")) {
      if (!binary) return named("buffer", i, name) + " has no 'uri' (only a .glb may embed its first buffer)";
      continue;
    }
    std::string uri = b["uri"].get<std::string>();
    if (uri.rfind("data:", 0) == 0) continue;
    if (!dir)
      return named("buffer", i, name) + " refers to the file '" + uri +
             "'; a character kept in memory (embedded in a project) must hold all its buffers";
    auto file = *dir / percent_decode(uri);
    std::error_code ec;
    if (!std::filesystem::exists(file, ec))
      return named("buffer", i, name) + " refers to '" + uri + "', which does not exist";
    uint64_t size = std::filesystem::file_size(file, ec);
    uint64_t want = b["byteLength"].get<uint64_t>();
    if (!ec && size != want)
      return named("buffer", i, name) + " declares byteLength " + std::to_string(want) + " but '" + uri +
             "' holds " + std::to_string(size) + " bytes";
  }
  return "";
}

std::string read_whole_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// File access for a character parsed from memory: there are no other files.
bool no_file_exists(const std::string&, void*) { return false; }
std::string same_path(const std::string& path, void*) { return path; }
bool no_file_read(std::vector<unsigned char>*, std::string* err, const std::string& path, void*) {
  if (err) *err += "'" + path + "' cannot be read: a character in memory may refer to no other file\n";
  return false;
}
bool no_file_write(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err) *err += "no files are written\n";
  return false;
}

std::string first_lines(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  for (char& c : s)
    if (c == '\n') c = ';';
  return s;
}

class Importer {
 public:
  Importer(const tinygltf::Model& model, const std::string& file) : m_(model), file_(file), reader_(model, file) {}

  Result<Character> run() {
    Character c;
    c.source = file_;
    if (auto s = build_skeleton(c); !s) return s.error();
    if (auto s = build_skins(c); !s) return s.error();
    if (auto s = build_primitives(c); !s) return s.error();
    if (auto s = build_clips(c); !s) return s.error();
    if (lines_or_points_)
      warn(c, std::to_string(lines_or_points_) + " primitive(s) are points or lines (e.g. " + first_line_prim_ +
                  "); they have vertices but no triangles");
    return c;
  }

 private:
  Error fail(ErrorCode code, const std::string& msg) const { return make_error(code, file_ + ": " + msg); }
  void warn(Character& c, const std::string& msg) const { c.warnings.push_back(file_ + ": " + msg); }

  Status build_skeleton(Character& c) {
    const size_t n = m_.nodes.size();
    std::vector<SkeletonNode> nodes(n);
    size_t non_unit = 0;
    for (size_t i = 0; i < n; ++i) {
      const tinygltf::Node& src = m_.nodes[i];
      SkeletonNode& dst = nodes[i];
      dst.name = src.name;
      if (src.matrix.size() == 16) {
        dst.has_matrix = true;
        for (int k = 0; k < 16; ++k) glm::value_ptr(dst.matrix)[k] = static_cast<float>(src.matrix[k]);
      }
      if (src.translation.size() == 3)
        dst.rest.translation = glm::vec3(src.translation[0], src.translation[1], src.translation[2]);
      if (src.scale.size() == 3) dst.rest.scale = glm::vec3(src.scale[0], src.scale[1], src.scale[2]);
      if (src.rotation.size() == 4) {
        glm::dquat q(src.rotation[3], src.rotation[0], src.rotation[1], src.rotation[2]);
        double len = glm::length(q);
        if (!(len > 0) || !std::isfinite(len))
          return fail(ErrorCode::kNonFinite, named("node", i, src.name) + " has a zero or non-finite rotation");
        if (std::abs(len - 1.0) > 1e-3) ++non_unit;
        dst.rest.rotation = glm::quat(q / len);
      }
      for (int child : src.children) {
        if (child < 0 || child >= static_cast<int>(n))
          return fail(ErrorCode::kIndexOutOfRange, named("node", i, src.name) + " lists child " +
                                                       std::to_string(child) + ", but the file has " +
                                                       std::to_string(n) + " nodes");
        if (nodes[child].parent >= 0 && nodes[child].parent != static_cast<int32_t>(i))
          return fail(ErrorCode::kParse, named("node", child, m_.nodes[child].name) + " is a child of both node " +
                                             std::to_string(nodes[child].parent) + " and node " + std::to_string(i) +
                                             "; the node hierarchy must be a tree");
        nodes[child].parent = static_cast<int32_t>(i);
      }
    }
    if (non_unit) warn(c, std::to_string(non_unit) + " node rotation(s) were not unit quaternions; normalized");
    auto s = Skeleton::create(std::move(nodes), file_);
    if (!s) return s.error();
    c.skeleton = std::move(s).value();
    // The nodes the default scene reaches (all roots when the file has no scene).
    reachable_.assign(n, false);
    std::vector<int> stack;
    if (m_.scenes.empty()) {
      for (size_t i = 0; i < n; ++i)
        if (c.skeleton.node(i).parent < 0) stack.push_back(static_cast<int>(i));
    } else {
      int scene = m_.defaultScene >= 0 ? m_.defaultScene : 0;
      if (scene >= static_cast<int>(m_.scenes.size()))
        return fail(ErrorCode::kIndexOutOfRange, "the default scene is " + std::to_string(scene) +
                                                     ", but the file has " + std::to_string(m_.scenes.size()) +
                                                     " scenes");
      for (int root : m_.scenes[scene].nodes) {
        if (root < 0 || root >= static_cast<int>(n))
          return fail(ErrorCode::kIndexOutOfRange, named("scene", scene, m_.scenes[scene].name) + " lists node " +
                                                       std::to_string(root) + ", but the file has " +
                                                       std::to_string(n) + " nodes");
        stack.push_back(root);
      }
    }
    while (!stack.empty()) {
      int i = stack.back();
      stack.pop_back();
      if (reachable_[i]) continue;
      reachable_[i] = true;
      for (int ch : m_.nodes[i].children) stack.push_back(ch);
    }
    return Ok{};
  }

  Status build_skins(Character& c) {
    for (size_t s = 0; s < m_.skins.size(); ++s) {
      const tinygltf::Skin& src = m_.skins[s];
      const std::string label = named("skin", s, src.name);
      Skin skin;
      skin.name = src.name;
      for (size_t k = 0; k < src.joints.size(); ++k) {
        int j = src.joints[k];
        if (j < 0 || j >= static_cast<int>(m_.nodes.size()))
          return fail(ErrorCode::kIndexOutOfRange, label + " joint " + std::to_string(k) + " is node " +
                                                       std::to_string(j) + ", but the file has " +
                                                       std::to_string(m_.nodes.size()) + " nodes");
        skin.joints.push_back(static_cast<uint32_t>(j));
      }
      if (skin.joints.empty()) return fail(ErrorCode::kEmpty, label + " has no joints");
      if (skin.joints.size() > 65535)
        return fail(ErrorCode::kInvalidArgument, label + " has more than 65535 joints");
      skin.inverse_bind.assign(skin.joints.size(), glm::mat4(1.0f));
      if (src.inverseBindMatrices >= 0) {
        auto m = reader_.read(src.inverseBindMatrices, label + " inverseBindMatrices", 16, true, false);
        if (!m) return m.error();
        if (m->size() / 16 < skin.joints.size())
          return fail(ErrorCode::kTopologyMismatch, label + " has " + std::to_string(skin.joints.size()) +
                                                        " joints but only " + std::to_string(m->size() / 16) +
                                                        " inverse bind matrices");
        for (size_t j = 0; j < skin.joints.size(); ++j)
          for (int k = 0; k < 16; ++k)
            glm::value_ptr(skin.inverse_bind[j])[k] = static_cast<float>((*m)[j * 16 + k]);
      }
      c.skins.push_back(std::move(skin));
    }
    return Ok{};
  }

  Status build_primitives(Character& c) {
    for (size_t node = 0; node < m_.nodes.size(); ++node) {
      const tinygltf::Node& n = m_.nodes[node];
      if (!reachable_[node] || n.mesh < 0) continue;
      if (n.mesh >= static_cast<int>(m_.meshes.size()))
        return fail(ErrorCode::kIndexOutOfRange, named("node", node, n.name) + " refers to mesh " +
                                                     std::to_string(n.mesh) + ", but the file has " +
                                                     std::to_string(m_.meshes.size()) + " meshes");
      if (n.skin >= static_cast<int>(m_.skins.size()))
        return fail(ErrorCode::kIndexOutOfRange, named("node", node, n.name) + " refers to skin " +
                                                     std::to_string(n.skin) + ", but the file has " +
                                                     std::to_string(m_.skins.size()) + " skins");
      const tinygltf::Mesh& mesh = m_.meshes[n.mesh];
      for (size_t p = 0; p < mesh.primitives.size(); ++p) {
        Primitive prim;
        prim.mesh_name = mesh.name;
        prim.mesh = static_cast<uint32_t>(n.mesh);
        prim.primitive = static_cast<uint32_t>(p);
        prim.node = static_cast<uint32_t>(node);
        if (auto s = build_primitive(c, mesh.primitives[p], n, mesh, prim); !s) return s.error();
        c.primitives.push_back(std::move(prim));
      }
    }
    return Ok{};
  }

  Status build_primitive(Character& c, const tinygltf::Primitive& src, const tinygltf::Node& node,
                         const tinygltf::Mesh& mesh, Primitive& prim) {
    const std::string label = prim.label();
    auto attr = [&](const std::string& name) {
      auto it = src.attributes.find(name);
      return it == src.attributes.end() ? -1 : it->second;
    };
    int pos_acc = attr("POSITION");
    if (pos_acc < 0) return fail(ErrorCode::kParse, label + " has no POSITION attribute");
    auto pos = reader_.read(pos_acc, label + " POSITION", 3, true, true);
    if (!pos) return pos.error();
    const size_t nv = pos->size() / 3;
    prim.positions.resize(nv);
    for (size_t v = 0; v < nv; ++v)
      prim.positions[v] = glm::vec3((*pos)[3 * v], (*pos)[3 * v + 1], (*pos)[3 * v + 2]);

    // Indices, then triangles by mode.
    std::vector<uint32_t> idx;
    if (src.indices >= 0) {
      auto ix = reader_.read(src.indices, label + " indices", 1, false, true);
      if (!ix) return ix.error();
      idx.resize(ix->size());
      for (size_t k = 0; k < ix->size(); ++k) {
        double v = (*ix)[k];
        if (v >= double(nv))
          return fail(ErrorCode::kIndexOutOfRange, label + ": index " + std::to_string(uint64_t(v)) +
                                                       " at position " + std::to_string(k) + " of accessor " +
                                                       std::to_string(src.indices) + " is out of range (the "
                                                       "primitive has " + std::to_string(nv) + " vertices)");
        idx[k] = static_cast<uint32_t>(v);
      }
    } else {
      idx.resize(nv);
      std::iota(idx.begin(), idx.end(), 0u);
    }
    const int mode = src.mode < 0 ? TINYGLTF_MODE_TRIANGLES : src.mode;
    if (mode == TINYGLTF_MODE_TRIANGLES) {
      for (size_t k = 0; k + 2 < idx.size(); k += 3) prim.triangles.push_back({idx[k], idx[k + 1], idx[k + 2]});
      if (idx.size() % 3)
        warn(c, label + ": " + std::to_string(idx.size()) + " indices is not a multiple of 3; the last " +
                    std::to_string(idx.size() % 3) + " were ignored");
    } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
      for (size_t k = 0; k + 2 < idx.size(); ++k) {
        Tri t = k % 2 == 0 ? Tri{idx[k], idx[k + 1], idx[k + 2]} : Tri{idx[k + 1], idx[k], idx[k + 2]};
        if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) prim.triangles.push_back(t);  // skip restart degenerates
      }
    } else if (mode == TINYGLTF_MODE_TRIANGLE_FAN) {
      for (size_t k = 1; k + 1 < idx.size(); ++k) prim.triangles.push_back({idx[k], idx[k + 1], idx[0]});
    } else if (mode >= 0 && mode <= 3) {
      if (lines_or_points_++ == 0) first_line_prim_ = label;
    } else {
      return fail(ErrorCode::kParse, label + " has unknown mode " + std::to_string(mode));
    }

    // Skin weights.
    if (node.skin >= 0) {
      if (attr("JOINTS_0") < 0) {
        warn(c, label + " is instanced by a skinned node but has no JOINTS_0; it moves rigidly with its node");
      } else {
        prim.skin = node.skin;
        if (auto s = build_weights(c, src, prim, c.skins[node.skin], node.skin); !s) return s.error();
      }
    }

    // Morph targets (position offsets) and their default weights.
    for (size_t t = 0; t < src.targets.size(); ++t) {
      std::vector<glm::vec3> delta(nv, glm::vec3(0.0f));
      auto it = src.targets[t].find("POSITION");
      if (it != src.targets[t].end()) {
        auto d = reader_.read(it->second, label + " morph target " + std::to_string(t) + " POSITION", 3);
        if (!d) return d.error();
        if (d->size() / 3 != nv)
          return fail(ErrorCode::kTopologyMismatch, label + " morph target " + std::to_string(t) + " has " +
                                                        std::to_string(d->size() / 3) + " positions, but the "
                                                        "primitive has " + std::to_string(nv) + " vertices");
        for (size_t v = 0; v < nv; ++v) delta[v] = glm::vec3((*d)[3 * v], (*d)[3 * v + 1], (*d)[3 * v + 2]);
      }
      prim.morph_targets.push_back(std::move(delta));
    }
    const auto& defaults = !node.weights.empty() ? node.weights : mesh.weights;
    prim.morph_weights.assign(prim.morph_targets.size(), 0.0f);
    for (size_t t = 0; t < prim.morph_weights.size() && t < defaults.size(); ++t)
      prim.morph_weights[t] = static_cast<float>(defaults[t]);
    return Ok{};
  }

  Status build_weights(Character& c, const tinygltf::Primitive& src, Primitive& prim, const Skin& skin,
                       int skin_index) {
    const std::string label = prim.label();
    const size_t nv = prim.num_vertices();
    std::vector<std::vector<double>> joints, weights;
    for (int set = 0;; ++set) {
      auto jt = src.attributes.find("JOINTS_" + std::to_string(set));
      if (jt == src.attributes.end()) break;
      auto wt = src.attributes.find("WEIGHTS_" + std::to_string(set));
      if (wt == src.attributes.end())
        return fail(ErrorCode::kParse, label + " has JOINTS_" + std::to_string(set) + " but no WEIGHTS_" +
                                           std::to_string(set));
      auto j = reader_.read(jt->second, label + " JOINTS_" + std::to_string(set), 4, false, true);
      if (!j) return j.error();
      auto w = reader_.read(wt->second, label + " WEIGHTS_" + std::to_string(set), 4, true, true);
      if (!w) return w.error();
      if (j->size() != nv * 4 || w->size() != nv * 4)
        return fail(ErrorCode::kTopologyMismatch, label + " JOINTS_" + std::to_string(set) + "/WEIGHTS_" +
                                                      std::to_string(set) + " have " + std::to_string(j->size() / 4) +
                                                      " and " + std::to_string(w->size() / 4) +
                                                      " elements, but the primitive has " + std::to_string(nv) +
                                                      " vertices");
      joints.push_back(std::move(j).value());
      weights.push_back(std::move(w).value());
    }
    const size_t nj = skin.joints.size();
    SkinWeightCleanup cleanup;
    prim.influence_start.assign(1, 0);
    prim.influence_start.reserve(nv + 1);
    std::vector<std::pair<uint32_t, double>> entries;
    for (size_t v = 0; v < nv; ++v) {
      entries.clear();
      for (size_t set = 0; set < joints.size(); ++set) {
        for (int k = 0; k < 4; ++k) {
          const double j = joints[set][v * 4 + k], w = weights[set][v * 4 + k];
          if (w > 0 && j >= double(nj))  // (JOINTS of a signed component type were refused when read)
            return fail(ErrorCode::kIndexOutOfRange,
                        label + " vertex " + std::to_string(v) + ": JOINTS_" + std::to_string(set) + " lists joint " +
                            std::to_string(uint64_t(j)) + ", but " + named("skin", skin_index, skin.name) + " has " +
                            std::to_string(nj) + " joints");
          entries.emplace_back(static_cast<uint32_t>(std::min(j, double(UINT32_MAX))), w);
        }
      }
      cleanup.add_vertex(v, entries, prim);
    }
    for (const std::string& w : cleanup.take_warnings(label, named("skin", skin_index, skin.name))) warn(c, w);
    return Ok{};
  }

  Status build_clips(Character& c) {
    size_t skipped_channels = 0;
    std::string skipped_example;
    for (size_t a = 0; a < m_.animations.size(); ++a) {
      const tinygltf::Animation& src = m_.animations[a];
      const std::string alabel = named("animation", a, src.name);
      Clip clip;
      clip.name = src.name.empty() ? "animation_" + std::to_string(a) : src.name;
      clip.samplers.resize(src.samplers.size());
      std::vector<bool> decoded(src.samplers.size(), false);
      for (size_t ci = 0; ci < src.channels.size(); ++ci) {
        const tinygltf::AnimationChannel& ch = src.channels[ci];
        const std::string clabel = alabel + " channel " + std::to_string(ci);
        if (ch.sampler < 0 || ch.sampler >= static_cast<int>(src.samplers.size()))
          return fail(ErrorCode::kIndexOutOfRange, clabel + " uses sampler " + std::to_string(ch.sampler) +
                                                       ", but the animation has " +
                                                       std::to_string(src.samplers.size()) + " samplers");
        if (ch.target_node >= static_cast<int>(m_.nodes.size()))
          return fail(ErrorCode::kIndexOutOfRange, clabel + " targets node " + std::to_string(ch.target_node) +
                                                       ", but the file has " + std::to_string(m_.nodes.size()) +
                                                       " nodes");
        AnimationChannel out;
        out.sampler = static_cast<uint32_t>(ch.sampler);
        uint32_t components = 0;
        bool known_path = true;
        if (ch.target_path == "translation") {
          out.path = ChannelPath::kTranslation;
          components = 3;
        } else if (ch.target_path == "rotation") {
          out.path = ChannelPath::kRotation;
          components = 4;
        } else if (ch.target_path == "scale") {
          out.path = ChannelPath::kScale;
          components = 3;
        } else if (ch.target_path == "weights") {
          out.path = ChannelPath::kWeights;
        } else {
          known_path = false;
        }
        // A node given by a matrix may not be animated (glTF 2.0, 3.5.2); channels without a node
        // belong to extensions.
        bool usable = known_path && ch.target_node >= 0 && m_.nodes[ch.target_node].matrix.size() != 16;
        if (!usable) {
          if (skipped_channels++ == 0)
            skipped_example = clabel + " (path '" + ch.target_path + "', node " + std::to_string(ch.target_node) + ")";
          continue;
        }
        out.node = static_cast<uint32_t>(ch.target_node);
        AnimationSampler& s = clip.samplers[ch.sampler];
        if (out.path == ChannelPath::kWeights) {
          // One weight per morph target of the node's mesh.
          const tinygltf::Node& n = m_.nodes[ch.target_node];
          size_t targets = 0;
          if (n.mesh >= 0 && n.mesh < static_cast<int>(m_.meshes.size()) && !m_.meshes[n.mesh].primitives.empty())
            targets = m_.meshes[n.mesh].primitives[0].targets.size();
          if (targets == 0) {
            if (skipped_channels++ == 0) skipped_example = clabel + " (weights of a node without morph targets)";
            continue;
          }
          components = static_cast<uint32_t>(targets);
        }
        if (!decoded[ch.sampler]) {
          if (auto st = decode_sampler(src.samplers[ch.sampler], alabel + " sampler " + std::to_string(ch.sampler),
                                       components, s);
              !st)
            return st.error();
          decoded[ch.sampler] = true;
        } else if (s.components != components) {
          return fail(ErrorCode::kParse, clabel + " uses sampler " + std::to_string(ch.sampler) + " with " +
                                             std::to_string(components) + " components, but another channel uses it "
                                             "with " + std::to_string(s.components));
        }
        if (!s.times.empty()) clip.duration = std::max(clip.duration, double(s.times.back()));
        clip.channels.push_back(out);
      }
      c.clips.push_back(std::move(clip));
    }
    if (skipped_channels)
      warn(c, std::to_string(skipped_channels) + " animation channel(s) target nothing this importer can animate "
                                                 "(e.g. " + skipped_example + "); ignored");
    return Ok{};
  }

  Status decode_sampler(const tinygltf::AnimationSampler& src, const std::string& label, uint32_t components,
                        AnimationSampler& s) {
    if (src.interpolation == "STEP")
      s.interpolation = Interpolation::kStep;
    else if (src.interpolation == "CUBICSPLINE")
      s.interpolation = Interpolation::kCubicSpline;
    else if (src.interpolation == "LINEAR" || src.interpolation.empty())
      s.interpolation = Interpolation::kLinear;
    else
      return fail(ErrorCode::kParse, label + " has unknown interpolation '" + src.interpolation + "'");
    auto in = reader_.read(src.input, label + " input", 1, true, false);
    if (!in) return in.error();
    auto out = reader_.read(src.output, label + " output", 0);
    if (!out) return out.error();
    const size_t k = in->size();
    if (k == 0) return fail(ErrorCode::kEmpty, label + " has no keyframes");
    for (size_t i = 1; i < k; ++i)
      if ((*in)[i] < (*in)[i - 1])
        return fail(ErrorCode::kParse, label + ": key " + std::to_string(i) + " time " + std::to_string((*in)[i]) +
                                           " is earlier than key " + std::to_string(i - 1) + " time " +
                                           std::to_string((*in)[i - 1]));
    const size_t per_key = components * (s.interpolation == Interpolation::kCubicSpline ? 3 : 1);
    if (out->size() != k * per_key)
      return fail(ErrorCode::kTopologyMismatch, label + " output holds " + std::to_string(out->size()) +
                                                    " values, but " + std::to_string(k) + " keys of " +
                                                    std::to_string(per_key) + " values need " +
                                                    std::to_string(k * per_key));
    s.components = components;
    s.times.assign(in->begin(), in->end());
    s.values.assign(out->begin(), out->end());
    return Ok{};
  }


  const tinygltf::Model& m_;
  const std::string& file_;
  AccessorReader reader_;
  std::vector<bool> reachable_;
  size_t lines_or_points_ = 0;
  std::string first_line_prim_;
};

// tinygltf parses into `model`; a throw from inside it (it indexes some arrays with at(), and a huge
// size can fail to allocate) becomes a parse failure with the exception's text, never a crash.
bool parse_guarded(const std::function<bool(std::string*, std::string*)>& parse, std::string& err,
                   std::string& warn) {
  try {
    return parse(&err, &warn);
  } catch (const std::bad_alloc&) {
    err = "it asks for more memory than there is (a size in it is too large)";
  } catch (const std::exception& e) {
    err = std::string("the glTF reader stopped: ") + e.what();
  }
  return false;
}

Result<Character> import_parsed(bool ok, const tinygltf::Model& model, const std::string& err,
                                const std::string& warn, const std::string& name, const std::string& bytes,
                                bool binary, const std::filesystem::path* dir) {
  if (!ok) {
    std::string which = diagnose_buffers(bytes, binary, dir);
    if (!which.empty()) return make_error(ErrorCode::kFileUnreadable, name + ": " + which);
    return make_error(ErrorCode::kParse, name + ": not a usable glTF 2.0 file: " + first_lines(err));
  }
  // Required extensions that change what the geometry's bytes mean: the compressed ones cannot be read here
  // (KHR_mesh_quantization, integer attributes, is read like any accessor).
  for (const std::string& ext : model.extensionsRequired)
    if (ext == "KHR_draco_mesh_compression" || ext == "EXT_meshopt_compression" || ext == "KHR_meshopt_compression")
      return make_error(ErrorCode::kUnsupportedFormat,
                        name + ": its meshes are compressed with " + ext +
                            ", which cagewrap does not read; save it uncompressed (e.g. gltf-transform copy, or "
                            "Blender's glTF export without compression)");
  try {
    auto c = Importer(model, name).run();
    if (c && !warn.empty()) c->warnings.insert(c->warnings.begin(), name + ": " + first_lines(warn));
    return c;
  } catch (const std::bad_alloc&) {
    return make_error(ErrorCode::kParse, name + ": not a usable glTF 2.0 file: a size in it is too large to load");
  }
}

}  // namespace

std::vector<std::string> character_extensions() {
  std::vector<std::string> out{".glb", ".gltf"};
  out.insert(out.end(), assimp_character_extensions().begin(), assimp_character_extensions().end());
  return out;
}

bool is_character_file(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& ch : ext) ch = char(std::tolower(static_cast<unsigned char>(ch)));
  return ext == ".glb" || ext == ".gltf" || is_assimp_character(path);
}

Result<Character> load_character(const std::string& path, const CharacterLoadOptions& options) {
  if (is_assimp_character(path)) return load_character_assimp(path, options);
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    return make_error(ErrorCode::kFileNotFound, path + ": no such file");
  if (std::filesystem::is_directory(path, ec))
    return make_error(ErrorCode::kFileUnreadable, path + ": is a directory, not a glTF file");
  char magic[4] = {};
  {
    std::ifstream in(path, std::ios::binary);
    if (!in) return make_error(ErrorCode::kFileUnreadable, path + ": cannot be opened");
    in.read(magic, 4);
  }
  const bool binary = std::memcmp(magic, "glTF", 4) == 0;
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(&ignore_image, nullptr);
  tinygltf::Model model;
  std::string err, warn;
  const bool ok = parse_guarded(
      [&](std::string* e, std::string* w) {
        return binary ? loader.LoadBinaryFromFile(&model, e, w, path) : loader.LoadASCIIFromFile(&model, e, w, path);
      },
      err, warn);
  const auto dir = std::filesystem::path(path).parent_path();
  return import_parsed(ok, model, err, warn, path, ok ? std::string() : read_whole_file(path), binary, &dir);
}

Result<Character> load_character_bytes(const std::string& bytes, const std::string& name, const CharacterLoadOptions& options,
                                       const std::string& file_name) {
  if (bytes.empty()) return make_error(ErrorCode::kEmpty, name + ": is empty");
  if (is_assimp_character(file_name)) return load_character_assimp_bytes(bytes, name, file_name, options);
  if (bytes.size() > std::numeric_limits<unsigned int>::max())
    return make_error(ErrorCode::kFileUnreadable, name + ": is larger than 4 GiB");
  const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(&ignore_image, nullptr);
  loader.SetFsCallbacks({&no_file_exists, &same_path, &no_file_read, &no_file_write, nullptr});
  tinygltf::Model model;
  std::string err, warn;
  const auto size = static_cast<unsigned int>(bytes.size());
  const bool ok = parse_guarded(
      [&](std::string* e, std::string* w) {
        return binary ? loader.LoadBinaryFromMemory(&model, e, w, reinterpret_cast<const unsigned char*>(bytes.data()),
                                                    size, "")
                      : loader.LoadASCIIFromString(&model, e, w, bytes.data(), size, "");
      },
      err, warn);
  return import_parsed(ok, model, err, warn, name, bytes, binary, nullptr);
}

}  // namespace cagewrap
