#include "core/io/patch_io.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>

#include "core/base/atomic_write.h"
#include "core/io/gltf_writer.h"
#include "core/geometry/mesh_io.h"

namespace cagewrap {

Json patch_surface_json(const PatchSurface& surface) {
  Json grids = Json::array();
  for (const PatchGrid& g : surface.grids) {
    Json rows = Json::array();
    for (uint32_t r = 0; r < g.rows; ++r) {
      Json row = Json::array();
      for (uint32_t c = 0; c < g.cols; ++c) {
        const glm::dvec3& p = g.at(r, c);
        row.push_back(Json::array({p.x, p.y, p.z}));
      }
      rows.push_back(std::move(row));
    }
    grids.push_back(Json{{"basis", patch_basis_name(g.basis)},
                         {"rows", g.rows},
                         {"cols", g.cols},
                         {"points", std::move(rows)}});
  }
  return Json{{"version", kPatchFormatVersion}, {"grids", std::move(grids)}};
}

namespace {

PatchSurface read_surface(const JsonReader& rd, const Json& j, const std::string& path) {
  if (!j.is_object()) rd.fail(ErrorCode::kParse, (path.empty() ? "the file" : path) + " should be an object");
  if (j.contains("version")) {
    const uint32_t v = rd.index(j["version"], JsonReader::join(path, "version"));
    if (v > uint32_t(kPatchFormatVersion))
      rd.fail(ErrorCode::kVersion, "patch driver format version " + std::to_string(v) +
                                       " is newer than this build reads (" +
                                       std::to_string(kPatchFormatVersion) + ")");
  }
  const std::string gp = JsonReader::join(path, "grids");
  const Json& grids = rd.array(rd.field(j, path, "grids"), gp);
  if (grids.empty()) rd.fail(ErrorCode::kEmpty, gp + " is empty: the patch driver needs at least one grid");
  PatchSurface s;
  for (size_t gi = 0; gi < grids.size(); ++gi) {
    const std::string p = JsonReader::at(gp, gi);
    const Json& jg = grids[gi];
    if (!jg.is_object()) rd.fail(ErrorCode::kParse, p + " should be an object, not " + JsonReader::show(jg));
    PatchGrid g;
    if (jg.contains("basis")) {
      const std::string basis = rd.string(jg["basis"], JsonReader::join(p, "basis"));
      if (!parse_patch_basis(basis, g.basis))
        rd.fail(ErrorCode::kParse,
                JsonReader::join(p, "basis") + " is \"" + basis + "\"; use \"bspline\" or \"bezier\"");
    }
    g.rows = rd.index(rd.field(jg, p, "rows"), JsonReader::join(p, "rows"));
    g.cols = rd.index(rd.field(jg, p, "cols"), JsonReader::join(p, "cols"));
    const std::string pp = JsonReader::join(p, "points");
    const Json& rows = rd.array(rd.field(jg, p, "points"), pp);
    if (rows.size() != g.rows)
      rd.fail(ErrorCode::kTopologyMismatch, pp + " has " + std::to_string(rows.size()) + " rows but " +
                                                JsonReader::join(p, "rows") + " is " +
                                                std::to_string(g.rows));
    for (uint32_t r = 0; r < g.rows; ++r) {
      const std::string rp = JsonReader::at(pp, r);
      const Json& row = rd.array(rows[r], rp);
      if (row.size() != g.cols)
        rd.fail(ErrorCode::kTopologyMismatch, "grid " + std::to_string(gi) + " row " + std::to_string(r) +
                                                  " (" + rp + ") has " + std::to_string(row.size()) +
                                                  " control points but " + JsonReader::join(p, "cols") +
                                                  " is " + std::to_string(g.cols));
      for (uint32_t c = 0; c < g.cols; ++c) {
        const std::string cp = JsonReader::at(rp, c);
        const std::string who = "grid " + std::to_string(gi) + " control point row " + std::to_string(r) +
                                " column " + std::to_string(c) + " (" + cp + ")";
        const Json& xyz = row[c];
        if (!xyz.is_array() || xyz.size() != 3)
          rd.fail(ErrorCode::kParse, who + " should be [x, y, z], not " + JsonReader::show(xyz));
        glm::dvec3 q;
        for (int k = 0; k < 3; ++k) {
          const Json& v = xyz[size_t(k)];
          if (v.is_null() || (v.is_number() && !std::isfinite(v.get<double>())))
            rd.fail(ErrorCode::kNonFinite,
                    who + " has a non-finite coordinate " + "xyz"[k] + " (a NaN or infinity was saved?)");
          if (!v.is_number())
            rd.fail(ErrorCode::kParse,
                    who + " coordinate " + "xyz"[k] + " should be a number, not " + JsonReader::show(v));
          q[k] = v.get<double>();
        }
        g.points.push_back(q);
      }
    }
    s.grids.push_back(std::move(g));
  }
  // sizes (>= 4, Bezier 3m + 1) with the file's name
  if (auto st = validate_patch_surface(s, path.empty() ? "the patch driver" : path); !st)
    rd.fail(st.error().code, st.error().message);
  return s;
}

}  // namespace

Result<PatchSurface> patch_surface_from_json(const Json& j, const std::string& file,
                                             const std::string& path) {
  try {
    return read_surface(JsonReader(file), j, path);
  } catch (const JsonLoadFailure& f) {
    return f.error;
  }
}

Status save_patch(const std::string& path, const PatchSurface& surface) {
  if (auto s = validate_patch_surface(surface, path); !s) return s;
  Json j{{"format", kPatchFormat}};
  const Json body = patch_surface_json(surface);
  for (const auto& [k, v] : body.items()) j[k] = v;
  return write_file_atomic(path, json_layout(j) + "\n");
}

Result<PatchSurface> load_patch(const std::string& path) {
  auto root = read_json_file(path);
  if (!root) return root.error();
  if (!root->is_object() || !root->contains("format") || (*root)["format"] != kPatchFormat)
    return make_error(ErrorCode::kUnsupportedFormat,
                      path + ": not a patch driver file (it should be a JSON object with \"format\": \"" +
                          kPatchFormat + "\")");
  return patch_surface_from_json(*root, path);
}

Status write_patch_gltf(const std::string& path, const PatchSurface& surface) {
  if (auto s = validate_patch_surface(surface, path); !s) return s;
  Json doc{{"asset", {{"version", "2.0"}, {"generator", "cagewrap"}}},
           {"scene", 0},
           {"scenes", Json::array({Json{{"nodes", Json::array({0})}}})},
           {"nodes", Json::array({Json{{"name", "patch driver"},
                                       {"extras", Json{{kPatchGltfKey, patch_surface_json(surface)}}}}})}};
  std::string text = doc.dump();
  if (!has_extension(path, ".glb")) return write_file_atomic(path, text + "\n");
  const std::vector<uint8_t> bytes = glb_container(text, {});
  return write_file_atomic(path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

Result<PatchSurface> load_patch_gltf(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return make_error(ErrorCode::kFileNotFound, path + ": cannot be opened");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (text.size() >= 4 && std::memcmp(text.data(), "glTF", 4) == 0) {  // a .glb: its JSON chunk
    auto json = glb_json_chunk(text, path);
    if (!json) return json.error();
    text = std::move(*json);
  }
  Json doc = Json::parse(text, nullptr, false);
  if (doc.is_discarded() || !doc.is_object())
    return make_error(ErrorCode::kParse, path + ": not a glTF file (its JSON does not parse)");
  for (const char* list : {"nodes", "meshes"}) {
    if (!doc.contains(list) || !doc[list].is_array()) continue;
    const Json& items = doc[list];
    for (size_t i = 0; i < items.size(); ++i) {
      const Json& item = items[i];
      if (!item.is_object() || !item.contains("extras") || !item["extras"].is_object() ||
          !item["extras"].contains(kPatchGltfKey))
        continue;
      const std::string where = std::string(list) + "[" + std::to_string(i) + "].extras." + kPatchGltfKey;
      return patch_surface_from_json(item["extras"][kPatchGltfKey], path, where);
    }
  }
  return make_error(ErrorCode::kEmpty, path + ": no node or mesh holds a patch driver (extras." +
                                           kPatchGltfKey + ", docs/patch-format.md)");
}

namespace {
bool gltf_name(const std::string& path) { return has_extension(path, ".gltf") || has_extension(path, ".glb"); }
}  // namespace

Result<PatchSurface> load_patch_any(const std::string& path) {
  return gltf_name(path) ? load_patch_gltf(path) : load_patch(path);
}

Status save_patch_any(const std::string& path, const PatchSurface& surface) {
  return gltf_name(path) ? write_patch_gltf(path, surface) : save_patch(path, surface);
}

}  // namespace cagewrap
