// The workspace's rig edits (app/workspace/workspace.h "the rig"): attachment modes, cage vertices
// assigned to joints, keypose sets and their keys. The Rig window draws them; these make the change.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "app/workspace/workspace.h"
#include "core/character/mirror_names.h"

namespace cagewrap::app {

bool Workspace::set_attachment_mode(AttachmentMode mode, double smooth_width) {
  if (!scene_) return false;
  if (!(smooth_width > 0.0)) {
    report_error("the smooth attachment's width must be above 0 (got " + std::to_string(smooth_width) + ")");
    return false;
  }
  AttachmentSettings a = scene_->doc().attachment;
  a.mode = mode;
  a.smooth_width = smooth_width;
  if (a == scene_->doc().attachment) return true;
  scene_->apply(std::string("Attachment: ") + attachment_mode_name(mode), with_attachment(scene_->doc(), a));
  return true;
}

bool Workspace::assign_cage_vertices(bool automatic) {
  if (!scene_) return false;
  const Document& doc = scene_->doc();
  const Selection& sel = view.selection;
  if (!doc.cage || sel.cage_vertices.empty()) {
    log("error: select cage vertices first (F5)", true);
    return false;
  }
  std::optional<uint32_t> node;
  if (!automatic) {
    if (sel.joints.size() != 1) {
      log("error: select exactly one joint to assign the cage vertices to (F8 or the outliner)", true);
      return false;
    }
    node = sel.joints.indices()[0];
  }
  AttachmentSettings a = assign_vertices(doc.attachment, sel.cage_vertices.indices(), node);
  if (view.mirror.enabled) {
    auto m = mirror_assignment(a, doc.character->skeleton, doc.cage->polygons.positions, sel.cage_vertices.indices(),
                               rig_mirror_tolerance());
    if (!m) {
      report_error(m.error().message);
      return false;
    }
    if (!m->unmatched.empty()) log("warning: " + std::to_string(m->unmatched.size()) + " vertices have no mirror counterpart");
    a = m->settings;
  }
  // the attachment must be valid before it is committed
  if (auto att = attach_cage(*doc.character, doc.cage->polygons.positions, a, doc.cage->elements); !att) {
    report_error(att.error().message);
    return false;
  }
  const std::string what = automatic ? "automatic" : doc.character->skeleton.node(*node).name;
  scene_->apply("Attach " + std::to_string(sel.cage_vertices.size()) + " vertices: " + what, with_attachment(doc, a));
  return true;
}

bool Workspace::add_keypose_set(int axis) {
  if (!scene_) return false;
  if (view.selection.joints.size() != 1) {
    log("error: select the joint that drives the keypose (F8)", true);
    return false;
  }
  const uint32_t node = view.selection.joints.indices()[0];
  KeyposeSet set;
  set.name = scene_->doc().character->skeleton.node(node).name + "_" + "XYZ"[axis % 3];
  JointDriver d;
  d.node = node;
  d.axis = glm::vec3(0.f);
  d.axis[axis % 3] = 1.f;
  set.drivers.push_back(d);
  std::vector<KeyposeSet> sets = scene_->doc().keyposes;
  view.keypose_set = upsert_keypose_set(sets, set);
  scene_->apply("Add keypose set " + set.name, with_keyposes(scene_->doc(), std::move(sets)));
  return true;
}

const KeyposeSet* Workspace::active_keypose_set() {
  if (!scene_ || scene_->doc().keyposes.empty()) return nullptr;
  view.keypose_set = std::min(view.keypose_set, scene_->doc().keyposes.size() - 1);
  return &scene_->doc().keyposes[view.keypose_set];
}

bool Workspace::key_sculpt() {
  const KeyposeSet* active = active_keypose_set();
  if (!active || !scene_->doc().cage) {
    log("error: add a keypose set first (select a joint, Rig > Keyposes > Add set)", true);
    return false;
  }
  const Document& doc = scene_->doc();
  const KeyposeSet& set = *active;
  std::vector<double> values = driver_values(set, doc.character->skeleton, current_pose());
  for (double& v : values) v = std::round(v * 10.0) / 10.0;  // keys at tenths of a degree
  // what was sculpted since the last key: the driver offsets, taken out of them into the key
  std::vector<glm::vec3> delta = doc.cage_offsets;
  delta.resize(doc.cage->num_vertices(), glm::vec3(0.f));
  std::vector<KeyposeSet> sets = doc.keyposes;
  sets[view.keypose_set] = cagewrap::key_sculpt(set, values, delta);
  char label[128];
  std::snprintf(label, sizeof label, "Key %s at %.1f", set.name.c_str(), values.empty() ? 0.0 : values[0]);
  scene_->apply(label, with_cage_offsets(with_keyposes(doc, std::move(sets)), {}));
  log(label);
  return true;
}

bool Workspace::remove_key(size_t k) {
  const KeyposeSet* active = active_keypose_set();
  if (!active || k >= active->keys.size()) {
    log("error: the keypose set has no key " + std::to_string(k), true);
    return false;
  }
  std::vector<KeyposeSet> sets = scene_->doc().keyposes;
  cagewrap::remove_key(sets[view.keypose_set], active->keys[k].values);
  scene_->apply("Delete key of " + active->name, with_keyposes(scene_->doc(), std::move(sets)));
  return true;
}

bool Workspace::mirror_keypose_set() {
  const KeyposeSet* active = active_keypose_set();
  if (!active || !scene_->doc().cage) {
    log("error: no keypose set to mirror", true);
    return false;
  }
  const Document& doc = scene_->doc();
  auto m = cagewrap::mirror_keypose_set(*active, doc.character->skeleton, doc.cage->polygons.positions, rig_mirror_tolerance());
  if (!m) {
    report_error(m.error().message);
    return false;
  }
  std::vector<KeyposeSet> sets = doc.keyposes;
  upsert_keypose_set(sets, m->set);
  scene_->apply("Mirror keypose set " + active->name, with_keyposes(doc, std::move(sets)));
  return true;
}

bool Workspace::replace_keypose_set(KeyposeSet set, const std::string& label) {
  const KeyposeSet* active = active_keypose_set();
  if (!active || !scene_->doc().cage) return false;
  std::sort(set.keys.begin(), set.keys.end(), [](const KeyposeKey& a, const KeyposeKey& b) { return a.values < b.values; });
  if (set == *active) return true;
  const Document& doc = scene_->doc();
  if (auto st = validate_keypose_set(set, doc.character->skeleton.size(), doc.cage->num_vertices()); !st) {
    report_error(st.error().message);
    return false;
  }
  std::vector<KeyposeSet> sets = doc.keyposes;
  sets[view.keypose_set] = std::move(set);
  scene_->apply(label, with_keyposes(doc, std::move(sets)));
  return true;
}

}  // namespace cagewrap::app
