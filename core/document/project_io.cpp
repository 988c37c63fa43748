#include "core/document/project_io.h"

#include <bit>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/base/atomic_write.h"
#include "core/base/base64.h"
#include "core/document/binding_cache.h"
#include "core/base/file_hash.h"
#include "core/io/gltf_loader.h"
#include "core/base/json_reader.h"
#include "core/io/patch_io.h"
#include "core/io/set_edits_io.h"
#include "core/deform/set_editing.h"
#include "core/deform/patch_binding.h"

namespace cagewrap {

namespace fs = std::filesystem;

namespace {

const char* const kKnownFields[] = {"format",     "version",  "recovery",      "character",
                                    "cage",       "binding",  "set_edits",     "attachment",
                                    "keyposes",   "extensions", "binding_cache", "simulation",
                                    "patch_driver", "more_drivers", "deformers", "deformer_stack"};

// The members of "binding_cache.inputs", in the order they are written.
const std::pair<const char*, std::string BindingInputs::*> kInputFields[] = {
    {"program", &BindingInputs::program},     {"character", &BindingInputs::character},
    {"cage", &BindingInputs::cage},           {"binding", &BindingInputs::params},
    {"set_edits", &BindingInputs::set_edits}, {"attachment", &BindingInputs::attachment},
};

bool known_field(const std::string& key) {
  for (const char* k : kKnownFields)
    if (key == k) return true;
  return false;
}

// ------------------------------------------------------------------ writing

// The double nearest to the shortest decimal that reads back as `f` (core/base/json_reader.h).
double short_float(float f) { return json_short_float(f); }

std::string number(double x) { return Json(x).dump(); }

// {"a": 1, "b": "x"}: one line, spaced like the rest of the file.
std::string one_line(const Json& object) {
  std::string s = "{";
  for (const auto& [key, value] : object.items()) s += (s.size() > 1 ? ", " : "") + Json(key).dump() + ": " + value.dump();
  return s + "}";
}

// A path as the project records it (the character, the binding cache): relative to the project's
// folder, '/' separated.
std::string relative_path(const std::string& project_path, const std::string& file) {
  fs::path project_dir = fs::absolute(project_path).lexically_normal().parent_path();
  fs::path target = fs::absolute(file).lexically_normal();
  fs::path rel = target.lexically_relative(project_dir);
  return (rel.empty() ? target : rel).generic_string();
}

std::string vec3_text(const glm::vec3& v) {
  std::string s(1, '[');
  s += number(short_float(v.x));
  s += ", ";
  s += number(short_float(v.y));
  s += ", ";
  s += number(short_float(v.z));
  s += ']';
  return s;
}

// A node as the file names it: its name when that is unique and not empty, else its index.
Json node_ref(const Document& doc, uint32_t node) {
  if (doc.character && node < doc.character->skeleton.size()) {
    const Skeleton& sk = doc.character->skeleton;
    const std::string& name = sk.node(node).name;
    if (!name.empty() && sk.find(name) == static_cast<int32_t>(node)) {
      bool unique = true;
      for (size_t i = node + 1; i < sk.size() && unique; ++i) unique = sk.node(i).name != name;
      if (unique) return Json(name);
    }
  }
  return Json(node);
}

// "attachment": `a` (the document's, a layer's or a parametric driver's, whose "vertex" is a control point).
std::string attachment_text(const Document& doc, const AttachmentSettings& a) {
  std::string s = "  \"attachment\": {\"mode\": " + Json(attachment_mode_name(a.mode)).dump() +
                  ", \"smooth_width\": " + number(a.smooth_width) + ", \"overrides\": [";
  for (size_t i = 0; i < a.overrides.size(); ++i)
    s += std::string(i ? "," : "") + "\n    {\"vertex\": " + std::to_string(a.overrides[i].vertex) +
         ", \"node\": " + node_ref(doc, a.overrides[i].node).dump() + "}";
  s += a.overrides.empty() ? "]},\n" : "\n  ]},\n";
  return s;
}
std::string attachment_text(const Document& doc) { return attachment_text(doc, doc.attachment); }

// "keyposes": `sets` (the document's own, a layer's or the parametric driver's).
std::string keyposes_text(const Document& doc, std::span<const KeyposeSet> sets) {
  std::string s = "  \"keyposes\": [";
  for (size_t i = 0; i < sets.size(); ++i) {
    const KeyposeSet& k = sets[i];
    s += std::string(i ? "," : "") + "\n    {\"name\": " + Json(k.name).dump() + ",\n     \"drivers\": [";
    for (size_t d = 0; d < k.drivers.size(); ++d) {
      const JointDriver& dr = k.drivers[d];
      s += std::string(d ? ", " : "") + "{\"node\": " + node_ref(doc, dr.node).dump() + ", \"kind\": " +
           Json(driver_kind_name(dr.kind)).dump() + ", \"axis\": " + vec3_text(dr.axis) + "}";
    }
    s += "],\n     \"interpolation\": " + Json(key_interpolation_name(k.interpolation)).dump() +
         ", \"kernel\": " + Json(rbf_kernel_name(k.kernel)).dump() +
         ", \"rbf_width\": " + number(k.rbf_width) + ", \"rest_key\": " + (k.rest_key ? "true" : "false") +
         ", \"mute\": " + (k.mute ? "true" : "false") + ", \"solo\": " + (k.solo ? "true" : "false") +
         ",\n     \"keys\": [";
    for (size_t j = 0; j < k.keys.size(); ++j) {
      const KeyposeKey& key = k.keys[j];
      s += std::string(j ? "," : "") + "\n      {\"values\": [";
      for (size_t d = 0; d < key.values.size(); ++d) s += std::string(d ? ", " : "") + number(key.values[d]);
      s += "], \"vertices\": " + json_index_list(key.vertices) + ",\n       \"offsets\": [";
      for (size_t e = 0; e < key.offsets.size(); ++e)
        s += std::string(e ? ", " : "") + vec3_text(key.offsets[e]);
      s += "]}";
    }
    s += k.keys.empty() ? "]}" : "\n     ]}";
  }
  s += sets.empty() ? "],\n" : "\n  ],\n";
  return s;
}

// "simulation" (only when the settings differ from the defaults, so older files stay as they were).
std::string simulation_text(const Document& doc) {
  const SimSettings& sim = doc.sim;
  if (sim == SimSettings{}) return "";
  const SimParams& p = sim.params;
  Json params = {{"enabled", sim.enabled},
                 {"frame_rate", p.frame_rate},
                 {"substeps", p.substeps},
                 {"iterations", p.iterations},
                 {"gravity", {p.gravity.x, p.gravity.y, p.gravity.z}},
                 {"damping", p.damping},
                 {"goal_frequency", p.goal_frequency},
                 {"edges", p.edges},
                 {"edge_compliance", p.edge_compliance},
                 {"collision_margin", p.collision_margin},
                 {"skeleton_colliders", p.skeleton_colliders},
                 {"skeleton_radius_scale", p.skeleton_radius_scale},
                 {"preroll", p.preroll}};
  std::string s = "  \"simulation\": " + one_line(params);
  s.pop_back();  // the closing brace: the per-vertex weights and colliders follow
  if (!sim.vertices.empty()) {
    std::string pinned, mass, stiffness;
    for (size_t v = 0; v < sim.vertices.size(); ++v) {
      const char* sep = v ? ", " : "";
      pinned += sep + std::string(sim.vertices[v].pinned ? "1" : "0");
      mass += sep + number(short_float(sim.vertices[v].mass));
      stiffness += sep + number(short_float(sim.vertices[v].stiffness));
    }
    s += ",\n    \"pinned\": [" + pinned + "],\n    \"mass\": [" + mass + "],\n    \"stiffness\": [" + stiffness + "]";
  }
  s += ",\n    \"colliders\": [";
  for (size_t c = 0; c < sim.colliders.size(); ++c) {
    const Collider& k = sim.colliders[c];
    Json j = {{"name", k.name},
              {"kind", collider_kind_name(k.kind)},
              {"a", {k.a.x, k.a.y, k.a.z}},
              {"b", {k.b.x, k.b.y, k.b.z}},
              {"radius", k.radius}};
    if (k.node >= 0) j["node"] = node_ref(doc, static_cast<uint32_t>(k.node));
    s += std::string(c ? "," : "") + "\n      " + one_line(j);
  }
  s += sim.colliders.empty() ? "]},\n" : "\n    ]},\n";
  return s;
}

// "binding": every binding parameter.
Json binding_json(const BindParams& p) {
  return {{"variant", variant_name(p.variant)}, {"local", p.local},
          {"epsilon", p.epsilon},               {"max_elements", p.max_elements},
          {"scale", p.scale},                   {"max_distance", p.max_distance},
          {"close_distance", p.close_distance}, {"separate", p.separate},
          {"separation_steps", p.separation_steps}};
}

// "mask": a deformer's skin mask, 16 weights a line; `what` names the deformer in errors.
Result<std::string> mask_text(const std::string& path, const std::string& what, const std::vector<float>& mask) {
  std::string s = "  \"mask\": [";
  for (size_t p = 0; p < mask.size(); ++p) {
    const float w = mask[p];
    if (!(w >= 0.0f && w <= 1.0f))
      return make_error(ErrorCode::kInvalidArgument, path + ": not saved: " + what + ": mask weight of skin vertex " +
                                                         std::to_string(p) + " is not in [0, 1]");
    s += std::string(p ? "," : "") + (p % 16 == 0 ? "\n    " : " ") + number(short_float(w));
  }
  return s + "\n  ],\n";
}

// "binding_cache": the record (its file relative to the project's folder), or {} when caching is on
// and nothing is cached.
std::string binding_cache_text(const std::string& path, const BindingCacheRecord& record) {
  if (record.file.empty()) return "  \"binding_cache\": {},\n";
  Json inputs = Json::object();
  for (const auto& [key, member] : kInputFields) inputs[key] = record.inputs.*member;
  std::string s = "  \"binding_cache\": {\"file\": " + Json(relative_path(path, record.file)).dump() +
                  ", \"hash\": " + Json(record.file_hash).dump() + ",\n    \"inputs\": " + one_line(inputs) + "},\n";
  return s;
}

// A parametric driver's object ("{...}"): the rest grids in the .cwpatch layout, the density, whether it
// drives the skin and the posed control points, grid by grid; then its name, place in the stack, mask,
// binding and keyposes (DriverPlacement) when they are not the defaults. ("{...}"); `who` names it in messages ("the parametric driver", "parametric driver 'x'").
Result<std::string> driver_object_text(const std::string& path, const Document& doc, const PatchDriver& d,
                                       const DriverPlacement& place, const std::string& who, const BindingCacheRecord* cache) {
  if (auto v = validate_patch_surface(d.rest, who); !v)
    return make_error(v.error().code, path + ": not saved: " + v.error().message);
  if (d.posed.num_control_points() != d.rest.num_control_points())
    return make_error(ErrorCode::kTopologyMismatch, path + ": not saved: the parametric driver has " +
                                                        std::to_string(d.posed.num_control_points()) +
                                                        " posed control points for " +
                                                        std::to_string(d.rest.num_control_points()) + " at rest");
  if (auto v = validate_patch_surface(d.posed, who + " (posed)"); !v)
    return make_error(v.error().code, path + ": not saved: " + v.error().message);
  std::string s = "{\"density\": " + std::to_string(d.density) +
                  ", \"drive_skin\": " + (d.drive_skin ? "true" : "false") +
                  ",\n    \"rest\": " + patch_surface_json(d.rest).dump() + ",\n    \"posed\": [";
  const std::vector<glm::dvec3> posed = d.posed.control_points();
  for (size_t k = 0; k < posed.size(); ++k)
    s += std::string(k ? ", " : "") + Json::array({posed[k].x, posed[k].y, posed[k].z}).dump();
  s += "]";
  if (!place.name.empty()) s += ",\n    \"name\": " + Json(place.name).dump();
  if (place.hidden) s += ",\n    \"hidden\": true";
  if (place.after >= 0) s += ",\n    \"after\": " + std::to_string(place.after);
  if (!place.mask_source.empty()) s += ",\n    \"mask_source\": " + Json(place.mask_source).dump();
  if (place.mask) {
    auto m = mask_text(path, who, *place.mask);
    if (!m) return m.error();
    s += ",\n" + m->substr(0, m->size() - 2);  // without its ",\n"
  }
  for (const KeyposeSet& k : place.keyposes)
    if (auto v = validate_keypose_set(k, doc.character ? doc.character->skeleton.size() : SIZE_MAX, posed.size()); !v)
      return make_error(v.error().code, path + ": not saved: " + who + "'s " + v.error().message);
  if (place.params) {
    if (auto v = validate(*place.params); !v)
      return make_error(ErrorCode::kInvalidArgument, path + ": not saved: " + who + "'s binding: " + v.error().message);
    s += ",\n    \"binding\": " + one_line(binding_json(*place.params));
  }
  if (place.attachment) {
    if (place.attachment->mode == AttachmentMode::kFitted || !std::isfinite(place.attachment->smooth_width) ||
        place.attachment->smooth_width <= 0)
      return make_error(ErrorCode::kInvalidArgument, path + ": not saved: " + who + "'s attachment is rigid, smooth or skin_weights, "
                                                         "with a positive smooth width");
    for (const AttachmentOverride& o : place.attachment->overrides)
      if (o.vertex >= posed.size())
        return make_error(ErrorCode::kIndexOutOfRange, path + ": not saved: " + who + "'s attachment names control point " +
                                                           std::to_string(o.vertex) + " of " + std::to_string(posed.size()));
    const std::string a = attachment_text(doc, *place.attachment);
    s += ",\n" + a.substr(0, a.size() - 2);
  }
  if (!place.set_edits.empty()) {
    const size_t samples = patch_sample_count(d.rest, d.density);
    const size_t points = doc.character ? doc.character->num_vertices() : SIZE_MAX;
    s += ",\n    \"set_edits\": [";
    for (size_t i = 0; i < place.set_edits.size(); ++i) {
      const SetEdit& e = place.set_edits[i];
      bool in_range = e.point < points;
      for (const auto* list : {&e.exclude, &e.include})
        for (uint32_t k : *list) in_range = in_range && k < samples;
      if (!in_range)
        return make_error(ErrorCode::kIndexOutOfRange, path + ": not saved: " + who + "'s set edit of skin point " + std::to_string(e.point) +
                                                           " names a point or sample out of range (" + std::to_string(samples) + " samples)");
      s += std::string(i ? "," : "") + "\n      " + set_edit_json(e);
    }
    s += "\n    ]";
  }
  if (!place.keyposes.empty()) {
    const std::string k = keyposes_text(doc, place.keyposes);
    s += ",\n" + k.substr(0, k.size() - 2);
  }
  if (cache) {
    const std::string c = binding_cache_text(path, *cache);
    s += ",\n  " + c.substr(0, c.size() - 2);
  }
  return s + "}";
}

// "patch_driver" (the first) and "more_drivers" (the others), only when the document has them.
// `caches`: each driver's binding cache record to write (null: caching is off).
Result<std::string> patch_driver_text(const std::string& path, const Document& doc, const std::vector<BindingCacheRecord>* caches) {
  if (!doc.patch_driver) return std::string();
  auto cache = [caches](size_t i) { return caches && i < caches->size() ? &(*caches)[i] : nullptr; };
  auto first = driver_object_text(path, doc, *doc.patch_driver, doc.driver_place, "the parametric driver", cache(0));
  if (!first) return first.error();
  std::string s = "  \"patch_driver\": " + *first + ",\n";
  if (doc.more_drivers.empty()) return s;
  s += "  \"more_drivers\": [";
  for (size_t i = 0; i < doc.more_drivers.size(); ++i) {
    auto o = driver_object_text(path, doc, *doc.more_drivers[i].driver, doc.more_drivers[i].place,
                                "parametric driver '" + driver_name(doc, i + 1) + "'", cache(i + 1));
    if (!o) return o.error();
    s += std::string(i ? ",\n    " : "\n    ") + *o;
  }
  return s + "\n  ],\n";
}

// What the document's own cage and every layer hold, each field a line ending in ",\n": the cage
// (positions, faces, offsets), "binding", "set_edits", "attachment", "keyposes", "simulation".
Result<std::string> deformer_fields_text(const std::string& path, const Document& doc) {
  std::string s = "  \"cage\": {\n    \"positions\": [";
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
  if (!std::isfinite(doc.attachment.smooth_width) || doc.attachment.smooth_width <= 0)
    return make_error(ErrorCode::kInvalidArgument,
                      path + ": not saved: the attachment's smooth width must be a positive number");
  const size_t num_nodes = doc.character ? doc.character->skeleton.size() : SIZE_MAX;
  for (const KeyposeSet& k : doc.keyposes)
    if (auto v = validate_keypose_set(k, num_nodes, positions.size()); !v)
      return make_error(v.error().code, path + ": not saved: " + v.error().message);
  s += "  \"binding\": " + one_line(binding_json(doc.params)) + ",\n";
  s += "  \"set_edits\": [";
  for (size_t i = 0; i < doc.set_edits.size(); ++i) {
    s += std::string(i ? "," : "") + "\n    " + set_edit_json(doc.set_edits[i]);
  }
  s += doc.set_edits.empty() ? "],\n" : "\n  ],\n";
  s += attachment_text(doc);
  s += keyposes_text(doc, doc.keyposes);
  if (auto v = validate_sim_settings(doc.sim, positions.size(), num_nodes); !v)
    return make_error(v.error().code, path + ": not saved: " + v.error().message);
  s += simulation_text(doc);
  return s;
}

// "deformers" and "deformer_stack" (only when the document has layers, so older files stay as they
// were): each layer is an object of the same fields as the document's own cage, and its name, mask and mute.
// `caches`: each layer's binding cache record to write (null: caching is off).
Result<std::string> layers_text(const std::string& path, const Document& doc, const std::vector<BindingCacheRecord>* caches) {
  if (doc.layers.empty() && doc.stack == DeformerStack{}) return std::string();
  std::string s;
  if (!doc.layers.empty()) s += "  \"deformers\": [";
  for (size_t i = 0; i < doc.layers.size(); ++i) {
    const DeformerLayer& l = doc.layers[i];
    auto fields = deformer_fields_text(path, layer_document(doc, i));
    if (!fields) return make_error(fields.error().code, fields.error().message + " (deformer '" + l.name + "')");
    s += std::string(i ? "," : "") + "\n  {\n" + *fields;
    if (l.mask) {
      auto m = mask_text(path, "deformer '" + l.name + "'", *l.mask);
      if (!m) return m.error();
      s += *m;
    }
    if (caches && i < caches->size()) s += binding_cache_text(path, (*caches)[i]);
    Json tail = {{"name", l.name}, {"muted", l.muted}};
    if (l.hidden) tail["hidden"] = true;
    if (!l.mask_source.empty()) tail["mask_source"] = l.mask_source;
    const std::string t = one_line(tail);
    s += "  " + t.substr(1, t.size() - 2) + "\n  }";
  }
  if (!doc.layers.empty()) s += "\n  ],\n";
  if (!(doc.stack.exponent >= 0.0) || !std::isfinite(doc.stack.exponent))
    return make_error(ErrorCode::kInvalidArgument, path + ": not saved: the deformer stack's exponent must be a number >= 0");
  if (doc.stack.solo >= 0 && static_cast<size_t>(doc.stack.solo) >= deformer_count(doc))
    return make_error(ErrorCode::kInvalidArgument, path + ": not saved: the soloed deformer " + std::to_string(doc.stack.solo) +
                                                       " does not exist (the deformers are 0 to " + std::to_string(doc.layers.size()) + ")");
  Json stack = {{"mode", stack_mode_name(doc.stack.mode)}, {"exponent", doc.stack.exponent}};
  if (doc.stack.base_muted) stack["base_muted"] = true;
  if (doc.stack.base_hidden) stack["base_hidden"] = true;
  if (doc.stack.solo >= 0) stack["solo"] = doc.stack.solo;
  if (!doc.stack.solo_driver.empty()) {
    if (!soloed_driver(doc))
      return make_error(ErrorCode::kInvalidArgument, path + ": not saved: the soloed parametric driver '" + doc.stack.solo_driver +
                                                         "' does not exist");
    stack["solo_driver"] = doc.stack.solo_driver;
  }
  s += "  \"deformer_stack\": " + one_line(stack) + ",\n";
  return s;
}

// The binding cache records a project writes: the document's cage's, each layer's, each driver's.
struct CacheRecords {
  BindingCacheRecord cage;
  std::vector<BindingCacheRecord> layers, drivers;
};

// `caches`: the records to write (null: caching is off).
Result<std::string> project_text(const std::string& path, const Document& doc, const CacheRecords* caches,
                                 const std::optional<RecoveryInfo>& recovery) {
  Json preserved = Json::object();
  if (!doc.preserved_fields.empty()) {
    preserved = Json::parse(doc.preserved_fields, nullptr, false);
    if (!preserved.is_object())
      return make_error(ErrorCode::kInvalidArgument, path + ": the document's preserved fields are not a JSON object");
  }
  std::string s = "{\n";
  s += "  \"format\": " + Json(kProjectFormat).dump() + ",\n";
  // the oldest version that holds the document: older builds still open what needs nothing newer
  // (4: deformer layers, which an older build would drop; 3: an embedded character)
  s += "  \"version\": " + std::to_string(!doc.layers.empty() ? 4 : doc.embedded_character ? 3 : 2) + ",\n";
  if (recovery) {
    Json r = {{"project", recovery->project}, {"pid", recovery->pid}};
    s += "  \"recovery\": " + one_line(r) + ",\n";
  }
  Json character = {{"path", relative_path(path, doc.character_path)}, {"hash", doc.character_hash}};
  if (doc.character_keep_units) character["keep_units"] = true;
  if (doc.embedded_character) character["embedded"] = base64_encode(*doc.embedded_character);
  s += "  \"character\": " + one_line(character) + ",\n";
  auto fields = deformer_fields_text(path, doc);
  if (!fields) return fields.error();
  s += *fields;
  auto layers = layers_text(path, doc, caches ? &caches->layers : nullptr);
  if (!layers) return layers.error();
  s += *layers;
  auto patch = patch_driver_text(path, doc, caches ? &caches->drivers : nullptr);
  if (!patch) return patch.error();
  s += *patch;
  if (caches) s += binding_cache_text(path, caches->cage);
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

void warn_unknown(const Json& object, const std::string& path, std::initializer_list<const char*> known,
                  std::vector<std::string>& warnings, const std::string& file) {
  for (const auto& [key, value] : object.items()) {
    bool found = false;
    for (const char* k : known) found = found || key == k;
    if (!found)
      warnings.push_back(file + ": " + Reader::join(path, key.c_str()) +
                         " is not known to this build and was ignored");
  }
}

bool boolean(const Reader& r, const Json& j, const std::string& path) {
  if (!j.is_boolean()) r.fail(ErrorCode::kParse, path + " should be true or false, not " + Reader::show(j));
  return j.get<bool>();
}

glm::vec3 read_vec3(const Reader& r, const Json& j, const std::string& path) {
  if (!j.is_array() || j.size() != 3)
    r.fail(ErrorCode::kParse, path + " should be [x, y, z], not " + Reader::show(j));
  return {r.finite_float(j[0], path + "[0]"), r.finite_float(j[1], path + "[1]"),
          r.finite_float(j[2], path + "[2]")};
}

// A node named (a string) or numbered (an index) in the character's skeleton.
uint32_t read_node(const Reader& r, const Json& j, const std::string& path, const Skeleton& skeleton) {
  if (j.is_string()) {
    int32_t n = skeleton.find(j.get<std::string>());
    if (n < 0)
      r.fail(ErrorCode::kInvalidArgument,
             path + " is node '" + j.get<std::string>() + "', but the character has no node of that name");
    return static_cast<uint32_t>(n);
  }
  uint32_t n = r.index(j, path);
  if (n >= skeleton.size())
    r.fail(ErrorCode::kIndexOutOfRange, path + " is node " + std::to_string(n) + ", but the character has " +
                                            std::to_string(skeleton.size()) + " nodes");
  return n;
}

AttachmentSettings read_attachment(const Reader& r, const Json& a, const Character& character,
                                   size_t num_vertices, std::vector<std::string>& warnings,
                                   const std::string& file) {
  if (!a.is_object()) r.fail(ErrorCode::kParse, "attachment should be an object, not " + Reader::show(a));
  AttachmentSettings out;
  out.mode = AttachmentMode::kRigid;  // the only mode of the first files: leaving it out means rigid
  if (a.contains("mode")) {
    std::string mode = r.string(a["mode"], "attachment.mode");
    if (!parse_attachment_mode(mode, out.mode))
      r.fail(ErrorCode::kParse, "attachment.mode is '" + mode + "'; expected rigid, smooth, skin_weights or fitted");
  }
  if (a.contains("smooth_width")) {
    out.smooth_width = r.number(a["smooth_width"], "attachment.smooth_width");
    if (out.smooth_width <= 0) r.fail(ErrorCode::kInvalidArgument, "attachment.smooth_width must be > 0");
  }
  std::vector<int32_t> joint_of(character.skeleton.size(), -1);
  if (!character.skins.empty())
    for (size_t j = 0; j < character.skins[0].joints.size(); ++j)
      if (character.skins[0].joints[j] < joint_of.size())
        joint_of[character.skins[0].joints[j]] = static_cast<int32_t>(j);
  if (a.contains("overrides")) {
    const Json& list = r.array(a["overrides"], "attachment.overrides");
    std::vector<int32_t> per_vertex(num_vertices, -1);
    for (size_t i = 0; i < list.size(); ++i) {
      std::string path = Reader::at("attachment.overrides", i);
      const Json& o = list[i];
      if (!o.is_object()) r.fail(ErrorCode::kParse, path + " should be an object, not " + Reader::show(o));
      uint32_t v = r.index(r.field(o, path, "vertex"), path + ".vertex");
      if (v >= num_vertices)
        r.fail(ErrorCode::kIndexOutOfRange, path + ".vertex is " + std::to_string(v) + ", but the cage has " +
                                                std::to_string(num_vertices) + " vertices");
      uint32_t node = read_node(r, r.field(o, path, "node"), path + ".node", character.skeleton);
      if (!character.skins.empty() && joint_of[node] < 0)
        r.fail(ErrorCode::kInvalidArgument,
               path + ".node '" + character.skeleton.node(node).name +
                   "' is not a joint of the character's skin; a cage vertex can follow joints only");
      if (per_vertex[v] >= 0)
        r.fail(ErrorCode::kInvalidArgument,
               path + " assigns cage vertex " + std::to_string(v) + " a second time");
      per_vertex[v] = static_cast<int32_t>(node);
      warn_unknown(o, path, {"vertex", "node"}, warnings, file);
    }
    out = with_overrides_per_vertex(out, per_vertex);
  }
  warn_unknown(a, "attachment", {"mode", "smooth_width", "overrides"}, warnings, file);
  return out;
}

glm::dvec3 read_dvec3(const Reader& r, const Json& j, const std::string& path) {
  if (!j.is_array() || j.size() != 3)
    r.fail(ErrorCode::kParse, path + " should be [x, y, z], not " + Reader::show(j));
  return {r.number(j[0], path + "[0]"), r.number(j[1], path + "[1]"), r.number(j[2], path + "[2]")};
}

// "simulation": every field optional (the default when absent); checked by validate_sim_settings.
SimSettings read_simulation(const Reader& r, const Json& j, const Character& character, size_t num_vertices,
                            std::vector<std::string>& warnings, const std::string& file) {
  if (!j.is_object()) r.fail(ErrorCode::kParse, "simulation should be an object, not " + Reader::show(j));
  SimSettings out;
  SimParams& p = out.params;
  auto number = [&](const char* key, double& x) {
    if (j.contains(key)) x = r.number(j[key], Reader::join("simulation", key));
  };
  auto whole = [&](const char* key, int& x) {
    if (j.contains(key)) x = static_cast<int>(std::min<uint32_t>(r.index(j[key], Reader::join("simulation", key)), 1000000));
  };
  auto flag = [&](const char* key, bool& x) {
    if (j.contains(key)) x = r.boolean(j[key], Reader::join("simulation", key));
  };
  flag("enabled", out.enabled);
  number("frame_rate", p.frame_rate);
  whole("substeps", p.substeps);
  whole("iterations", p.iterations);
  if (j.contains("gravity")) p.gravity = read_dvec3(r, j["gravity"], "simulation.gravity");
  number("damping", p.damping);
  number("goal_frequency", p.goal_frequency);
  flag("edges", p.edges);
  number("edge_compliance", p.edge_compliance);
  number("collision_margin", p.collision_margin);
  flag("skeleton_colliders", p.skeleton_colliders);
  number("skeleton_radius_scale", p.skeleton_radius_scale);
  number("preroll", p.preroll);
  if (j.contains("pinned") || j.contains("mass") || j.contains("stiffness")) {
    const Json& pinned = r.array(r.field(j, "simulation", "pinned"), "simulation.pinned");
    const Json& mass = r.array(r.field(j, "simulation", "mass"), "simulation.mass");
    const Json& stiffness = r.array(r.field(j, "simulation", "stiffness"), "simulation.stiffness");
    for (const auto& [name, list] : {std::pair{"pinned", &pinned}, {"mass", &mass}, {"stiffness", &stiffness}})
      if (list->size() != num_vertices)
        r.fail(ErrorCode::kTopologyMismatch, std::string("simulation.") + name + " has " + std::to_string(list->size()) +
                                                 " entries but the cage has " + std::to_string(num_vertices) +
                                                 " vertices");
    out.vertices.resize(num_vertices);
    for (size_t v = 0; v < num_vertices; ++v) {
      const uint32_t pin = r.index(pinned[v], Reader::at("simulation.pinned", v));
      if (pin > 1) r.fail(ErrorCode::kParse, Reader::at("simulation.pinned", v) + " should be 0 or 1");
      out.vertices[v] = {pin == 1, r.finite_float(mass[v], Reader::at("simulation.mass", v)),
                         r.finite_float(stiffness[v], Reader::at("simulation.stiffness", v))};
    }
  }
  if (j.contains("colliders")) {
    const Json& list = r.array(j["colliders"], "simulation.colliders");
    for (size_t c = 0; c < list.size(); ++c) {
      const std::string path = Reader::at("simulation.colliders", c);
      const Json& k = list[c];
      if (!k.is_object()) r.fail(ErrorCode::kParse, path + " should be an object, not " + Reader::show(k));
      Collider col;
      if (k.contains("name")) col.name = r.string(k["name"], Reader::join(path, "name"));
      const std::string kind = r.string(r.field(k, path, "kind"), Reader::join(path, "kind"));
      if (!parse_collider_kind(kind, col.kind))
        r.fail(ErrorCode::kParse, Reader::join(path, "kind") + " is '" + kind + "'; expected plane, sphere or capsule");
      col.a = read_dvec3(r, r.field(k, path, "a"), Reader::join(path, "a"));
      if (k.contains("b")) col.b = read_dvec3(r, k["b"], Reader::join(path, "b"));
      if (k.contains("radius")) col.radius = r.number(k["radius"], Reader::join(path, "radius"));
      if (k.contains("node")) col.node = static_cast<int32_t>(read_node(r, k["node"], Reader::join(path, "node"), character.skeleton));
      warn_unknown(k, path, {"name", "kind", "a", "b", "radius", "node"}, warnings, file);
      out.colliders.push_back(std::move(col));
    }
  }
  warn_unknown(j, "simulation",
               {"enabled", "frame_rate", "substeps", "iterations", "gravity", "damping", "goal_frequency", "edges",
                "edge_compliance", "collision_margin", "skeleton_colliders", "skeleton_radius_scale", "preroll",
                "pinned", "mass", "stiffness", "colliders"},
               warnings, file);
  if (auto v = validate_sim_settings(out, num_vertices, character.skeleton.size()); !v)
    r.fail(v.error().code, v.error().message);
  return out;
}

// "patch_driver": checked like a .cwpatch file (its rest grids), the density (1 to 1024) and the posed
// control points (as many as the rest grids have, finite).
// `where` names it in messages ("patch_driver", "more_drivers[0]").
std::shared_ptr<const PatchDriver> read_patch_driver(const Reader& r, const Json& j, const std::string& file,
                                                     std::vector<std::string>& warnings, const std::string& where = "patch_driver") {
  if (!j.is_object()) r.fail(ErrorCode::kParse, where + " should be an object, not " + Reader::show(j));
  auto rest = patch_surface_from_json(r.field(j, where, "rest"), file, where + ".rest");
  if (!rest) r.fail(rest.error().code, rest.error().message);
  PatchDriver d;
  d.rest = std::move(*rest);
  if (j.contains("density")) {
    d.density = r.index(j["density"], where + ".density");
    if (d.density < 1 || d.density > 1024)
      r.fail(ErrorCode::kInvalidArgument, where + ".density is " + std::to_string(d.density) + "; it must be 1 to 1024");
  }
  if (j.contains("drive_skin")) d.drive_skin = r.boolean(j["drive_skin"], where + ".drive_skin");
  d.posed = d.rest;
  if (j.contains("posed")) {
    const Json& list = r.array(j["posed"], where + ".posed");
    const size_t n = d.rest.num_control_points();
    if (list.size() != n)
      r.fail(ErrorCode::kTopologyMismatch, where + ".posed has " + std::to_string(list.size()) +
                                               " control points, but " + where + ".rest has " + std::to_string(n));
    std::vector<glm::dvec3> points(n);
    for (size_t k = 0; k < n; ++k) points[k] = read_dvec3(r, list[k], Reader::at(where + ".posed", k));
    d.posed.set_control_points(points);
  }
  warn_unknown(j, where, {"density", "drive_skin", "rest", "posed", "name", "hidden", "set_edits", "after", "mask", "mask_source", "keyposes", "binding", "attachment", "binding_cache"},
               warnings, file);
  return std::make_shared<const PatchDriver>(std::move(d));
}

std::vector<KeyposeSet> read_keyposes(const Reader& r, const Json& list, const Character& character,
                                      size_t num_vertices, std::vector<std::string>& warnings,
                                      const std::string& file) {
  r.array(list, "keyposes");
  std::vector<KeyposeSet> out;
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string path = Reader::at("keyposes", i);
    const Json& k = list[i];
    if (!k.is_object()) r.fail(ErrorCode::kParse, path + " should be an object, not " + Reader::show(k));
    KeyposeSet set;
    if (k.contains("name")) set.name = r.string(k["name"], path + ".name");
    const Json& drivers = r.array(r.field(k, path, "drivers"), path + ".drivers");
    if (drivers.empty())
      r.fail(ErrorCode::kEmpty, path + ".drivers is empty; a keypose set needs at least one driver");
    for (size_t d = 0; d < drivers.size(); ++d) {
      const std::string dpath = Reader::at(path + ".drivers", d);
      const Json& dj = drivers[d];
      if (!dj.is_object()) r.fail(ErrorCode::kParse, dpath + " should be an object, not " + Reader::show(dj));
      JointDriver dr;
      dr.node = read_node(r, r.field(dj, dpath, "node"), dpath + ".node", character.skeleton);
      std::string kind = r.string(r.field(dj, dpath, "kind"), dpath + ".kind");
      if (!parse_driver_kind(kind, dr.kind))
        r.fail(ErrorCode::kParse, dpath + ".kind is '" + kind + "'; expected rotation, twist or swing");
      dr.axis = read_vec3(r, r.field(dj, dpath, "axis"), dpath + ".axis");
      if (dr.axis == glm::vec3(0.0f))
        r.fail(ErrorCode::kInvalidArgument, dpath + ".axis is [0, 0, 0]; it needs a direction");
      warn_unknown(dj, dpath, {"node", "kind", "axis"}, warnings, file);
      set.drivers.push_back(dr);
    }
    if (k.contains("interpolation")) {
      std::string v = r.string(k["interpolation"], path + ".interpolation");
      if (!parse_key_interpolation(v, set.interpolation))
        r.fail(ErrorCode::kParse, path + ".interpolation is '" + v + "'; expected linear or smooth");
    }
    if (k.contains("kernel")) {
      std::string v = r.string(k["kernel"], path + ".kernel");
      if (!parse_rbf_kernel(v, set.kernel))
        r.fail(ErrorCode::kParse, path + ".kernel is '" + v + "'; expected gaussian, thin_plate or linear");
    }
    if (k.contains("rbf_width")) set.rbf_width = r.number(k["rbf_width"], path + ".rbf_width");
    if (k.contains("rest_key")) set.rest_key = boolean(r, k["rest_key"], path + ".rest_key");
    if (k.contains("mute")) set.mute = boolean(r, k["mute"], path + ".mute");
    if (k.contains("solo")) set.solo = boolean(r, k["solo"], path + ".solo");
    const Json& keys = k.contains("keys") ? r.array(k["keys"], path + ".keys") : Json::array();
    for (size_t j = 0; j < keys.size(); ++j) {
      const std::string kpath = Reader::at(path + ".keys", j);
      const Json& kj = keys[j];
      if (!kj.is_object()) r.fail(ErrorCode::kParse, kpath + " should be an object, not " + Reader::show(kj));
      KeyposeKey key;
      const Json& values = r.array(r.field(kj, kpath, "values"), kpath + ".values");
      if (values.size() != set.drivers.size())
        r.fail(ErrorCode::kInvalidArgument, kpath + ".values has " + std::to_string(values.size()) +
                                                " entries; the set has " +
                                                std::to_string(set.drivers.size()) + " drivers");
      for (size_t d = 0; d < values.size(); ++d)
        key.values.push_back(r.number(values[d], Reader::at(kpath + ".values", d)));
      std::vector<uint32_t> vertices =
          kj.contains("vertices") ? r.indices(kj["vertices"], kpath + ".vertices") : std::vector<uint32_t>{};
      const Json& offsets =
          kj.contains("offsets") ? r.array(kj["offsets"], kpath + ".offsets") : Json::array();
      if (offsets.size() != vertices.size())
        r.fail(ErrorCode::kInvalidArgument, kpath + ".offsets has " + std::to_string(offsets.size()) +
                                                " entries for " + std::to_string(vertices.size()) +
                                                " vertices");
      std::vector<std::pair<uint32_t, glm::vec3>> entries;
      for (size_t e = 0; e < vertices.size(); ++e) {
        if (vertices[e] >= num_vertices)
          r.fail(ErrorCode::kIndexOutOfRange, Reader::at(kpath + ".vertices", e) + " is cage vertex " +
                                                  std::to_string(vertices[e]) + ", but the cage has " +
                                                  std::to_string(num_vertices) + " vertices");
        entries.emplace_back(vertices[e], read_vec3(r, offsets[e], Reader::at(kpath + ".offsets", e)));
      }
      std::stable_sort(entries.begin(), entries.end(),
                       [](const auto& a, const auto& b) { return a.first < b.first; });
      for (size_t e = 0; e < entries.size(); ++e) {
        if (e > 0 && entries[e].first == entries[e - 1].first)
          r.fail(ErrorCode::kInvalidArgument,
                 kpath + ".vertices lists cage vertex " + std::to_string(entries[e].first) + " twice");
        key.vertices.push_back(entries[e].first);
        key.offsets.push_back(entries[e].second);
      }
      warn_unknown(kj, kpath, {"values", "vertices", "offsets"}, warnings, file);
      set.keys.push_back(std::move(key));
    }
    if (auto v = validate_keypose_set(set, character.skeleton.size(), num_vertices); !v)
      r.fail(v.error().code, path + ": " + v.error().message);
    warn_unknown(
        k, path,
        {"name", "drivers", "interpolation", "kernel", "rbf_width", "rest_key", "mute", "solo", "keys"},
        warnings, file);
    out.push_back(std::move(set));
  }
  return out;
}

// A path the project records, resolved against the project's folder and made absolute
// (independent of later changes of the working folder).
std::string resolve_path(const std::string& project_path, const std::string& recorded) {
  fs::path resolved = fs::path(recorded);
  if (resolved.is_relative()) resolved = fs::path(project_path).parent_path() / resolved;
  return fs::absolute(resolved).lexically_normal().string();
}

// "binding_cache": caching on; its record when it names a file. A malformed record is a warning
// (the cache is a by-product: the project still opens, and binds).
void read_binding_cache(const Json& root, const std::string& path, Document& doc, std::vector<std::string>& warnings) {
  if (!root.contains("binding_cache")) return;
  doc.cache_binding = true;
  const Json& bc = root["binding_cache"];
  const Reader r(path);
  try {
    if (!bc.is_object()) r.fail(ErrorCode::kParse, "binding_cache should be an object, not " + Reader::show(bc));
    warn_unknown(bc, "binding_cache", {"file", "hash", "inputs"}, warnings, path);
    if (!bc.contains("file")) return;  // caching on, nothing cached yet
    BindingCacheRecord record;
    record.file = resolve_path(path, r.string(bc["file"], "binding_cache.file"));
    record.file_hash = r.string(r.field(bc, "binding_cache", "hash"), "binding_cache.hash");
    const Json& inputs = r.object(bc, "binding_cache", "inputs");
    for (const auto& [key, member] : kInputFields)
      record.inputs.*member = r.string(r.field(inputs, "binding_cache.inputs", key), Reader::join("binding_cache.inputs", key));
    doc.binding_cache = std::move(record);
  } catch (const JsonLoadFailure& f) {
    warnings.push_back(f.error.message + "; the cached binding is not used");
  }
}

std::optional<RecoveryInfo> read_recovery(const Reader& r, const Json& root) {
  if (!root.contains("recovery")) return std::nullopt;
  const Json& j = r.object(root, "", "recovery");
  RecoveryInfo info;
  info.project = r.string(r.field(j, "recovery", "project"), "recovery.project");
  const Json& pid = r.field(j, "recovery", "pid");
  if (!pid.is_number_integer()) r.fail(ErrorCode::kParse, "recovery.pid should be a whole number, not " + Reader::show(pid));
  info.pid = pid.get<int64_t>();
  return info;
}

// The fields of one deformer (the document's own cage, or a layer's) that need no character: the
// cage, "binding", "set_edits" and the cage's "offsets".
void read_cage_fields(const Reader& r, const Json& root, Document& doc, std::vector<std::string>& warnings,
                      const std::string& path) {
  doc.cage = read_cage(r, root);
  doc.params = read_params(r, root, warnings, path);
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
}

// The rest, checked against the character: set edits' points, "attachment", "keyposes", "simulation".
void read_posing_fields(const Reader& r, const Json& root, const Character& character, Document& doc,
                        std::vector<std::string>& warnings, const std::string& path) {
  const size_t num_points = character.num_vertices();
  for (size_t i = 0; i < doc.set_edits.size(); ++i)
    if (doc.set_edits[i].point >= num_points)
      r.fail(ErrorCode::kIndexOutOfRange, Reader::at("set_edits", i) + ".point is skin vertex " +
                                              std::to_string(doc.set_edits[i].point) + ", but the character has " +
                                              std::to_string(num_points) + " vertices");
  const size_t num_cage_vertices = doc.cage ? doc.cage->num_vertices() : 0;
  doc.attachment.mode = AttachmentMode::kRigid;  // a version 1 file: the cage followed the closest limb
  if (root.contains("attachment"))
    doc.attachment = read_attachment(r, root["attachment"], character, num_cage_vertices, warnings, path);
  if (root.contains("keyposes"))
    doc.keyposes = read_keyposes(r, root["keyposes"], character, num_cage_vertices, warnings, path);
  if (root.contains("simulation"))
    doc.sim = read_simulation(r, root["simulation"], character, num_cage_vertices, warnings, path);
}

// "deformers": each layer read like the document's own cage, its messages naming "deformers[i]".
// A deformer's "mask": one weight in [0, 1] per skin vertex of the character.
std::shared_ptr<const std::vector<float>> read_mask(const Reader& r, const Json& j, const std::string& where, const Character& character) {
  const Json& m = r.array(j, where);
  if (m.size() != character.num_vertices())
    r.fail(ErrorCode::kTopologyMismatch, where + " has " + std::to_string(m.size()) + " weights but the character has " +
                                             std::to_string(character.num_vertices()) + " vertices");
  auto mask = std::make_shared<std::vector<float>>(m.size());
  for (size_t p = 0; p < m.size(); ++p) {
    const float w = r.finite_float(m[p], Reader::at(where, p));
    if (w < 0.0f || w > 1.0f) r.fail(ErrorCode::kParse, Reader::at(where, p) + " should be in [0, 1], not " + Reader::show(m[p]));
    (*mask)[p] = w;
  }
  return mask;
}

// The parametric driver's place in the stack, mask and keyposes ("patch_driver"'s "after", "mask",
// "mask_source", "keyposes"), checked against the character and the driver's control points.
DriverPlacement read_driver_place(const Reader& r, const Json& j, const Character& character, size_t num_control_points,
                                  size_t num_samples, std::vector<std::string>& warnings, const std::string& file,
                                  const std::string& where = "patch_driver") {
  DriverPlacement place;
  if (j.contains("name")) place.name = r.string(j["name"], where + ".name");
  if (j.contains("hidden")) place.hidden = r.boolean(j["hidden"], where + ".hidden");
  if (j.contains("after")) place.after = static_cast<int32_t>(r.index(j["after"], where + ".after"));
  if (j.contains("mask_source")) place.mask_source = r.string(j["mask_source"], where + ".mask_source");
  if (j.contains("mask")) place.mask = read_mask(r, j["mask"], where + ".mask", character);
  if (j.contains("keyposes")) place.keyposes = read_keyposes(r, j["keyposes"], character, num_control_points, warnings, file);
  if (j.contains("binding")) place.params = read_params(Reader(r.file() + ": " + where), j, warnings, file);
  if (j.contains("set_edits")) {  // sample ids, checked against the driver's samples
    const Reader in(r.file() + ": " + where);
    const Json& list = in.array(j["set_edits"], "set_edits");
    for (size_t i = 0; i < list.size(); ++i) {
      place.set_edits.push_back(read_set_edit(in, list[i], Reader::at("set_edits", i), num_samples));
      if (place.set_edits.back().point >= character.num_vertices())
        in.fail(ErrorCode::kIndexOutOfRange, Reader::at("set_edits", i) + ".point is skin vertex " +
                                                 std::to_string(place.set_edits.back().point) + ", but the character has " +
                                                 std::to_string(character.num_vertices()));
    }
    place.set_edits = canonical_set_edits(place.set_edits);
  }
  if (j.contains("binding_cache")) {  // its cached binding (a malformed record is a warning: it binds again)
    Document cached;
    read_binding_cache(j, file, cached, warnings);
    place.binding_cache = std::move(cached.binding_cache);
  }
  if (j.contains("attachment")) {
    const Reader in(r.file() + ": " + where);
    place.attachment = read_attachment(in, j["attachment"], character, num_control_points, warnings, file);
    if (place.attachment->mode == AttachmentMode::kFitted)
      in.fail(ErrorCode::kInvalidArgument, "attachment.mode is fitted; a driver's control points are attached rigid, smooth or skin_weights");
  }
  return place;
}

std::vector<DeformerLayer> read_layers(const std::string& path, const Json& list, const Character& character,
                                       std::vector<std::string>& warnings) {
  Reader top(path);
  top.array(list, "deformers");
  std::vector<DeformerLayer> out;
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string where = Reader::at("deformers", i);
    const Reader r(path + ": " + where);
    const Json& j = list[i];
    if (!j.is_object()) top.fail(ErrorCode::kParse, where + " should be an object, not " + Reader::show(j));
    Document d;
    read_cage_fields(r, j, d, warnings, r.file());
    if (!d.cage) r.fail(ErrorCode::kParse, "the deformer has no cage");
    read_posing_fields(r, j, character, d, warnings, r.file());
    DeformerLayer l;
    l.name = j.contains("name") ? r.string(j["name"], "name") : "deformer " + std::to_string(i + 1);
    read_binding_cache(j, path, d, warnings);
    l.binding_cache = std::move(d.binding_cache);
    l.muted = j.contains("muted") && r.boolean(j["muted"], "muted");
    l.hidden = j.contains("hidden") && r.boolean(j["hidden"], "hidden");
    if (j.contains("mask_source")) l.mask_source = r.string(j["mask_source"], "mask_source");
    if (j.contains("mask")) l.mask = read_mask(r, j["mask"], "mask", character);
    l.cage = d.cage;
    l.params = d.params;
    l.set_edits = std::move(d.set_edits);
    l.cage_offsets = std::move(d.cage_offsets);
    l.attachment = d.attachment;
    l.keyposes = std::move(d.keyposes);
    l.sim = std::move(d.sim);
    warn_unknown(j, where, {"cage", "binding", "set_edits", "attachment", "keyposes", "simulation", "mask", "mask_source", "name", "muted", "hidden",
                          "binding_cache"},
                 warnings, path);
    out.push_back(std::move(l));
  }
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
  warn_unknown(character, "character", {"path", "hash", "keep_units", "embedded"}, out.warnings, path);
  CharacterLoadOptions load;
  if (character.contains("keep_units")) load.keep_units = r.boolean(character["keep_units"], "character.keep_units");
  doc.character_keep_units = load.keep_units;
  out.recovery = read_recovery(r, root);
  std::shared_ptr<const std::string> embedded;
  if (character.contains("embedded")) {
    auto bytes = base64_decode(r.string(character["embedded"], "character.embedded"), path + ": character.embedded");
    if (!bytes) return bytes.error();
    // a damaged file (an edit, a bad merge) must not load as another character
    if (const std::string h = format_hash(fnv1a64(*bytes)); h != recorded_hash)
      r.fail(ErrorCode::kParse, "character.embedded does not match character.hash (its bytes hash to " + h +
                                    "): the project file is damaged");
    embedded = std::make_shared<const std::string>(std::move(bytes).value());
  }
  read_cage_fields(r, root, doc, out.warnings, path);

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

  // The character: embedded, or a file whose relative path is relative to the project's folder.
  const std::string resolved = resolve_path(path, recorded);
  std::string character_path = resolved;
  std::optional<Result<Character>> loaded_file;
  if (embedded) {
    const std::string name = fs::path(recorded).filename().string();
    loaded_file.emplace(load_character_bytes(*embedded, path + ": the embedded character " + name, load, recorded));
    if (*loaded_file) (*loaded_file)->source = name + " (embedded)";
  } else {
    if (!character_override.empty()) character_path = character_override;
    out.character_relocated = !character_override.empty() && fs::path(character_override).lexically_normal() != resolved;
    std::error_code ec;
    if (!fs::exists(character_path, ec)) {
      if (missing) *missing = character_path;
      return make_error(ErrorCode::kFileNotFound, path + ": character file " + character_path +
                                                      " not found; locate it (or move it back beside the project)");
    }
    loaded_file.emplace(load_character(character_path, load));
  }
  auto& loaded = *loaded_file;
  if (!loaded)
    return make_error(loaded.error().code,
                      embedded ? loaded.error().message
                               : path + ": the character could not be loaded: " + loaded.error().message);
  std::string hash = recorded_hash;
  if (!embedded) {
    auto h = hash_file(character_path);
    if (!h) return h.error();
    hash = std::move(h).value();
  }
  if (hash != recorded_hash)
    out.warnings.push_back(path + ": the character file " + character_path +
                           " changed since the project was saved (hash " + hash + ", project says " + recorded_hash +
                           "); check that the cage and set edits still fit it");
  read_posing_fields(r, root, *loaded, doc, out.warnings, path);
  if (root.contains("deformers")) doc.layers = read_layers(path, root["deformers"], *loaded, out.warnings);
  if (root.contains("deformer_stack")) {
    const Json& st = r.object(root, "", "deformer_stack");
    const std::string mode = r.string(r.field(st, "deformer_stack", "mode"), "deformer_stack.mode");
    if (!parse_stack_mode(mode, doc.stack.mode))
      r.fail(ErrorCode::kParse, "deformer_stack.mode should be \"in_order\", \"sum\" or \"blend\", not \"" + mode + "\"");
    if (st.contains("exponent")) doc.stack.exponent = r.number(st["exponent"], "deformer_stack.exponent");
    if (!(doc.stack.exponent >= 0.0))
      r.fail(ErrorCode::kParse, "deformer_stack.exponent should be >= 0, not " + Reader::show(st["exponent"]));
    doc.stack.base_muted = st.contains("base_muted") && r.boolean(st["base_muted"], "deformer_stack.base_muted");
    doc.stack.base_hidden = st.contains("base_hidden") && r.boolean(st["base_hidden"], "deformer_stack.base_hidden");
    if (st.contains("solo")) {
      const uint32_t solo = r.index(st["solo"], "deformer_stack.solo");
      if (solo >= deformer_count(doc))
        r.fail(ErrorCode::kParse, "deformer_stack.solo is " + std::to_string(solo) + " but the deformers are 0 to " +
                                      std::to_string(doc.layers.size()));
      doc.stack.solo = static_cast<int32_t>(solo);
    }
    if (st.contains("solo_driver")) doc.stack.solo_driver = r.string(st["solo_driver"], "deformer_stack.solo_driver");
    warn_unknown(st, "deformer_stack", {"mode", "exponent", "base_muted", "base_hidden", "solo", "solo_driver"}, out.warnings, path);
  }
  if (root.contains("patch_driver")) {
    doc.patch_driver = read_patch_driver(r, root["patch_driver"], path, out.warnings);
    doc.driver_place = read_driver_place(r, root["patch_driver"], *loaded, doc.patch_driver->rest.num_control_points(),
                                         patch_sample_count(doc.patch_driver->rest, doc.patch_driver->density), out.warnings, path);
  }
  if (root.contains("more_drivers")) {
    const Json& list = r.array(root["more_drivers"], "more_drivers");
    if (!list.empty() && !doc.patch_driver) r.fail(ErrorCode::kParse, "more_drivers needs a patch_driver (the first driver)");
    for (size_t i = 0; i < list.size(); ++i) {
      const std::string where = Reader::at("more_drivers", i);
      DriverDeformer d;
      d.driver = read_patch_driver(r, list[i], path, out.warnings, where);
      d.place = read_driver_place(r, list[i], *loaded, d.driver->rest.num_control_points(),
                                  patch_sample_count(d.driver->rest, d.driver->density), out.warnings, path, where);
      doc.more_drivers.push_back(std::move(d));
    }
  }
  if (!doc.stack.solo_driver.empty() && !soloed_driver(doc))
    r.fail(ErrorCode::kParse, "deformer_stack.solo_driver is '" + doc.stack.solo_driver + "', but no parametric driver has that name");
  doc.character = std::make_shared<const Character>(std::move(loaded).value());
  doc.character_path = character_path;
  doc.character_hash = std::move(hash);
  doc.embedded_character = std::move(embedded);
  doc.project_path = path;
  read_binding_cache(root, path, doc, out.warnings);
  doc.revision = next_revision();
  return out;
}

}  // namespace

Status save_project(const std::string& path, const Document& doc, const SaveOptions& options) {
  if (doc.character_path.empty())
    return make_error(ErrorCode::kInvalidArgument, path + ": not saved: the document has no character file");
  std::error_code ec;
  if (fs::absolute(path).lexically_normal() == fs::absolute(doc.character_path).lexically_normal() ||
      fs::equivalent(path, doc.character_path, ec))
    return make_error(ErrorCode::kInvalidArgument,
                      path + ": not saved: that is the character file; choose another name for the project");
  if (auto v = validate(doc.params); !v)
    return make_error(ErrorCode::kInvalidArgument, path + ": not saved: " + v.error().message);
  // the binding caches (the document's cage's, each layer's and each driver's): written first, so a project
  // never names a cache file that is not there yet
  std::vector<BindingCacheFile> cache_files;
  CacheRecords records;  // what the project records; an empty record = nothing cached
  records.layers.resize(doc.layers.size());
  records.drivers.resize(driver_count(doc));
  // a record the document already has is kept when the file is where this save puts it and nothing the
  // binding depends on changed
  auto still_valid = [](const BindingCacheRecord& r, const std::string& file, const BindingInputs& now) {
    return r.file == fs::absolute(file).lexically_normal().string() && r.inputs == now;
  };
  if (doc.cache_binding && !options.recovery && doc.cage) {
    for (size_t d = 0; d < deformer_count(doc); ++d) {
      const Binding* binding = d == 0 ? options.binding
                                      : d - 1 < options.layer_bindings.size() ? options.layer_bindings[d - 1] : nullptr;
      BindingCacheRecord& record = d == 0 ? records.cage : records.layers[d - 1];
      const Document view = deformer_document(doc, d);
      if (binding) {
        auto made = make_binding_cache(path, view, *binding, d);
        if (!made) return make_error(made.error().code, made.error().message + (d ? " (deformer '" + doc.layers[d - 1].name + "')" : ""));
        record = made->record;
        cache_files.push_back(std::move(made).value());
      } else if (still_valid(view.binding_cache, binding_cache_path(path, d), binding_inputs(view))) {
        record = view.binding_cache;  // saved again, nothing the binding depends on changed
      }
    }
  }
  if (doc.cache_binding && !options.recovery) {
    for (size_t i = 0; i < driver_count(doc); ++i) {
      const Binding* binding = i < options.driver_bindings.size() ? options.driver_bindings[i] : nullptr;
      const BindingCacheRecord& had = driver_at(doc, i).place->binding_cache;
      if (binding) {
        auto made = make_driver_binding_cache(path, doc, i, *binding);
        if (!made) return make_error(made.error().code, made.error().message + " (parametric driver '" + driver_name(doc, i) + "')");
        records.drivers[i] = made->record;
        cache_files.push_back(std::move(made).value());
      } else if (still_valid(had, driver_binding_cache_path(path, i), driver_binding_inputs(doc, i))) {
        records.drivers[i] = had;
      }
    }
  }
  try {
    auto text = project_text(path, doc, doc.cache_binding ? &records : nullptr, options.recovery);
    if (!text) return text.error();
    for (const BindingCacheFile& f : cache_files)
      if (auto s = write_file_atomic(f.path, f.bytes); !s) return s.error();
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
