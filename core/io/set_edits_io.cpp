#include "core/io/set_edits_io.h"

#include "core/base/atomic_write.h"

namespace cagewrap {

std::string set_edit_json(const SetEdit& e) {
  std::string s = "{\"point\": " + std::to_string(e.point) + ", \"exclude\": " + json_index_list(e.exclude) +
                  ", \"include\": " + json_index_list(e.include);
  if (e.only) s += ", \"only\": true";
  return s + "}";
}

SetEdit read_set_edit(const JsonReader& r, const Json& e, const std::string& path, size_t num_elements) {
  if (!e.is_object()) r.fail(ErrorCode::kParse, path + " should be an object, not " + JsonReader::show(e));
  SetEdit edit;
  edit.point = r.index(r.field(e, path, "point"), path + ".point");
  for (auto [key, list] : {std::pair{"exclude", &edit.exclude}, std::pair{"include", &edit.include}}) {
    if (!e.contains(key)) continue;
    std::string list_path = JsonReader::join(path, key);
    *list = r.indices(e[key], list_path);
    for (size_t k = 0; k < list->size(); ++k)
      if ((*list)[k] >= num_elements)
        r.fail(ErrorCode::kIndexOutOfRange, JsonReader::at(list_path, k) + " is element " +
                                                std::to_string((*list)[k]) + ", but the cage has " +
                                                std::to_string(num_elements) + " elements (triangles)");
  }
  if (e.contains("only")) edit.only = r.boolean(e["only"], path + ".only");
  return edit;
}

namespace {

SetEditsFile read_file(const JsonReader& r, const Json& root) {
  if (!root.is_object() || !root.contains("format"))
    r.fail(ErrorCode::kUnsupportedFormat,
           std::string("not a set edits file (it has no \"format\": \"") + kSetEditsFormat + "\" field)");
  if (root["format"] != kSetEditsFormat)
    r.fail(ErrorCode::kUnsupportedFormat, "not a set edits file (\"format\" is " +
                                              JsonReader::show(root["format"]) + ", expected \"" +
                                              kSetEditsFormat + "\")");
  const Json& version = r.field(root, "", "version");
  if (!version.is_number_integer() || version.get<int64_t>() < 1)
    r.fail(ErrorCode::kParse, "version should be a whole number >= 1, not " + JsonReader::show(version));
  if (version.get<int64_t>() > kSetEditsVersion)
    r.fail(ErrorCode::kVersion, "made by a newer cagewrap: version " +
                                    std::to_string(version.get<int64_t>()) + ", this build reads up to " +
                                    std::to_string(kSetEditsVersion) + "; update cagewrap to read it");
  SetEditsFile out;
  if (root.contains("points")) out.num_points = r.index(root["points"], "points");
  if (root.contains("elements")) out.num_elements = r.index(root["elements"], "elements");
  if (!root.contains("edits") && !root.contains("rules"))
    r.fail(ErrorCode::kParse, "the file has neither \"edits\" nor \"rules\"");
  if (root.contains("edits")) {
    const Json& edits = r.array(root["edits"], "edits");
    for (size_t i = 0; i < edits.size(); ++i)
      out.edits.push_back(read_set_edit(r, edits[i], JsonReader::at("edits", i)));
  }
  if (root.contains("rules")) {
    const Json& rules = r.array(root["rules"], "rules");
    for (size_t i = 0; i < rules.size(); ++i) {
      const std::string path = JsonReader::at("rules", i);
      const Json& j = rules[i];
      if (!j.is_object())
        r.fail(ErrorCode::kParse, path + " should be an object, not " + JsonReader::show(j));
      SetEditRule rule;
      const std::string mode = r.string(r.field(j, path, "mode"), path + ".mode");
      if (!parse_set_edit_mode(mode, rule.mode))
        r.fail(ErrorCode::kParse, path + ".mode is \"" + mode + "\"; expected remove, add, only or reset");
      rule.points = r.indices(r.field(j, path, "points"), path + ".points");
      if (rule.mode != SetEditMode::kReset || j.contains("faces"))
        rule.faces = r.indices(r.field(j, path, "faces"), path + ".faces");
      if (j.contains("mirror")) {
        rule.mirror_tolerance = r.number(j["mirror"], path + ".mirror");
        if (!(rule.mirror_tolerance > 0))
          r.fail(ErrorCode::kParse, path + ".mirror should be a tolerance > 0 (scene units), not " +
                                        JsonReader::show(j["mirror"]));
      }
      out.rules.push_back(std::move(rule));
    }
  }
  return out;
}

}  // namespace

Result<SetEditsFile> load_set_edits(const std::string& path) {
  auto root = read_json_file(path);
  if (!root) return root.error();
  try {
    return read_file(JsonReader(path), *root);
  } catch (const JsonLoadFailure& f) {
    return f.error;
  }
}

Result<std::vector<SetEdit>> resolve_sample_edits(const SetEditsFile& file, const std::string& path, size_t num_points,
                                                  size_t num_samples) {
  if (!file.rules.empty())
    return make_error(ErrorCode::kInvalidArgument, path + ": rules by cage faces do not apply to a parametric driver: give per-point "
                                                          "edits of its samples");
  if ((file.num_points >= 0 && size_t(file.num_points) != num_points) || (file.num_elements >= 0 && size_t(file.num_elements) != num_samples))
    return make_error(ErrorCode::kTopologyMismatch, path + ": made for " + std::to_string(file.num_points) + " points and " +
                                                        std::to_string(file.num_elements) + " elements; the skin has " +
                                                        std::to_string(num_points) + " points and the driver " +
                                                        std::to_string(num_samples) + " samples");
  for (const SetEdit& e : file.edits) {
    if (e.point >= num_points)
      return make_error(ErrorCode::kIndexOutOfRange, path + ": the edit of skin point " + std::to_string(e.point) +
                                                         " names a point past the skin (" + std::to_string(num_points) + " points)");
    for (const auto* list : {&e.exclude, &e.include})
      for (uint32_t k : *list)
        if (k >= num_samples)
          return make_error(ErrorCode::kIndexOutOfRange, path + ": the edit of skin point " + std::to_string(e.point) + " names sample " +
                                                             std::to_string(k) + " (the skin has " + std::to_string(num_points) +
                                                             " points, the driver " + std::to_string(num_samples) + " samples)");
  }
  return canonical_set_edits(file.edits);
}

Result<ResolvedSetEdits> resolve_set_edits(const SetEditsFile& file, const std::string& path,
                                           std::span<const glm::vec3> skin_rest, const Cage& cage) {
  const size_t np = skin_rest.size(), ne = cage.num_elements(), nf = cage.polygons.num_faces();
  auto fail = [&](ErrorCode code, const std::string& what) { return make_error(code, path + ": " + what); };
  if (file.num_points >= 0 && size_t(file.num_points) != np)
    return fail(ErrorCode::kTopologyMismatch, "made for a skin of " + std::to_string(file.num_points) +
                                                  " points, but this skin has " + std::to_string(np));
  if (file.num_elements >= 0 && size_t(file.num_elements) != ne)
    return fail(ErrorCode::kTopologyMismatch, "made for a cage of " + std::to_string(file.num_elements) +
                                                  " elements (triangles), but this cage has " +
                                                  std::to_string(ne));
  auto check_list = [&](std::span<const uint32_t> list, const std::string& list_path, size_t limit,
                        const char* what, const char* owner) -> Status {
    for (size_t k = 0; k < list.size(); ++k)
      if (list[k] >= limit)
        return fail(ErrorCode::kIndexOutOfRange, JsonReader::at(list_path, k) + " is " + what + " " +
                                                     std::to_string(list[k]) + ", but the " + owner +
                                                     " has " + std::to_string(limit) + " " + what + "s");
    return Ok{};
  };
  for (size_t i = 0; i < file.edits.size(); ++i) {
    const SetEdit& e = file.edits[i];
    const std::string p = JsonReader::at("edits", i);
    if (e.point >= np)
      return fail(ErrorCode::kIndexOutOfRange, p + ".point is skin point " + std::to_string(e.point) +
                                                   ", but the skin has " + std::to_string(np) + " points");
    if (auto s = check_list(e.exclude, p + ".exclude", ne, "element", "cage"); !s) return s.error();
    if (auto s = check_list(e.include, p + ".include", ne, "element", "cage"); !s) return s.error();
  }
  ResolvedSetEdits out;
  out.edits = canonical_set_edits(file.edits);
  const std::vector<glm::vec3> centroids = face_centroids(cage.polygons);
  for (size_t i = 0; i < file.rules.size(); ++i) {
    const SetEditRule& rule = file.rules[i];
    const std::string p = JsonReader::at("rules", i);
    if (auto s = check_list(rule.points, p + ".points", np, "point", "skin"); !s) return s.error();
    if (auto s = check_list(rule.faces, p + ".faces", nf, "face", "cage"); !s) return s.error();
    MirrorMap point_map, face_map;
    SetEditMirror mirror;
    if (rule.mirror_tolerance > 0) {
      point_map = MirrorMap(skin_rest, rule.mirror_tolerance);
      face_map = MirrorMap(centroids, rule.mirror_tolerance);
      mirror = {&point_map, &face_map};
    }
    auto r =
        apply_set_edit(out.edits, rule.mode, IndexSet(rule.points), IndexSet(rule.faces), cage, np, mirror);
    if (!r) return fail(r.error().code, p + ": " + r.error().message);
    out.edits = std::move(r->edits);
    if (!r->unmatched_points.empty() || !r->unmatched_faces.empty())
      out.warnings.push_back(path + ": " + p + ": " + std::to_string(r->unmatched_points.size()) +
                             " points and " + std::to_string(r->unmatched_faces.size()) +
                             " faces have no mirror counterpart within " +
                             std::to_string(rule.mirror_tolerance));
  }
  return out;
}

Status save_set_edits(const std::string& path, std::span<const SetEdit> edits, size_t num_points,
                      size_t num_elements) {
  const std::vector<SetEdit> canonical = canonical_set_edits(edits);
  std::string s = "{\n";
  s += "  \"format\": \"" + std::string(kSetEditsFormat) + "\",\n";
  s += "  \"version\": " + std::to_string(kSetEditsVersion) + ",\n";
  s += "  \"points\": " + std::to_string(num_points) + ",\n";
  s += "  \"elements\": " + std::to_string(num_elements) + ",\n";
  s += "  \"edits\": [";
  for (size_t i = 0; i < canonical.size(); ++i)
    s += std::string(i ? "," : "") + "\n    " + set_edit_json(canonical[i]);
  s += canonical.empty() ? "]\n}\n" : "\n  ]\n}\n";
  return write_file_atomic(path, s);
}

}  // namespace cagewrap
