#include "app/workspace/workspace.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include <glm/trigonometric.hpp>

#include "app/workspace/move_gizmo.h"
#include "core/geometry/mesh.h"

namespace cagewrap::app {

const char* select_mode_name(SelectMode m) {
  switch (m) {
    case SelectMode::kCageVertices: return "cage vertices";
    case SelectMode::kCageFaces: return "cage faces";
    case SelectMode::kSkinVertices: return "skin vertices";
    case SelectMode::kJoints: return "joints";
  }
  return "?";
}

const char* select_op_name(SelectOp op) {
  switch (op) {
    case SelectOp::kAll: return "all";
    case SelectOp::kNone: return "none";
    case SelectOp::kInvert: return "invert";
    case SelectOp::kGrow: return "grow";
    case SelectOp::kShrink: return "shrink";
    case SelectOp::kMirror: return "mirror";
  }
  return "?";
}

Workspace::Workspace() {
  add_actions();
  add_stack_actions();
}

void Workspace::set_scene(std::unique_ptr<Scene> scene) {
  move_.reset();
  stroke_.reset();
  mask_stroke_.reset();
  view.mask.painting = false;
  view.mask.driver = -1;
  set_mirror_.reset();
  reset_fidelity();
  scene_ = std::move(scene);
  view.selection = {};
  view.patch.point = -1;
  view.playback = scene_ ? Playback::first_of(scene_->doc().character->clips) : Playback();
  view.soft.radius = 0.1 * scene_size();
  if (scene_ && !scene_->work().layers.empty())
    log("this project has " + std::to_string(deformer_count(scene_->work())) +
        " deformers (outliner: Deformers); the cage is active, the others bind in the background");
}

void Workspace::log(std::string text, bool error) {
  if (!log_.empty() && log_.back().text == text) {
    log_.back().repeats++;
    return;
  }
  std::fprintf(error ? stderr : stdout, "%s\n", text.c_str());
  std::fflush(error ? stderr : stdout);  // the log survives a crash or a kill
  log_.push_back({std::move(text), 1, error});
  if (log_.size() > 500) log_.pop_front();
}

bool Workspace::run(const std::string& line, const std::string& where) {
  where_ = where;
  const auto r = actions.run(line, scene_ != nullptr);
  switch (r.outcome) {
    case ActionTable::Outcome::kBlank: return false;
    case ActionTable::Outcome::kUnknown:
      log("error: " + where + ": unknown command '" + r.name + "' (`cagewrap actions` lists them)", true);
      return false;
    case ActionTable::Outcome::kNeedsDocument:
      log("error: " + where + ": '" + r.name + "' needs an open document", true);
      return false;
    case ActionTable::Outcome::kRan: break;
  }
  if (after_action) after_action(*r.action);
  return true;
}

void Workspace::fail(const std::string& text) { log("error: " + where_ + ": " + text, true); }

void Workspace::report_error(const std::string& message) {
  if (show_error)
    show_error(message);
  else
    log("error: " + message, true);
}

// ---------------------------------------------------------------- selection

IndexSet& Workspace::active_set() {
  switch (view.mode) {
    case SelectMode::kCageFaces: return view.selection.cage_faces;
    case SelectMode::kSkinVertices: return view.selection.skin_vertices;
    case SelectMode::kJoints: return view.selection.joints;
    case SelectMode::kCageVertices: break;
  }
  return view.selection.cage_vertices;
}

uint32_t Workspace::active_count() const {
  if (!scene_) return 0;
  const Cage* cage = scene_->doc().cage.get();
  switch (view.mode) {
    case SelectMode::kCageVertices: return cage ? static_cast<uint32_t>(cage->num_vertices()) : 0;
    case SelectMode::kCageFaces: return cage ? static_cast<uint32_t>(cage->polygons.num_faces()) : 0;
    case SelectMode::kSkinVertices: return static_cast<uint32_t>(scene_->skin_rest.size());
    case SelectMode::kJoints: return static_cast<uint32_t>(scene_->joint_heads.size());
  }
  return 0;
}

void Workspace::edit_selection(SelectOp op) {
  if (!scene_) return;
  IndexSet& s = active_set();
  const uint32_t n = active_count();
  const Cage* cage = scene_->doc().cage.get();
  const SelectMode mode = view.mode;
  const bool cage_mode = mode == SelectMode::kCageVertices || mode == SelectMode::kCageFaces;
  if (cage_mode && !cage) return;
  switch (op) {
    case SelectOp::kAll: s = select_all(n); break;
    case SelectOp::kNone: s.clear(); break;
    case SelectOp::kInvert: s = invert(s, n); break;
    case SelectOp::kGrow:
    case SelectOp::kShrink: {
      const bool grow = op == SelectOp::kGrow;
      if (mode == SelectMode::kCageVertices) s = grow ? grow_vertices(s, cage->polygons) : shrink_vertices(s, cage->polygons);
      else if (mode == SelectMode::kCageFaces) s = grow ? grow_faces(s, cage->polygons) : shrink_faces(s, cage->polygons);
      else if (mode == SelectMode::kSkinVertices) s = grow ? grow_vertices(s, scene_->skin_topology) : shrink_vertices(s, scene_->skin_topology);
      break;
    }
    case SelectOp::kMirror: {
      const double tol = mirror_tolerance();
      if (mode == SelectMode::kCageVertices) s.add(mirror_x(s, cage->polygons.positions, tol).mirrored.indices());
      else if (mode == SelectMode::kSkinVertices) s.add(mirror_x(s, scene_->skin_rest, tol).mirrored.indices());
      else if (mode == SelectMode::kJoints) s.add(mirror_x(s, scene_->joint_heads, tol).mirrored.indices());
      else if (mode == SelectMode::kCageFaces) {
        std::vector<glm::vec3> centroids = face_centroids(cage->polygons.positions);
        s.add(mirror_x(s, centroids, tol).mirrored.indices());
      }
      break;
    }
  }
}

std::vector<glm::vec3> Workspace::face_centroids(std::span<const glm::vec3> positions) const {
  std::vector<glm::vec3> c;
  if (!scene_ || !scene_->doc().cage) return c;
  const PolyMesh& m = scene_->doc().cage->polygons;
  c.reserve(m.num_faces());
  for (size_t f = 0; f < m.num_faces(); ++f) {
    glm::dvec3 sum(0.0);
    for (uint32_t v : m.face(f)) sum += glm::dvec3(positions[v]);
    c.emplace_back(sum / double(std::max<size_t>(1, m.face(f).size())));
  }
  return c;
}

// A cage that is only nearly symmetric (a decimated one) needs about an edge length
// (core/cage/keyposes.h mirror_keypose_set).
double Workspace::rig_mirror_tolerance() const {
  return scene_ && scene_->doc().cage ? std::max(mirror_tolerance(), mean_edge_length(scene_->doc().cage->polygons))
                                      : mirror_tolerance();
}

double Workspace::grid_spacing() const { return std::pow(10.0, std::floor(std::log10(scene_size() / 10.0))); }

// ---------------------------------------------------------------- moves

IndexSet Workspace::move_set() const {
  if (!scene_ || !scene_->doc().cage) return {};
  if (view.mode == SelectMode::kCageVertices) return view.selection.cage_vertices;
  if (view.mode == SelectMode::kCageFaces) return face_vertices(view.selection.cage_faces, scene_->doc().cage->polygons);
  return {};
}

// Measured on the rest cage, so a pose or an earlier sculpt does not change which vertices follow.
Result<MoveWeights> Workspace::move_weights_now() const {
  const Cage& cage = *scene_->doc().cage;
  MirrorParams mirror = view.mirror;
  mirror.tolerance = mirror_tolerance();
  return move_weights(move_set(), cage.polygons.positions, cage.polygons, view.soft, mirror);
}

std::vector<std::pair<uint32_t, float>> Workspace::sim_paint_weights() const {
  std::vector<std::pair<uint32_t, float>> out;
  if (!scene_ || !scene_->doc().cage || move_set().empty()) return out;
  auto w = move_weights_now();
  if (!w) return out;
  for (size_t i = 0; i < w->vertices.size(); ++i) out.emplace_back(w->vertices[i], std::max(w->direct[i], w->mirrored[i]));
  return out;
}

std::optional<glm::dvec3> Workspace::cage_selection_centre() const {
  if (!scene_) return std::nullopt;
  IndexSet s = move_set();
  if (s.empty()) return std::nullopt;
  glm::dvec3 c(0.0);
  for (uint32_t v : s)
    if (v < scene_->cage_posed.size()) c += glm::dvec3(scene_->cage_posed[v]);
  return c / double(s.size());
}

bool Workspace::begin_move(std::optional<Mover> mover) {
  if (!scene_) return false;
  MoveDrag d;
  if (!mover && patch_point_position())  // the parametric driver's control point, not the cage
    mover = Mover{[this](const Document& start, const glm::dvec3& total) { return patch_point_moved(start, total); },
                  "Move control point " + std::to_string(view.patch.point)};
  if (!mover) {
    if (!scene_->doc().cage || move_set().empty()) {
      log("error: nothing to move: select cage vertices or faces", true);
      return false;
    }
    auto w = move_weights_now();
    if (!w.ok()) {
      log("error: " + w.error().message, true);
      return false;
    }
    d.weights = std::move(w).value();
    if (!d.weights.unmatched.empty())
      log("warning: X-mirror: " + std::to_string(d.weights.unmatched.size()) + " selected vertices have no counterpart (first: vertex " +
          std::to_string(d.weights.unmatched.front()) + ")");
  }
  d.mover = std::move(mover);
  d.rest = view.move_rest;
  scene_->begin_drag();
  move_ = std::move(d);
  return true;
}

void Workspace::update_move(const glm::dvec3& total, bool snap) {
  if (!move_ || !scene_) return;
  MoveDrag& d = *move_;
  const Document* start = scene_->drag_start();
  if (!start) return;  // the drag was closed (an undo)
  d.total = snap ? snap_displacement(total, grid_spacing()) : total;
  scene_->drag(d.mover  ? d.mover->moved(*start, d.total)
               : d.rest ? scene_->moved_rest(*start, d.weights, d.total)
                        : scene_->moved(*start, d.weights, d.total));
}

void Workspace::end_move() {
  if (!move_ || !scene_) return;
  const std::string label = move_->mover ? move_->mover->label : move_->rest ? "Move rest cage vertices" : "Move cage vertices";
  // a pose-offset move needs no rebind: the deformer follows the live document already; a rest
  // move re-attaches and registers the reachable points again
  scene_->commit_drag(label, /*refresh=*/move_->rest);
  move_.reset();
}

void Workspace::cancel_move() {
  if (!move_ || !scene_) return;
  scene_->cancel_drag();
  move_.reset();
}

const glm::dvec3& Workspace::move_total() const {
  static const glm::dvec3 zero(0.0);
  return move_ ? move_->total : zero;
}

void Workspace::poll_jobs() {
  if (scene_)
    for (const std::string& m : scene_->poll_stack()) log(m, m.rfind("error", 0) == 0);  // the other deformers' binds
  poll_auto_cage();  // workspace_cage.cpp
  poll_export();     // workspace_export.cpp
  poll_patch();      // workspace_patch.cpp
  poll_fidelity();   // workspace_fidelity.cpp
}

// ---------------------------------------------------------------- undo, posing

void Workspace::undo() {
  if (!scene_) return;
  cancel_move();
  end_set_stroke();
  end_mask_stroke();
  if (std::string label = scene_->undo(); !label.empty()) log(label);
  clip_cage_selection();
}

void Workspace::redo() {
  if (!scene_) return;
  cancel_move();
  end_set_stroke();
  end_mask_stroke();
  if (std::string label = scene_->redo(); !label.empty()) log(label);
  clip_cage_selection();
}

void Workspace::set_pose_override(uint32_t node, const glm::quat& q) {
  if (!scene_) return;
  if (scene_->joint_globals.empty()) update_pose();
  auto& o = view.playback.pose_override;
  if (o.size() < scene_->joint_globals.size()) o.resize(scene_->joint_globals.size(), glm::quat(1, 0, 0, 0));
  if (node < o.size()) o[node] = glm::normalize(q);
}

bool Workspace::select_clip(const std::string& name) {
  if (!scene_) return false;
  const auto& clips = scene_->doc().character->clips;
  Playback& pb = view.playback;
  pb.clip = -1;
  pb.player = ClipPlayer(0.0);
  for (size_t i = 0; i < clips.size(); ++i)
    if (clips[i].name == name) {
      pb.clip = static_cast<int32_t>(i);
      pb.player = ClipPlayer(clips[i].duration);
      return true;
    }
  return name == "rest";
}

void Workspace::update_pose() {
  if (scene_) scene_->update_pose(view.playback);
}

Pose Workspace::current_pose() const { return scene_ ? scene_->current_pose(view.playback) : Pose{}; }

}  // namespace cagewrap::app
