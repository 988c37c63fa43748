#include "core/export/rig_json.h"

#include "core/cage/cage_attachment.h"
#include "core/base/json_reader.h"
#include "core/cage/keyposes.h"

namespace cagewrap {

namespace {

Json vec3_json(const glm::vec3& v) {
  return Json::array({json_short_float(v.x), json_short_float(v.y), json_short_float(v.z)});
}

// A node by name and by index (names need not be unique in a glTF file).
void add_node(Json& object, const Skeleton& skeleton, uint32_t node, const char* name_key = "node",
              const char* index_key = "node_index") {
  object[name_key] = node < skeleton.size() ? skeleton.node(node).name : std::string();
  object[index_key] = node;
}

Json keypose_json(const KeyposeSet& set, const Skeleton& skeleton, bool active) {
  Json s = Json::object();
  s["name"] = set.name;
  s["active"] = active;
  s["drivers"] = Json::array();
  for (const JointDriver& d : set.drivers) {
    Json dj = Json::object();
    add_node(dj, skeleton, d.node);
    dj["kind"] = driver_kind_name(d.kind);
    dj["axis"] = vec3_json(d.axis);
    s["drivers"].push_back(std::move(dj));
  }
  s["interpolation"] = key_interpolation_name(set.interpolation);
  s["kernel"] = rbf_kernel_name(set.kernel);
  s["rbf_width"] = set.rbf_width;
  s["rest_key"] = set.rest_key;
  s["mute"] = set.mute;
  s["solo"] = set.solo;
  s["keys"] = Json::array();
  for (const KeyposeKey& k : set.keys) {
    Json kj = Json::object();
    kj["values"] = k.values;
    kj["vertices"] = k.vertices;
    Json offsets = Json::array();
    for (const glm::vec3& o : k.offsets) offsets.push_back(vec3_json(o));
    kj["offsets"] = std::move(offsets);
    s["keys"].push_back(std::move(kj));
  }
  return s;
}

}  // namespace

Result<RigJson> rig_json(const Document& doc, const CageAttachment* attachment) {
  if (!doc.character || !doc.cage)
    return make_error(ErrorCode::kInvalidArgument,
                      "the document has no cage yet: there is no rig to describe");
  const Character& ch = *doc.character;
  const Skeleton& sk = ch.skeleton;
  const Cage& cage = *doc.cage;
  const auto rest = doc.cage_positions();
  RigJson out;
  out.vertices = cage.num_vertices();
  out.faces = cage.polygons.num_faces();
  out.keypose_sets = doc.keyposes.size();

  Json root = Json::object();
  root["format"] = kRigJsonFormat;
  root["version"] = kRigJsonVersion;
  root["character"] = {{"path", doc.character_path}, {"hash", doc.character_hash}};

  Json c = Json::object();
  c["positions"] = Json::array();
  c["offsets"] = Json::array();
  for (size_t v = 0; v < rest.size(); ++v) {
    c["positions"].push_back(vec3_json(rest[v]));
    c["offsets"].push_back(vec3_json(v < doc.cage_offsets.size() ? doc.cage_offsets[v] : glm::vec3(0.0f)));
  }
  c["faces"] = Json::array();
  for (size_t f = 0; f < cage.polygons.num_faces(); ++f) {
    auto face = cage.polygons.face(f);
    c["faces"].push_back(std::vector<uint32_t>(face.begin(), face.end()));
  }
  c["elements"] = Json::array();
  for (const Tri& t : cage.elements) c["elements"].push_back(t);
  c["element_face"] = cage.element_face;
  root["cage"] = std::move(c);

  if (ch.skins.empty()) {
    root["skin"] = nullptr;
    root["attachment"] = nullptr;
  } else {
    auto att = attachment ? Result<CageAttachment>(*attachment) : attach_cage(ch, rest, doc.attachment, cage.elements);
    if (!att) return make_error(att.error().code, "attachment: " + att.error().message);
    out.attached = true;
    const Skin& skin = ch.skins[att->skin];
    Json s = Json::object();
    s["index"] = att->skin;
    s["name"] = skin.name;
    s["joints"] = Json::array();
    for (size_t j = 0; j < skin.joints.size(); ++j) {
      Json jj = Json::object();
      add_node(jj, sk, skin.joints[j]);
      Json m = Json::array();
      for (int col = 0; col < 4; ++col)
        for (int row = 0; row < 4; ++row) m.push_back(json_short_float(skin.inverse_bind[j][col][row]));
      jj["inverse_bind"] = std::move(m);
      s["joints"].push_back(std::move(jj));
    }
    root["skin"] = std::move(s);

    Json a = Json::object();
    a["mode"] = attachment_mode_name(doc.attachment.mode);
    a["smooth_width"] = doc.attachment.smooth_width;
    a["overrides"] = Json::array();
    for (const AttachmentOverride& o : doc.attachment.overrides) {
      Json oj = {{"vertex", o.vertex}};
      add_node(oj, sk, o.node);
      a["overrides"].push_back(std::move(oj));
    }
    a["vertices"] = Json::array();
    for (size_t v = 0; v < rest.size(); ++v) {
      Json names = Json::array(), nodes = Json::array(), joints = Json::array(), weights = Json::array();
      for (uint32_t i = att->influence_start[v]; i < att->influence_start[v + 1]; ++i) {
        const uint32_t node = skin.joints[att->influence_joint[i]];
        names.push_back(sk.node(node).name);
        nodes.push_back(node);
        joints.push_back(att->influence_joint[i]);
        weights.push_back(json_short_float(att->influence_weight[i]));
      }
      Json vj = {{"nodes", std::move(names)},
                 {"node_indices", std::move(nodes)},
                 {"joints", std::move(joints)},
                 {"weights", std::move(weights)}};
      if (assigned_node(doc.attachment, static_cast<uint32_t>(v))) vj["override"] = true;
      a["vertices"].push_back(std::move(vj));
    }
    root["attachment"] = std::move(a);
  }

  root["keyposes"] = Json::array();
  for (size_t i = 0; i < doc.keyposes.size(); ++i)
    root["keyposes"].push_back(keypose_json(doc.keyposes[i], sk, keypose_set_active(doc.keyposes, i)));
  out.text = json_layout(root) + "\n";
  return out;
}

}  // namespace cagewrap
