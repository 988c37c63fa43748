// Small hostile files, one per loader and per count or size field: each is a valid file made by the
// project's own writers (or the tests' GltfBuilder) with one field changed to claim a huge count or
// size (1e9, 3e9, 4e9, 2^63, a chunk length near 2^32). None is larger than a few kilobytes. Every
// loader must refuse each of them with a message naming the file, without asking for the memory the
// claim implies (issue 19): cagewrap_alloc_cap (tests/tools/alloc_cap.cpp) loads them under a 64 MB
// cap on any single allocation, and cagewrap_fuzz_seeds copies them into the fuzzers' seed corpora.
#pragma once

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/base/base64.h"
#include "core/io/binding_io.h"
#include "core/document/character_embedding.h"
#include "core/document/document.h"
#include "core/base/file_hash.h"
#include "core/base/json_reader.h"
#include "core/geometry/mesh_io.h"
#include "core/io/patch_io.h"
#include "core/document/project_io.h"
#include "core/deform/registration.h"
#include "core/io/set_edits_io.h"
#include "tests/fixtures.h"
#include "tests/fuzz/seed_fixtures.h"

namespace cagewrap::hostile {

// Which loader reads a file (and so which fuzzer's seeds it joins).
enum class Loader {
  kCharacter,  // load_character (.gltf, .glb)
  kMesh,       // load_mesh (.obj, .ply, .off, .stl)
  kProject,    // load_project (.cagewrap)
  kSetEdits,   // load_set_edits, then resolve_set_edits against set_edits_skin() and set_edits_cage()
  kPatch,      // load_patch (.cwpatch)
  kPatchGltf,  // load_patch_gltf (a driver in a glTF file's extras)
  kBinding,    // load_binding (.cwb)
};

inline const char* loader_name(Loader loader) {
  switch (loader) {
    case Loader::kCharacter:
      return "character";
    case Loader::kMesh:
      return "mesh";
    case Loader::kProject:
      return "project";
    case Loader::kSetEdits:
      return "set edits";
    case Loader::kPatch:
      return "patch";
    case Loader::kPatchGltf:
      return "patch glTF";
    case Loader::kBinding:
      return "binding";
  }
  return "?";
}

struct HostileFile {
  std::string name;   // a file name; its extension is what the loader goes by
  std::string bytes;  // the whole file
  Loader loader;
  std::string field;  // the field changed and its claim, for the report
};

// The skin and cage the set edits files were written for ("points": 4, "elements": the cage's).
inline std::vector<glm::vec3> set_edits_skin() { return {{0.1f, 0, 0}, {-0.1f, 0, 0}, {0, 0.2f, 0}, {0, 0, 0.3f}}; }
inline Cage set_edits_cage() { return fixtures::box_cage(1.0, 2); }

inline constexpr uint64_t k1e9 = 1000000000, k3e9 = 3000000000, k4e9 = 4000000000;
inline constexpr uint64_t k2e31 = uint64_t(1) << 31, k2e63 = uint64_t(1) << 63;

// A file's bytes, and bytes written as a file (both throw std::runtime_error when they cannot).
inline std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("hostile corpus: cannot read " + path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

inline void write_all(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw std::runtime_error("hostile corpus: cannot write " + path);
}

namespace detail {

using Json = nlohmann::ordered_json;

template <class T>
T get(const std::string& bytes, size_t at) {
  if (at + sizeof(T) > bytes.size()) throw std::runtime_error("hostile corpus: a field past the end of its file");
  T v;
  std::memcpy(&v, bytes.data() + at, sizeof(T));
  return v;
}

// Little-endian, as every binary format here stores its numbers (and x86-64 does).
template <class T>
void put(std::string& bytes, size_t at, T value) {
  if (at + sizeof(T) > bytes.size()) throw std::runtime_error("hostile corpus: a field past the end of its file");
  std::memcpy(bytes.data() + at, &value, sizeof(T));
}

template <class T>
void append(std::string& bytes, T value) {
  bytes.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

// `text` with its first `from` replaced by `to` (which must be there: the corpus follows its writers).
inline std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  if (at == std::string::npos) throw std::runtime_error("hostile corpus: no '" + from + "' in a generated file");
  return text.replace(at, from.size(), to);
}

// The builder's file as .glb / as .gltf with its buffer embedded as a data URI.
inline std::string glb_bytes(const test::GltfBuilder& builder, const std::string& scratch) {
  test::GltfBuilder b = builder;
  const std::string path = scratch + "/made.glb";
  b.write_glb(path);
  return read_all(path);
}
inline std::string gltf_bytes(const test::GltfBuilder& builder, const std::string& scratch) {
  test::GltfBuilder b = builder;
  const std::string path = scratch + "/made.gltf";
  b.write_embedded(path);
  return read_all(path);
}

// A GLB's chunks: the JSON chunk's length at byte 12, the BIN chunk's header after the JSON.
inline constexpr size_t kGlbTotalLength = 8, kGlbJsonLength = 12;
inline size_t glb_bin_length_offset(const std::string& glb) { return 20 + get<uint32_t>(glb, kGlbJsonLength); }

// glTF cases: the tetrahedron (accessor 0 POSITION VEC3, 1 indices) and the rig (2 JOINTS_0,
// 3 WEIGHTS_0, 4 inverseBindMatrices MAT4, 5 key times, 6 translations) of tests/fuzz/seed_fixtures.h.
inline void gltf_cases(const std::string& scratch, std::vector<HostileFile>& out, std::vector<HostileFile>& valid) {
  auto add = [&](std::string name, std::string bytes, std::string field) {
    out.push_back({std::move(name), std::move(bytes), Loader::kCharacter, std::move(field)});
  };
  auto with = [](test::GltfBuilder b, auto&& change) {
    change(b.doc);
    return b;
  };
  const test::GltfBuilder tet = fuzz::tet_builder(), rig = fuzz::rig_builder();
  valid.push_back({"tet.gltf", gltf_bytes(tet, scratch), Loader::kCharacter, ""});
  valid.push_back({"tet.glb", glb_bytes(tet, scratch), Loader::kCharacter, ""});
  valid.push_back({"rig.gltf", gltf_bytes(rig, scratch), Loader::kCharacter, ""});
  valid.push_back({"rig.glb", glb_bytes(rig, scratch), Loader::kCharacter, ""});
  add("gltf_positions_count_1e9.gltf",
      gltf_bytes(with(tet, [](auto& d) { d["accessors"][0]["count"] = k1e9; }), scratch),
      "accessor 0 (POSITION, VEC3) count 1,000,000,000");
  add("glb_positions_count_2e63.glb",
      glb_bytes(with(tet, [](auto& d) { d["accessors"][0]["count"] = k2e63; }), scratch),
      "accessor 0 (POSITION, VEC3) count 2^63");
  add("glb_indices_count_4e9.glb",
      glb_bytes(with(tet, [](auto& d) { d["accessors"][1]["count"] = k4e9; }), scratch),
      "accessor 1 (indices) count 4,000,000,000");
  add("glb_joints_count_1e9.glb", glb_bytes(with(rig, [](auto& d) { d["accessors"][2]["count"] = k1e9; }), scratch),
      "accessor 2 (JOINTS_0) count 1,000,000,000");
  add("glb_inverse_bind_count_1e9.glb",
      glb_bytes(with(rig, [](auto& d) { d["accessors"][4]["count"] = k1e9; }), scratch),
      "accessor 4 (skin inverseBindMatrices, MAT4) count 1,000,000,000");
  add("glb_sampler_input_count_3e9.glb",
      glb_bytes(with(rig, [](auto& d) { d["accessors"][5]["count"] = k3e9; }), scratch),
      "accessor 5 (animation sampler input) count 3,000,000,000");
  add("gltf_sampler_output_count_3e9.gltf",
      gltf_bytes(with(rig, [](auto& d) { d["accessors"][6]["count"] = k3e9; }), scratch),
      "accessor 6 (animation sampler output) count 3,000,000,000");
  add("gltf_accessor_byte_offset_2e63.gltf",
      gltf_bytes(with(tet, [](auto& d) { d["accessors"][0]["byteOffset"] = k2e63; }), scratch),
      "accessor 0 byteOffset 2^63");
  {
    // a sparse POSITION accessor (one substitution: index 0 of view 1, a value of view 0), then a
    // sparse count of 2,000,000,000 (the largest that fits glTF's 32-bit sparse count, ten times 2^27)
    auto sparse = [](uint64_t count) {
      return [count](auto& d) {
        d["accessors"][0]["sparse"] = {{"count", count},
                                       {"indices", {{"bufferView", 1}, {"componentType", test::kUnsignedShort}}},
                                       {"values", {{"bufferView", 0}}}};
      };
    };
    valid.push_back({"tet_sparse.gltf", gltf_bytes(with(tet, sparse(1)), scratch), Loader::kCharacter, ""});
    add("gltf_sparse_count_2e9.gltf", gltf_bytes(with(tet, sparse(2 * k1e9)), scratch),
        "accessor 0 sparse count 2,000,000,000");
  }
  {
    // a morph target whose POSITION accessor has no bufferView (zeros), claiming 1e9 elements
    auto morph = [](uint64_t count) {
      return [count](auto& d) {
        d["accessors"].push_back({{"componentType", test::kFloat}, {"type", "VEC3"}, {"count", count}});
        d["meshes"][0]["primitives"][0]["targets"] = {{{"POSITION", d["accessors"].size() - 1}}};
      };
    };
    valid.push_back({"tet_morph.glb", glb_bytes(with(tet, morph(4)), scratch), Loader::kCharacter, ""});
    add("glb_zero_filled_count_1e9.glb", glb_bytes(with(tet, morph(k1e9)), scratch),
        "accessor 2 (morph target POSITION, no bufferView) count 1,000,000,000");
  }
  add("gltf_view_byte_length_4e9.gltf",
      gltf_bytes(with(tet, [](auto& d) { d["bufferViews"][0]["byteLength"] = k4e9; }), scratch),
      "bufferView 0 byteLength 4,000,000,000");
  add("glb_view_byte_stride_4e9.glb",
      glb_bytes(with(tet, [](auto& d) { d["bufferViews"][0]["byteStride"] = k4e9; }), scratch),
      "bufferView 0 byteStride 4,000,000,000");
  add("glb_view_byte_offset_2e63.glb",
      glb_bytes(with(tet, [](auto& d) { d["bufferViews"][0]["byteOffset"] = k2e63; }), scratch),
      "bufferView 0 byteOffset 2^63");
  add("glb_view_byte_offset_2e64.glb",
      glb_bytes(with(tet, [](auto& d) { d["bufferViews"][0]["byteOffset"] = uint64_t(0) - 16; }), scratch),
      "bufferView 0 byteOffset 2^64 - 16 (byteOffset + byteLength wraps in 64 bits)");
  add("gltf_buffer_byte_length_1e12.gltf",
      gltf_bytes(with(tet, [](auto& d) { d["buffers"] = {{{"byteLength", 1000 * k1e9}}}; }), scratch),
      "buffer 0 (data URI) byteLength 1,000,000,000,000");
  add("glb_buffer_byte_length_4e9.glb",
      glb_bytes(with(tet, [](auto& d) { d["buffers"] = {{{"byteLength", k4e9}}}; }), scratch),
      "buffer 0 (the BIN chunk) byteLength 4,000,000,000");
  const std::string glb = glb_bytes(tet, scratch);
  {
    std::string bad = glb;
    put<uint32_t>(bad, kGlbTotalLength, 0xFFFFFFF0u);
    add("glb_total_length_4e9.glb", bad, "GLB header length 4,294,967,280");
  }
  {
    std::string bad = glb;
    put<uint32_t>(bad, kGlbJsonLength, 0xFFFFFFF0u);
    add("glb_json_chunk_length_4e9.glb", bad, "GLB JSON chunk length 4,294,967,280");
  }
  {
    std::string bad = glb;
    put<uint32_t>(bad, glb_bin_length_offset(bad), 0xFFFFFFF0u);
    add("glb_bin_chunk_length_4e9.glb", bad, "GLB BIN chunk length 4,294,967,280");
  }
}

// Mesh cases: OBJ (no counts: huge corner indices), ASCII and binary PLY, ASCII and binary OFF, binary STL.
inline void mesh_cases(const std::string& scratch, std::vector<HostileFile>& out, std::vector<HostileFile>& valid) {
  auto add = [&](std::string name, std::string bytes, std::string field) {
    out.push_back({std::move(name), std::move(bytes), Loader::kMesh, std::move(field)});
  };
  {
    PolyMesh tet;
    tet.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (auto face : {std::vector<uint32_t>{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}) tet.add_face(face);
    const std::string path = scratch + "/made.obj";
    if (!save_obj(path, tet.positions, tet).ok()) throw std::runtime_error("hostile corpus: cannot write " + path);
    const std::string obj = read_all(path);
    valid.push_back({"tet.obj", obj, Loader::kMesh, ""});
    add("obj_face_index_4e9.obj", replaced(obj, "f 2 3 4", "f 2 3 4000000000"), "face 3 corner 4,000,000,000");
    add("obj_face_index_2e63.obj", replaced(obj, "f 2 3 4", "f 2 3 9223372036854775808"), "face 3 corner 2^63");
  }
  // (OpenMesh reads list lengths of type uchar and int only)
  const std::string ply_ascii =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 2\nproperty list int int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
      "3 0 2 1\n4 0 1 3 2\n";
  valid.push_back({"tet_ascii.ply", ply_ascii, Loader::kMesh, ""});
  add("ply_ascii_vertex_count_1e9.ply", replaced(ply_ascii, "element vertex 4", "element vertex 1000000000"),
      "element vertex 1,000,000,000");
  add("ply_ascii_face_count_4e9.ply", replaced(ply_ascii, "element face 2", "element face 4000000000"),
      "element face 4,000,000,000");
  add("ply_ascii_list_count_2e9.ply", replaced(ply_ascii, "\n4 0 1 3 2", "\n2000000000 0 1 3 2"),
      "face 1 vertex_indices list count 2,000,000,000");
  add("ply_ascii_empty_element_2e63.ply",
      replaced(ply_ascii, "element face 2", "element nothing 9223372036854775807\nelement face 2"),
      "element nothing (no properties) count 2^63 - 1");
  std::string ply_binary =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list int int vertex_indices\nend_header\n";
  for (float x : {0.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f}) append(ply_binary, x);
  const size_t list_count = ply_binary.size();
  append<int32_t>(ply_binary, 3);
  for (int32_t i : {0, 1, 2}) append(ply_binary, i);
  valid.push_back({"tri_binary.ply", ply_binary, Loader::kMesh, ""});
  add("ply_binary_vertex_count_1e9.ply", replaced(ply_binary, "element vertex 3", "element vertex 1000000000"),
      "element vertex 1,000,000,000");
  add("ply_binary_vertex_count_2e63.ply",
      replaced(ply_binary, "element vertex 3", "element vertex 9223372036854775807"), "element vertex 2^63 - 1");
  add("ply_binary_face_count_4e9.ply", replaced(ply_binary, "element face 1", "element face 4000000000"),
      "element face 4,000,000,000");
  {
    std::string bad = ply_binary;
    put<int32_t>(bad, list_count, int32_t(2 * k1e9));
    add("ply_binary_list_count_2e9.ply", bad, "face 0 vertex_indices list count 2,000,000,000");
  }
  const std::string off = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  valid.push_back({"tet.off", off, Loader::kMesh, ""});
  add("off_vertex_count_1e9.off", replaced(off, "4 4 0", "1000000000 4 0"), "vertex count 1,000,000,000");
  add("off_face_count_4e9.off", replaced(off, "4 4 0", "4 4000000000 0"), "face count 4,000,000,000");
  add("off_face_corners_2e63.off", replaced(off, "3 1 2 3", "9223372036854775807 1 2 3"),
      "face 3 corner count 2^63 - 1");
  {
    // binary OFF as OpenMesh reads it: the header line, then little-endian 32-bit counts, coordinates
    // and faces (a corner count and the corners)
    auto binary_off = [](uint32_t vertices, uint32_t faces, uint32_t corners) {
      std::string b = "OFF BINARY\n";
      for (uint32_t n : {vertices, faces, 0u}) append(b, n);
      for (float x : {0.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f}) append(b, x);
      for (uint32_t n : {corners, 0u, 1u, 2u}) append(b, n);
      return b;
    };
    valid.push_back({"tri_binary.off", binary_off(3, 1, 3), Loader::kMesh, ""});
    add("off_binary_vertex_count_1e9.off", binary_off(uint32_t(k1e9), 1, 3), "vertex count 1,000,000,000");
    add("off_binary_face_count_4e9.off", binary_off(3, uint32_t(k4e9), 3), "face count 4,000,000,000");
    add("off_binary_face_corners_2e31.off", binary_off(3, 1, uint32_t(k2e31 - 1)),
        "face 0 corner count 2,147,483,647");
  }
  {
    std::string stl(80, ' ');
    append<uint32_t>(stl, 1);
    for (float x : {0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f}) append(stl, x);
    stl.append(2, '\0');
    valid.push_back({"tri_binary.stl", stl, Loader::kMesh, ""});
    std::string bad = stl;
    put<uint32_t>(bad, 80, 0xFFFFFFFFu);
    add("stl_binary_count_4e9.stl", bad, "triangle count 4,294,967,295");
    // 84 + 50 x (2^31 + 1) is 134 in 32-bit arithmetic: the size of this one-triangle file
    put<uint32_t>(bad, 80, uint32_t(k2e31 + 1));
    add("stl_binary_count_2e31.stl", bad, "triangle count 2,147,483,649 (its size wraps to the file's in 32 bits)");
  }
}

// Project cases: a project embedding the tetrahedron (so that it needs no other file), with a box cage
// and a set edit, saved by save_project; then one field changed.
inline void project_cases(const std::string& scratch, std::vector<HostileFile>& out, std::vector<HostileFile>& valid) {
  auto add = [&](std::string name, const Json& project, std::string field) {
    out.push_back({std::move(name), project.dump(1) + "\n", Loader::kProject, std::move(field)});
  };
  const std::string hero = scratch + "/hero.gltf", cage = scratch + "/cage.obj", project = scratch + "/made.cagewrap";
  fuzz::write_tet_gltf(hero);
  const Cage box = fixtures::box_cage(1.0, 2);
  if (!save_obj(cage, box.polygons.positions, box.polygons).ok())
    throw std::runtime_error("hostile corpus: cannot write " + cage);
  auto doc = document_from_files(hero, cage);
  if (!doc.ok()) throw std::runtime_error(doc.error().message);
  auto embedded = embed_character(with_set_edits(*doc, {SetEdit{1, {0, 3}, {}}}));
  if (!embedded.ok()) throw std::runtime_error(embedded.error().message);
  if (auto s = save_project(project, *embedded); !s.ok()) throw std::runtime_error(s.error().message);
  const Json base = Json::parse(read_all(project));
  valid.push_back({"embedded.cagewrap", read_all(project), Loader::kProject, ""});
  auto with = [&](auto&& change) {
    Json j = base;
    change(j);
    return j;
  };
  // the embedded character replaced by a hostile one, its hash updated so that it is loaded
  auto embedding = [&](const std::string& glb) {
    return with([&](Json& j) {
      j["character"]["embedded"] = base64_encode(glb);
      j["character"]["hash"] = format_hash(fnv1a64(glb));
    });
  };
  add("project_embedded_positions_count_1e9.cagewrap",
      embedding(glb_bytes([] {
        test::GltfBuilder b = fuzz::tet_builder();
        b.doc["accessors"][0]["count"] = k1e9;
        return b;
      }(), scratch)),
      "character.embedded: a glTF whose accessor 0 (POSITION) claims 1,000,000,000 elements");
  add("project_embedded_sampler_input_count_3e9.cagewrap",
      embedding(glb_bytes([] {
        test::GltfBuilder b = fuzz::rig_builder();
        b.doc["accessors"][5]["count"] = k3e9;
        return b;
      }(), scratch)),
      "character.embedded: a glTF whose animation sampler input claims 3,000,000,000 keys");
  add("project_set_edit_point_4e9.cagewrap", with([](Json& j) { j["set_edits"][0]["point"] = k4e9; }),
      "set_edits[0].point 4,000,000,000");
  add("project_set_edit_exclude_4e9.cagewrap", with([](Json& j) { j["set_edits"][0]["exclude"][0] = k4e9; }),
      "set_edits[0].exclude[0] 4,000,000,000");
  add("project_cage_face_corner_4e9.cagewrap", with([](Json& j) { j["cage"]["faces"][0][0] = k4e9; }),
      "cage.faces[0][0] 4,000,000,000");
  add("project_attachment_vertex_4e9.cagewrap",
      with([](Json& j) { j["attachment"]["overrides"] = {{{"vertex", k4e9}, {"node", 0}}}; }),
      "attachment.overrides[0].vertex 4,000,000,000");
  add("project_version_2e63.cagewrap", with([](Json& j) { j["version"] = k2e63 - 1; }), "version 2^63 - 1");
}

// Set edits cases: a file saved by save_set_edits for set_edits_skin() and set_edits_cage(), plus a rule.
inline void set_edits_cases(const std::string& scratch, std::vector<HostileFile>& out, std::vector<HostileFile>& valid) {
  auto add = [&](std::string name, const Json& file, std::string field) {
    out.push_back({std::move(name), file.dump(1) + "\n", Loader::kSetEdits, std::move(field)});
  };
  const std::string path = scratch + "/made.json";
  const std::vector<SetEdit> edits = {SetEdit{0, {1, 2}, {}}, SetEdit{3, {}, {4}}};
  if (auto s = save_set_edits(path, edits, set_edits_skin().size(), set_edits_cage().num_elements()); !s.ok())
    throw std::runtime_error(s.error().message);
  Json base = Json::parse(read_all(path));
  base["rules"] = Json::array({{{"mode", "remove"}, {"points", {0, 1}}, {"faces", {0}}}});
  valid.push_back({"edits.json", base.dump(1) + "\n", Loader::kSetEdits, ""});
  auto with = [&](auto&& change) {
    Json j = base;
    change(j);
    return j;
  };
  add("set_edits_points_4e9.json", with([](Json& j) { j["points"] = k4e9; }), "points 4,000,000,000");
  add("set_edits_points_2e63.json", with([](Json& j) { j["points"] = k2e63; }), "points 2^63");
  add("set_edits_elements_4e9.json", with([](Json& j) { j["elements"] = k4e9; }), "elements 4,000,000,000");
  add("set_edits_edit_point_4e9.json", with([](Json& j) { j["edits"][0]["point"] = k4e9; }),
      "edits[0].point 4,000,000,000");
  add("set_edits_rule_point_4e9.json", with([](Json& j) { j["rules"][0]["points"][1] = k4e9; }),
      "rules[0].points[1] 4,000,000,000");
}

// Patch driver cases: a 4 x 5 B-spline grid saved by save_patch and write_patch_gltf.
inline void patch_cases(const std::string& scratch, std::vector<HostileFile>& out, std::vector<HostileFile>& valid) {
  PatchSurface driver;
  PatchGrid g;
  g.rows = 4;
  g.cols = 5;
  for (uint32_t r = 0; r < g.rows; ++r)
    for (uint32_t c = 0; c < g.cols; ++c) g.points.push_back({double(c), 0.1 * r * c, double(r)});
  driver.grids.push_back(g);
  const std::string cwpatch = scratch + "/made.cwpatch", gltf = scratch + "/made_patch.gltf",
                    glb = scratch + "/made_patch.glb";
  for (const std::string& path : {cwpatch, gltf, glb})
    if (auto s = save_patch_any(path, driver); !s.ok()) throw std::runtime_error(s.error().message);
  const Json base = Json::parse(read_all(cwpatch));
  valid.push_back({"driver.cwpatch", read_all(cwpatch), Loader::kPatch, ""});
  valid.push_back({"driver.gltf", read_all(gltf), Loader::kPatchGltf, ""});
  valid.push_back({"driver.glb", read_all(glb), Loader::kPatchGltf, ""});
  auto cw = [&](std::string name, const char* key, uint64_t claim, std::string field) {
    Json j = base;
    j["grids"][0][key] = claim;
    out.push_back({std::move(name), j.dump(1) + "\n", Loader::kPatch, std::move(field)});
  };
  cw("patch_rows_4e9.cwpatch", "rows", k4e9, "grids[0].rows 4,000,000,000");
  cw("patch_cols_4e9.cwpatch", "cols", k4e9, "grids[0].cols 4,000,000,000");
  cw("patch_rows_2e63.cwpatch", "rows", k2e63, "grids[0].rows 2^63");
  {
    Json j = Json::parse(read_all(gltf));
    j["nodes"][0]["extras"][kPatchGltfKey]["grids"][0]["cols"] = k4e9;
    out.push_back({"patch_gltf_cols_4e9.gltf", j.dump() + "\n", Loader::kPatchGltf,
                   "nodes[0].extras.cagewrap_patch.grids[0].cols 4,000,000,000"});
  }
  {
    std::string bad = read_all(glb);
    put<uint32_t>(bad, kGlbJsonLength, 0xFFFFFFF0u);
    out.push_back({"patch_glb_json_chunk_length_4e9.glb", bad, Loader::kPatchGltf,
                   "GLB JSON chunk length 4,294,967,280"});
  }
}

// The byte offset of every count in a version 2 .cwb file, found by walking a valid file along the
// layout documented in core/io/binding_io.h.
inline std::vector<std::pair<std::string, size_t>> binding_count_offsets(const std::string& bytes) {
  constexpr size_t kParams = 8 + 8 + 4 + 8 + 8 + 8 + 1;  // local, epsilon, K, scale, max_distance, close_distance, variant
  constexpr size_t kNumPoints = 8 + 4 + kParams + 8 + 3 * 8;  // magic, version, parameters, h, origin
  std::vector<std::pair<std::string, size_t>> out = {{"num_points", kNumPoints}, {"num_cage_vertices", kNumPoints + 4}};
  size_t at = kNumPoints + 8;
  auto table = [&](const char* name, size_t element) {
    out.emplace_back(name, at);
    at += 8 + get<uint64_t>(bytes, at) * element;
  };
  table("rest_cage", 12);
  table("elements", 12);
  table("element_status", 1);
  table("offsets", 4);
  table("ids", 4);
  table("weights", 4);
  table("bary", 4);
  table("rigid_points", 4);
  table("rigid_element", 4);
  table("rigid_bary", 4);
  at += 4 + 4 + 8 + 1 + 4 + 1;  // the report; separate, separation_steps, separation_applied
  table("set_offsets", 4);
  table("set_ids", 4);
  table("set_weights", 4);
  table("separated", 4);
  if (at != bytes.size()) throw std::runtime_error("hostile corpus: the .cwb layout changed (see core/io/binding_io.h)");
  return out;
}

// Binding cases: a small sphere bound to a box cage (extended variant: the set tables are filled),
// saved by binding_bytes; then each count of the header and of every table made huge.
inline void binding_cases(std::vector<HostileFile>& out, std::vector<HostileFile>& valid) {
  const PolyMesh skin = fixtures::sphere_skin(0.5, 4, 6);
  const Cage cage = fixtures::box_cage(1.0, 2);
  auto b = bind_skin(skin.positions, cage, cage.polygons.positions, BindParams{});
  if (!b.ok()) throw std::runtime_error(b.error().message);
  const std::string bytes = binding_bytes(*b);
  valid.push_back({"sphere.cwb", bytes, Loader::kBinding, ""});
  bool odd = false;
  for (const auto& [field, at] : binding_count_offsets(bytes)) {
    std::string bad = bytes;
    if (field == "num_points" || field == "num_cage_vertices") {
      put<uint32_t>(bad, at, uint32_t(k4e9));
      out.push_back({"binding_" + field + "_4e9.cwb", bad, Loader::kBinding, field + " 4,000,000,000"});
      continue;
    }
    // 1e9 and 2^63 entries, table by table in turn (2^63 times the entry size does not fit 64 bits)
    const uint64_t claim = (odd = !odd) ? k1e9 : k2e63;
    put<uint64_t>(bad, at, claim);
    out.push_back({"binding_" + field + (claim == k1e9 ? "_count_1e9.cwb" : "_count_2e63.cwb"), bad,
                   Loader::kBinding, field + " count " + (claim == k1e9 ? "1,000,000,000" : "2^63")});
  }
}

}  // namespace detail

struct Corpus {
  std::vector<HostileFile> hostile;
  // the valid files they were made from (their `field` empty): each must load, or a hostile file could
  // fail for a reason of its own
  std::vector<HostileFile> originals;
};

// Every hostile file and its original. `scratch` is an existing folder the writers may use (the files
// are returned, not left there).
inline Corpus hostile_corpus(const std::string& scratch) {
  Corpus c;
  detail::gltf_cases(scratch, c.hostile, c.originals);
  detail::mesh_cases(scratch, c.hostile, c.originals);
  detail::project_cases(scratch, c.hostile, c.originals);
  detail::set_edits_cases(scratch, c.hostile, c.originals);
  detail::patch_cases(scratch, c.hostile, c.originals);
  detail::binding_cases(c.hostile, c.originals);
  return c;
}

}  // namespace cagewrap::hostile
