// The workspace's contributing-set edits (app/workspace/workspace.h "contributing sets"): remove /
// add / only / reset the selected cage faces' elements on skin points, applied to a selection or
// painted with a brush measured along the skin, with X mirroring. Edits re-register only the touched
// points (Scene::apply_set_edits, update_set_edits_live), so the skin follows at once. The Sets
// window and the actions set_edit, select_limb_faces and paint_at_skin_vertex run these.
#include <algorithm>

#include "app/workspace/workspace.h"
#include "core/geometry/mesh.h"

namespace cagewrap::app {

const SetEditMirror& Workspace::set_edit_mirror() {
  const auto& cage = scene_->doc().cage;
  if (!set_mirror_ || set_mirror_->cage != cage || set_mirror_->skin_points != scene_->skin_rest.size()) {
    const double tol = 2e-3 * scene_->skin_diagonal;
    const std::vector<glm::vec3> centroids = cagewrap::face_centroids(cage->polygons);
    set_mirror_.emplace(SetMirrorMaps{cage, scene_->skin_rest.size(), MirrorMap(scene_->skin_rest, tol),
                                      MirrorMap(centroids, std::max(tol, 0.25 * mean_edge_length(cage->polygons))), {}});
    set_mirror_->maps.points = &set_mirror_->points;
    set_mirror_->maps.faces = &set_mirror_->faces;
  }
  return set_mirror_->maps;
}

bool Workspace::apply_set_edit(const IndexSet& points) {
  if (!scene_) return false;
  const Document& doc = scene_->doc();
  if (!doc.cage) {
    log("error: there is no cage: build or import one first (Cage menu)", true);
    return false;
  }
  if (points.empty()) {
    log("error: select the skin vertices to edit first (F7)", true);
    return false;
  }
  const SetEditMode mode = view.sets.mode;
  if (mode != SetEditMode::kReset && view.selection.cage_faces.empty()) {
    log("error: select the cage faces to " + std::string(set_edit_mode_name(mode)) + " first (F6)", true);
    return false;
  }
  const SetEditMirror mirror = view.sets.mirror ? set_edit_mirror() : SetEditMirror{};
  auto r = cagewrap::apply_set_edit(doc.set_edits, mode, points, view.selection.cage_faces, *doc.cage, scene_->skin_rest.size(), mirror);
  if (!r) {
    report_error(r.error().message);
    return false;
  }
  if (r->changed_points.empty()) return true;
  Document next = with_set_edits(doc, r->edits);
  if (stroke_) {
    scene_->drag(std::move(next));
    if (!scene_->update_set_edits_live(scene_->doc().set_edits, r->changed_points)) scene_->document_changed();  // a full rebind
  } else {
    scene_->apply_set_edits(std::string("Sets: ") + set_edit_mode_name(mode) + " on " + std::to_string(points.size()) + " points",
                            std::move(next), r->changed_points);
  }
  return true;
}

void Workspace::begin_set_stroke() {
  if (!scene_ || stroke_) return;
  stroke_.emplace(scene_->skin_posed(), scene_->skin_triangles());
  scene_->begin_drag();
}

bool Workspace::set_stroke_dab(uint32_t triangle, const glm::dvec3& hit) {
  if (!stroke_) return false;
  if (view.sets.brush_radius <= 0.0) view.sets.brush_radius = 0.03 * scene_->skin_diagonal;
  auto pts = stroke_->points_within(triangle, hit, view.sets.brush_radius);
  if (!pts) {
    log("error: brush: " + pts.error().message, true);
    return false;
  }
  return !pts->points.empty() && apply_set_edit(IndexSet(pts->points));
}

void Workspace::end_set_stroke() {
  if (!stroke_) return;
  stroke_.reset();
  // the stroke's edits are in the binding already (update_set_edits_live): nothing to refresh
  scene_->commit_drag(std::string("Paint sets: ") + set_edit_mode_name(view.sets.mode), /*refresh=*/false);
}

IndexSet Workspace::limb_faces(const IndexSet& joints) const {
  std::vector<uint32_t> faces;
  const Cage* cage = scene_ ? scene_->doc().cage.get() : nullptr;
  if (!cage || !scene_->attachment || scene_->attachment->joint.size() != cage->num_vertices()) return {};
  const auto& skin_joints = scene_->doc().character->skins[scene_->attachment->skin].joints;
  auto follows = [&](uint32_t v) {
    const uint32_t j = scene_->attachment->joint[v];
    return j < skin_joints.size() && joints.contains(skin_joints[j]);
  };
  for (size_t f = 0; f < cage->polygons.num_faces(); ++f) {
    const auto c = cage->polygons.face(f);
    if (std::all_of(c.begin(), c.end(), follows)) faces.push_back(static_cast<uint32_t>(f));
  }
  return IndexSet(std::move(faces));
}

}  // namespace cagewrap::app
