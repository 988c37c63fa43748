#include "core/project_io.h"

#include <bit>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/atomic_write.h"
#include "core/file_hash.h"
#include "core/gltf_loader.h"
#include "core/json_reader.h"
#include "core/set_edits_io.h"

namespace cagewrap {

namespace fs = std::filesystem;

namespace {

const char* const kKnownFields[] = {"format", "version", "character", "cage", "binding", "set_edits", "extensions"};

bool known_field(const std::string& key) {
  for (const char* k : kKnownFields)
    if (key == k) return true;
  return false;
}

// ------------------------------------------------------------------ writing

// The double nearest to the shortest decimal that reads back as `f` (so the file says 0.1, not
// 0.100000001490116); falls back to f itself in the rare case reading that double as a float
// would round differently. Either way the float reads back bit for bit.
double short_float(float f) {
  char text[32];
  auto written = std::to_chars(text, text + sizeof text, f);
  double d = 0;
  std::from_chars(text, written.ptr, d);
  return std::bit_cast<uint32_t>(static_cast<float>(d)) == std::bit_cast<uint32_t>(f) ? d : double(f);
}

std::string number(double x) { return Json(x).dump(); }

// {"a": 1, "b": "x"}: one line, spaced like the rest of the file.
std::string one_line(const Json& object) {
  std::string s = "{";
  for (const auto& [key, value] : object.items()) s += (s.size() > 1 ? ", " : "") + Json(key).dump() + ": " + value.dump();
  return s + "}";
}

// The character path as the project records it: relative to the project's folder, '/' separated.
std::string relative_character_path(const std::string& project_path, const std::string& character_path) {
  fs::path project_dir = fs::absolute(project_path).lexically_normal().parent_path();
  fs::path character = fs::absolute(character_path).lexically_normal();
  fs::path rel = character.lexically_relative(project_dir);
  return (rel.empty() ? character : rel).generic_string();
}

Result<std::string> project_text(const std::string& path, const Document& doc) {
  Json preserved = Json::object();
  if (!doc.preserved_fields.empty()) {
    preserved = Json::parse(doc.preserved_fields, nullptr, false);
    if (!preserved.is_object())
      return make_error(ErrorCode::kInvalidArgument, path + ": the document's preserved fields are not a JSON object");
  }
  std::string s = "{\n";
  s += "  \"format\": " + Json(kProjectFormat).dump() + ",\n";
  s += "  \"version\": " + std::to_string(kProjectVersion) + ",\n";
  Json character = {{"path", relative_character_path(path, doc.character_path)}, {"hash", doc.character_hash}};
  s += "  \"character\": " + one_line(character) + ",\n";
  s += "  \"cage\": {\n    \"positions\": [";
  auto positions = doc.cage_positions();
  for (size_t v = 0; v < positions.size(); ++v) {
    const glm::vec3& p = positions[v];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      return make_error(ErrorCode::kNonFinite, path + ": not saved: cage vertex " + std::to_string(v) +
                                                   " has a non-finite coordinate; move it back first");
    s += std::string(v ? "," : "") + "\n      [" + number(short_float(p.x)) + ", " + number(short_float(p.y)) + ", " +
         number(short_float(p.z)) + "]";
  }
  s += positions.empty() ? "],\n    \"faces\": [" : "\n    ],\n    \"faces\": [";
  size_t num_faces = doc.cage ? doc.cage->polygons.num_faces() : 0;
  for (size_t f = 0; f < num_faces; ++f) s += std::string(f ? "," : "") + "\n      " + json_index_list(doc.cage->polygons.face(f));
  s += num_faces ? "\n    ]" : "]";
  if (!doc.cage_offsets.empty()) {
    s += ",\n    \"offsets\": [";
    for (size_t v = 0; v < doc.cage_offsets.size(); ++v) {
      const glm::vec3& o = doc.cage_offsets[v];
      s += std::string(v ? "," : "") + "\n      [" + number(short_float(o.x)) + ", " + number(short_float(o.y)) + ", " +
           number(short_float(o.z)) + "]";
    }
    s += "\n    ]";
  }
  s += "\n  },\n";
  const BindParams& p = doc.params;
  Json binding = {{"variant", variant_name(p.variant)}, {"local", p.local},
                  {"epsilon", p.epsilon},               {"max_elements", p.max_elements},
                  {"scale", p.scale},                   {"max_distance", p.max_distance},
                  {"close_distance", p.close_distance}, {"separate", p.separate},
                  {"separation_steps", p.separation_steps}};
  s += "  \"binding\": " + one_line(binding) + ",\n";
  s += "  \"set_edits\": [";
  for (size_t i = 0; i < doc.set_edits.size(); ++i) {
    s += std::string(i ? "," : "") + "\n    " + set_edit_json(doc.set_edits[i]);
  }
  s += doc.set_edits.empty() ? "],\n" : "\n  ],\n";
  s += "  \"extensions\": " + (preserved.contains("extensions") ? preserved["extensions"] : Json::object()).dump();
  for (const auto& [key, value] : preserved.items())
    if (!known_field(key)) s += ",\n  " + Json(key).dump() + ": " + value.dump();
  return s + "\n}\n";
}

// ------------------------------------------------------------------ reading

using Reader = JsonReader;

std::shared_ptr<const Cage> read_cage(const Reader& r, const Json& root) {
  const Json& cage = r.object(root, "", "cage");
  const Json& positions = r.array(r.field(cage, "cage", "positions"), "cage.positions");
  const Json& faces = r.array(r.field(cage, "cage", "faces"), "cage.faces");
  if (positions.empty() && faces.empty()) return nullptr;  // no cage yet
  PolyMesh mesh;
  for (size_t v = 0; v < positions.size(); ++v) {
    std::string path = Reader::at("cage.positions", v);
    const Json& p = positions[v];
    if (!p.is_array() || p.size() != 3) r.fail(ErrorCode::kParse, path + " should be [x, y, z], not " + Reader::show(p));
    mesh.positions.emplace_back(r.finite_float(p[0], path + "[0]"), r.finite_float(p[1], path + "[1]"),
                                r.finite_float(p[2], path + "[2]"));
  }
  if (faces.empty()) r.fail(ErrorCode::kEmpty, "cage.faces is empty; a cage needs at least one face");
  std::vector<uint32_t> corners;
  for (size_t f = 0; f < faces.size(); ++f) {
    std::string path = Reader::at("cage.faces", f);
    corners = r.indices(faces[f], path);
    if (corners.size() < 3)
      r.fail(ErrorCode::kParse, path + " has " + std::to_string(corners.size()) + " corners; a face needs at least 3");
    for (size_t k = 0; k < corners.size(); ++k)
      if (corners[k] >= mesh.positions.size())
        r.fail(ErrorCode::kIndexOutOfRange, Reader::at(path, k) + " is vertex " + std::to_string(corners[k]) +
                                                ", but the cage has " + std::to_string(mesh.positions.size()) +
                                                " vertices");
    mesh.add_face(corners);
  }
  auto made = make_cage(std::move(mesh), "cage");
  if (!made) r.fail(made.error().code, made.error().message);
  return std::make_shared<const Cage>(std::move(made).value());
}

BindParams read_params(const Reader& r, const Json& root, std::vector<std::string>& warnings, const std::string& file) {
  const Json& b = r.object(root, "", "binding");
  BindParams p;
  std::string variant = r.string(r.field(b, "binding", "variant"), "binding.variant");
  if (!parse_variant(variant, p.variant))
    r.fail(ErrorCode::kParse, "binding.variant is '" + variant + "'; expected basic, clamped or extended");
  p.local = r.number(r.field(b, "binding", "local"), "binding.local");
  p.epsilon = r.number(r.field(b, "binding", "epsilon"), "binding.epsilon");
  p.max_elements = r.index(r.field(b, "binding", "max_elements"), "binding.max_elements");
  p.scale = r.number(r.field(b, "binding", "scale"), "binding.scale");
  p.max_distance = r.number(r.field(b, "binding", "max_distance"), "binding.max_distance");
  p.close_distance = r.number(r.field(b, "binding", "close_distance"), "binding.close_distance");
  // added after version 1 was fixed: a project without them was made without automatic separation
  p.separate = b.contains("separate") && r.boolean(b["separate"], "binding.separate");
  if (b.contains("separation_steps")) p.separation_steps = r.index(b["separation_steps"], "binding.separation_steps");
  if (auto v = validate(p); !v) r.fail(ErrorCode::kInvalidArgument, "binding: " + v.error().message);
  for (const auto& [key, value] : b.items())
    if (key != "variant" && key != "local" && key != "epsilon" && key != "max_elements" && key != "scale" &&
        key != "max_distance" && key != "close_distance" && key != "separate" && key != "separation_steps")
      warnings.push_back(file + ": binding." + key + " is not known to this build and was ignored");
  return p;
}

std::vector<SetEdit> read_set_edits(const Reader& r, const Json& root, size_t num_elements) {
  const Json& edits = r.array(r.field(root, "", "set_edits"), "set_edits");
  std::vector<SetEdit> out;
  for (size_t i = 0; i < edits.size(); ++i) out.push_back(read_set_edit(r, edits[i], Reader::at("set_edits", i), num_elements));
  return out;
}

Result<ProjectLoad> load(const std::string& path, const std::string& character_override, std::string* missing) {
  Reader r(path);
  auto parsed = read_json_file(path);
  if (!parsed) return parsed.error();
  const Json& root = *parsed;
  if (!root.is_object() || !root.contains("format"))
    return make_error(ErrorCode::kUnsupportedFormat,
                      path + ": not a cagewrap project (it has no \"format\": \"cagewrap-project\" field)");
  if (root["format"] != kProjectFormat)
    return make_error(ErrorCode::kUnsupportedFormat, path + ": not a cagewrap project (\"format\" is " +
                                                         Reader::show(root["format"]) + ", expected \"" +
                                                         kProjectFormat + "\")");
  const Json& version = r.field(root, "", "version");
  if (!version.is_number_integer() || version.get<int64_t>() < 1)
    r.fail(ErrorCode::kParse, "version should be a whole number >= 1, not " + Reader::show(version));
  if (version.get<int64_t>() > kProjectVersion)
    return make_error(ErrorCode::kVersion, path + ": made by a newer cagewrap: version " +
                                               std::to_string(version.get<int64_t>()) + ", this build reads up to " +
                                               std::to_string(kProjectVersion) + "; update cagewrap to open it");

  ProjectLoad out;
  Document& doc = out.document;
  const Json& character = r.object(root, "", "character");
  std::string recorded = r.string(r.field(character, "character", "path"), "character.path");
  if (recorded.empty()) r.fail(ErrorCode::kParse, "character.path is empty");
  std::string recorded_hash = r.string(r.field(character, "character", "hash"), "character.hash");
  doc.cage = read_cage(r, root);
  doc.params = read_params(r, root, out.warnings, path);
  doc.set_edits = read_set_edits(r, root, doc.cage ? doc.cage->num_elements() : 0);
  if (const Json& cage = r.object(root, "", "cage"); cage.contains("offsets")) {
    const Json& offsets = r.array(cage["offsets"], "cage.offsets");
    const size_t nv = doc.cage ? doc.cage->num_vertices() : 0;
    if (offsets.size() != nv)
      r.fail(ErrorCode::kTopologyMismatch, "cage.offsets has " + std::to_string(offsets.size()) +
                                               " entries but the cage has " + std::to_string(nv) + " vertices");
    for (size_t v = 0; v < offsets.size(); ++v) {
      std::string path = Reader::at("cage.offsets", v);
      const Json& o = offsets[v];
      if (!o.is_array() || o.size() != 3) r.fail(ErrorCode::kParse, path + " should be [x, y, z], not " + Reader::show(o));
      doc.cage_offsets.emplace_back(r.finite_float(o[0], path + "[0]"), r.finite_float(o[1], path + "[1]"),
                                    r.finite_float(o[2], path + "[2]"));
    }
  }

  Json preserved = Json::object();
  if (root.contains("extensions")) {
    if (!root["extensions"].is_object())
      r.fail(ErrorCode::kParse, "extensions should be an object, not " + Reader::show(root["extensions"]));
    if (!root["extensions"].empty()) preserved["extensions"] = root["extensions"];
  }
  for (const auto& [key, value] : root.items())
    if (!known_field(key)) {
      preserved[key] = value;
      out.warnings.push_back(path + ": field '" + key +
                             "' is not known to this build (made by a newer cagewrap?); it is kept and written back on save");
    }
  if (!preserved.empty()) doc.preserved_fields = preserved.dump();

  // The character: a relative path is relative to the project's folder.
  fs::path resolved = fs::path(recorded);
  if (resolved.is_relative()) resolved = fs::path(path).parent_path() / resolved;
  resolved = fs::absolute(resolved).lexically_normal();  // independent of later changes of the working folder
  std::string character_path = character_override.empty() ? resolved.string() : character_override;
  out.character_relocated = !character_override.empty() && fs::path(character_override).lexically_normal() != resolved;
  std::error_code ec;
  if (!fs::exists(character_path, ec)) {
    if (missing) *missing = character_path;
    return make_error(ErrorCode::kFileNotFound, path + ": character file " + character_path +
                                                    " not found; locate it (or move it back beside the project)");
  }
  auto loaded = load_character(character_path);
  if (!loaded) return make_error(loaded.error().code, path + ": the character could not be loaded: " + loaded.error().message);
  auto hash = hash_file(character_path);
  if (!hash) return hash.error();
  if (*hash != recorded_hash)
    out.warnings.push_back(path + ": the character file " + character_path +
                           " changed since the project was saved (hash " + *hash + ", project says " + recorded_hash +
                           "); check that the cage and set edits still fit it");
  const size_t num_points = loaded->num_vertices();
  for (size_t i = 0; i < doc.set_edits.size(); ++i)
    if (doc.set_edits[i].point >= num_points)
      r.fail(ErrorCode::kIndexOutOfRange, Reader::at("set_edits", i) + ".point is skin vertex " +
                                              std::to_string(doc.set_edits[i].point) + ", but the character has " +
                                              std::to_string(num_points) + " vertices");
  doc.character = std::make_shared<const Character>(std::move(loaded).value());
  doc.character_path = character_path;
  doc.character_hash = std::move(hash).value();
  doc.project_path = path;
  doc.revision = next_revision();
  return out;
}

}  // namespace

Status save_project(const std::string& path, const Document& doc) {
  if (doc.character_path.empty())
    return make_error(ErrorCode::kInvalidArgument, path + ": not saved: the document has no character file");
  std::error_code ec;
  if (fs::absolute(path).lexically_normal() == fs::absolute(doc.character_path).lexically_normal() ||
      fs::equivalent(path, doc.character_path, ec))
    return make_error(ErrorCode::kInvalidArgument,
                      path + ": not saved: that is the character file; choose another name for the project");
  if (auto v = validate(doc.params); !v)
    return make_error(ErrorCode::kInvalidArgument, path + ": not saved: " + v.error().message);
  try {
    auto text = project_text(path, doc);
    if (!text) return text.error();
    return write_file_atomic(path, *text);
  } catch (const Json::exception& e) {  // a string that is not UTF-8 (a file name, a preserved field)
    return make_error(ErrorCode::kInvalidArgument, path + ": not saved: " + e.what());
  }
}

Result<ProjectLoad> load_project(const std::string& path, const std::string& character_override,
                                 std::string* missing_character) {
  if (missing_character) missing_character->clear();
  try {
    return load(path, character_override, missing_character);
  } catch (const JsonLoadFailure& f) {
    return f.error;
  }
}

}  // namespace cagewrap
