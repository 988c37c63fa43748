// The tests' own hand-built glTF writer: JSON through nlohmann::json, one binary buffer that is
// embedded as a base64 data URI, written beside the .gltf, or packed into a .glb. Independent of
// core/gltf_writer so the loader is checked against files it did not produce.
#pragma once

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <unistd.h>

namespace cagewrap::test {

constexpr int kByte = 5120, kUnsignedByte = 5121, kShort = 5122, kUnsignedShort = 5123, kUnsignedInt = 5125,
              kFloat = 5126;

inline std::string base64(const std::vector<uint8_t>& data) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  size_t i = 0;
  for (; i + 2 < data.size(); i += 3) {
    uint32_t n = (data[i] << 16) | (data[i + 1] << 8) | data[i + 2];
    for (int k = 3; k >= 0; --k) out += kAlphabet[(n >> (6 * k)) & 63];
  }
  if (i + 1 == data.size()) {
    uint32_t n = data[i] << 16;
    out += kAlphabet[(n >> 18) & 63];
    out += kAlphabet[(n >> 12) & 63];
    out += "==";
  } else if (i + 2 == data.size()) {
    uint32_t n = (data[i] << 16) | (data[i + 1] << 8);
    out += kAlphabet[(n >> 18) & 63];
    out += kAlphabet[(n >> 12) & 63];
    out += kAlphabet[(n >> 6) & 63];
    out += '=';
  }
  return out;
}

class GltfBuilder {
 public:
  nlohmann::json doc;        // edit freely before writing
  std::vector<uint8_t> bin;  // buffer 0

  GltfBuilder() {
    doc["asset"] = {{"version", "2.0"}, {"generator", "cagewrap tests"}};
  }

  // Appends bytes (4-aligned) as a new bufferView; returns its index.
  int add_view(const void* data, size_t bytes) {
    while (bin.size() % 4) bin.push_back(0);
    size_t offset = bin.size();
    bin.resize(offset + bytes);
    std::memcpy(bin.data() + offset, data, bytes);
    nlohmann::json v = {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}};
    doc["bufferViews"].push_back(v);
    return static_cast<int>(doc["bufferViews"].size()) - 1;
  }

  // An accessor over a new bufferView holding `values` (component type from T unless given).
  template <class T>
  int add_accessor(const std::vector<T>& values, const std::string& type, int component_type,
                   bool normalized = false, bool min_max = false) {
    int view = add_view(values.data(), values.size() * sizeof(T));
    size_t nc = components(type);
    nlohmann::json a = {{"bufferView", view}, {"componentType", component_type}, {"count", values.size() / nc},
                        {"type", type}};
    if (normalized) a["normalized"] = true;
    if (min_max) {
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
  int add_floats(const std::vector<float>& v, const std::string& type, bool min_max = false) {
    return add_accessor(v, type, kFloat, false, min_max);
  }

  int add_node(nlohmann::json node) {
    doc["nodes"].push_back(std::move(node));
    return static_cast<int>(doc["nodes"].size()) - 1;
  }
  void set_scene(const std::vector<int>& roots) {
    doc["scenes"] = nlohmann::json::array({{{"nodes", roots}}});
    doc["scene"] = 0;
  }

  // .gltf with buffer 0 as a base64 data URI.
  void write_embedded(const std::string& path) {
    nlohmann::json d = finished();
    d["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64(bin);
    std::ofstream(path) << d.dump(1);
  }
  // .gltf plus `bin_name` beside it.
  void write_external(const std::string& path, const std::string& bin_name) {
    nlohmann::json d = finished();
    d["buffers"][0]["uri"] = bin_name;
    std::ofstream(path) << d.dump(1);
    auto bin_path = std::filesystem::path(path).parent_path() / bin_name;
    std::ofstream(bin_path, std::ios::binary).write(reinterpret_cast<const char*>(bin.data()), bin.size());
  }
  void write_glb(const std::string& path) {
    std::string json = finished().dump();
    while (json.size() % 4) json += ' ';
    std::vector<uint8_t> b = bin;
    while (b.size() % 4) b.push_back(0);
    uint32_t total = 12 + 8 + json.size() + 8 + b.size();
    std::ofstream out(path, std::ios::binary);
    auto u32 = [&](uint32_t v) { out.write(reinterpret_cast<const char*>(&v), 4); };
    u32(0x46546C67);
    u32(2);
    u32(total);
    u32(static_cast<uint32_t>(json.size()));
    u32(0x4E4F534A);
    out.write(json.data(), json.size());
    u32(static_cast<uint32_t>(b.size()));
    u32(0x004E4942);
    out.write(reinterpret_cast<const char*>(b.data()), b.size());
  }

  static size_t components(const std::string& type) {
    if (type == "SCALAR") return 1;
    if (type == "VEC2") return 2;
    if (type == "VEC3") return 3;
    if (type == "VEC4" || type == "MAT2") return 4;
    if (type == "MAT3") return 9;
    return 16;
  }

 private:
  nlohmann::json finished() const {
    nlohmann::json d = doc;
    while (d["buffers"].size() < 1) d["buffers"].push_back(nlohmann::json::object());
    // a byteLength already in doc is kept (tests of bad lengths)
    if (!d["buffers"][0].contains("byteLength")) d["buffers"][0]["byteLength"] = bin.size();
    return d;
  }
};

// A fresh, empty temporary folder for one test.
inline std::string temp_dir(const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() / ("cagewrap_test_" + name + "_" + std::to_string(getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

}  // namespace cagewrap::test
