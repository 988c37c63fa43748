#include "app/editor_window.h"

#if CAGEWRAP_GUI

namespace cagewrap::app {

// Rebuilds the per-vertex display of the selection (soft weights, face and joint masks) when the
// selection, the tool settings or the cage changed.
void Editor::update_selection_display() {
  const Cage* cage = ws_.scene()->doc().cage.get();
  const SoftSelectionParams& soft = ws_.view.soft;
  SelectionDisplayKey key{ws_.scene()->doc().cage,
                          ws_.view.mode,
                          soft.enabled,
                          soft.radius,
                          soft.falloff,
                          soft.distance,
                          ws_.view.mirror.enabled,
                          ws_.view.mirror_tolerance_share,
                          ws_.view.selection.cage_vertices,
                          ws_.view.selection.cage_faces,
                          ws_.view.selection.joints,
                          sim_panel_.visible() ? ws_.scene()->doc().revision : 0,
                          color_by_bone_,
                          ws_.scene()->attachment_revision};
  if (display_key_ && *display_key_ == key) return;
  display_key_ = std::move(key);
  // the cage coloured by the bone each vertex follows; in joint mode the selected joints' vertices
  // are highlighted
  bone_colors_.clear();
  if (cage && ws_.scene()->attachment && ws_.scene()->attachment->joint.size() == cage->num_vertices()) {
    const Character& ch = *ws_.scene()->doc().character;
    const auto& joints = ch.skins[ws_.scene()->attachment->skin].joints;
    if (color_by_bone_) {
      bone_colors_.resize(cage->num_vertices());
      for (size_t v = 0; v < bone_colors_.size(); ++v) {
        const double hue = std::fmod(0.618033988749895 * ws_.scene()->attachment->joint[v], 1.0) * 6.0;
        const double x = 1.0 - std::abs(std::fmod(hue, 2.0) - 1.0);
        glm::vec3 rgb = hue < 1 ? glm::vec3(1, x, 0) : hue < 2 ? glm::vec3(x, 1, 0) : hue < 3 ? glm::vec3(0, 1, x)
                      : hue < 4 ? glm::vec3(0, x, 1) : hue < 5 ? glm::vec3(x, 0, 1) : glm::vec3(1, 0, x);
        bone_colors_[v] = glm::vec4(0.25f + 0.7f * rgb, 1.0f);
      }
    }
    if (sim_panel_.visible()) bone_colors_ = SimPanel::vertex_colors(ws_.scene()->doc().sim, cage->num_vertices());
    if (ws_.view.mode == SelectMode::kJoints && !ws_.view.selection.joints.empty()) {
      cage_weights_.assign(cage->num_vertices(), 0.0f);
      for (size_t v = 0; v < cage_weights_.size(); ++v) {
        const uint32_t j = ws_.scene()->attachment->joint[v];
        if (j < joints.size() && ws_.view.selection.joints.contains(joints[j])) cage_weights_[v] = 1.0f;
      }
    }
  }
  if (ws_.view.mode == SelectMode::kJoints && !ws_.view.selection.joints.empty() && !cage_weights_.empty()) {
    face_mask_.clear();
    joint_mask_.assign(ws_.scene()->joint_heads.size(), 0);
    for (uint32_t j : ws_.view.selection.joints)
      if (j < joint_mask_.size()) joint_mask_[j] = 1;
    return;
  }
  cage_weights_.clear();
  face_mask_.clear();
  if (cage) {
    auto w = ws_.move_weights_now();
    if (w.ok()) cage_weights_ = w.value().dense(cage->num_vertices());
    if (ws_.view.mode != SelectMode::kCageFaces)  // the vertex selection stays visible in the other modes
      for (uint32_t v : ws_.view.selection.cage_vertices)
        if (v < cage_weights_.size()) cage_weights_[v] = std::max(cage_weights_[v], 1.0f);
    face_mask_.assign(cage->polygons.num_faces(), 0);
    for (uint32_t f : ws_.view.selection.cage_faces)
      if (f < face_mask_.size()) face_mask_[f] = 1;
  }
  joint_mask_.assign(ws_.scene()->joint_heads.size(), 0);
  for (uint32_t j : ws_.view.selection.joints)
    if (j < joint_mask_.size()) joint_mask_[j] = 1;
}

glm::dvec2 Editor::to_view(const ImVec2& p) const { return {p.x - view_x_, p.y - view_y_}; }

bool Editor::in_view(const ImVec2& p) const {
  return p.x >= view_x_ && p.y >= view_y_ && p.x < view_x_ + view_w_ && p.y < view_y_ + view_h_;
}

std::optional<glm::dvec3> Editor::selection_centre() const {
  if (auto p = ws_.patch_point_position()) return p;  // a parametric driver's control point
  return ws_.cage_selection_centre();
}

GizmoLayout Editor::gizmo() const {
  auto c = selection_centre();
  if (!c) return {};
  return gizmo_layout(ws_.view.camera, Viewport{view_w_, view_h_},
                      drag_handle_ != GizmoHandle::kNone ? drag_centre_ + ws_.move_total() : *c);
}

// The gizmo's drag is the workspace's move (one undo step); Ctrl snaps to the grid.
void Editor::apply_move(const glm::dvec3& total) { ws_.update_move(total, ImGui::GetIO().KeyCtrl); }

bool Editor::begin_move(GizmoHandle handle, glm::dvec2 from) {
  const glm::dvec3 centre = selection_centre().value_or(glm::dvec3(0.0));
  if (!ws_.begin_move()) return false;  // the cage selection, or the parametric driver's control point
  drag_handle_ = handle;
  drag_from_ = from;
  drag_centre_ = centre;
  return true;
}

void Editor::end_move() {
  ws_.end_move();
  drag_handle_ = GizmoHandle::kNone;
}

const TriangleBvh& Editor::skin_occluder() {
  if (!skin_bvh_built_) {
    skin_bvh_ = TriangleBvh(ws_.scene()->skin_posed(), ws_.scene()->skin_triangles());
    skin_bvh_built_ = true;
  } else {
    skin_bvh_.refit(ws_.scene()->skin_posed());
  }
  return skin_bvh_;
}

// Click: replace, shift adds, ctrl removes. In cage-vertex mode a click that misses every vertex
// may still pick a joint (the skeleton is drawn on top).
void Editor::click_select(const ImVec2& mouse, bool add, bool remove) {
  Viewport vp{view_w_, view_h_};
  glm::dvec2 px = to_view(mouse);
  std::optional<uint32_t> hit;
  // a parametric driver's control point (or sample, with its sample tool), while its window is open
  if (patch_panel_.pick(ws_, ws_.view.camera, vp, px, add, remove)) return;
  if (!add && !remove) ws_.view.patch.point = -1;
  IndexSet* set = &ws_.active_set();
  switch (ws_.view.mode) {
    case SelectMode::kCageVertices:
      if (ws_.scene()->doc().cage && style_.show_cage) hit = pick_vertex(ws_.view.camera, vp, px, ws_.scene()->cage_posed, 8.0);
      if (!hit && style_.show_skeleton && (hit = pick_joint(ws_.view.camera, vp, px, ws_.scene()->joint_heads, 8.0))) set = &ws_.view.selection.joints;
      break;
    case SelectMode::kCageFaces:
      if (ws_.scene()->doc().cage && style_.show_cage) {
        cage_picker_.refit(ws_.scene()->cage_posed);
        if (auto f = cage_picker_.pick(ws_.view.camera.ray(px.x, px.y, vp.width, vp.height))) hit = f->face;
      }
      break;
    case SelectMode::kSkinVertices:
      if (style_.show_skin) hit = pick_vertex(ws_.view.camera, vp, px, ws_.scene()->skin_posed(), 8.0, style_.xray ? nullptr : &skin_occluder());
      break;
    case SelectMode::kJoints:
      if (style_.show_skeleton) hit = pick_joint(ws_.view.camera, vp, px, ws_.scene()->joint_heads, 8.0);
      break;
  }
  if (hit) {
    uint32_t idx[1] = {*hit};
    if (remove) set->remove(idx);
    else if (add) set->add(idx);
    else {
      if (set != &ws_.active_set()) ws_.active_set().clear();
      set->set(idx);
    }
    return;
  }
  if (!add && !remove) {
    ws_.active_set().clear();
    if (ws_.view.mode == SelectMode::kCageVertices) ws_.view.selection.joints.clear();
  }
}

void Editor::box_select_in_mode(const ImVec2& a, const ImVec2& b, bool add, bool remove) {
  Viewport vp{view_w_, view_h_};
  std::vector<uint32_t> hits;
  switch (ws_.view.mode) {
    case SelectMode::kCageVertices:
      if (ws_.scene()->doc().cage) hits = box_select(ws_.view.camera, vp, to_view(a), to_view(b), ws_.scene()->cage_posed);
      break;
    case SelectMode::kCageFaces:
      if (ws_.scene()->doc().cage) hits = box_select(ws_.view.camera, vp, to_view(a), to_view(b), ws_.face_centroids(ws_.scene()->cage_posed));
      break;
    case SelectMode::kSkinVertices:
      hits = box_select(ws_.view.camera, vp, to_view(a), to_view(b), ws_.scene()->skin_posed(), style_.xray ? nullptr : &skin_occluder());
      break;
    case SelectMode::kJoints:
      hits = box_select(ws_.view.camera, vp, to_view(a), to_view(b), ws_.scene()->joint_heads);
      break;
  }
  IndexSet& s = ws_.active_set();
  if (remove) s.remove(hits);
  else if (add) s.add(hits);
  else s.set(hits);
}

void Editor::handle_input() {
  ImGuiIO& io = ImGui::GetIO();
  const bool over_view = in_view(io.MousePos) && !io.WantCaptureMouse;
  if (ws_.scene() && ws_.set_stroking()) {  // a set-edit brush stroke in progress
    if (!io.MouseDown[0]) {
      ws_.end_set_stroke();
    } else if (io.MouseDelta.x != 0 || io.MouseDelta.y != 0) {
      paint_dab(io.MousePos);
    }
    return;
  }
  if (ws_.scene() && ws_.mask_stroking()) {  // a mask brush stroke in progress
    if (!io.MouseDown[0]) ws_.end_mask_stroke();
    else if (io.MouseDelta.x != 0 || io.MouseDelta.y != 0) mask_dab(io.MousePos);
    return;
  }
  if (ws_.scene() && over_view && !io.KeyAlt && ImGui::IsMouseClicked(0) && ws_.view.mask.painting) {
    ws_.begin_mask_stroke();
    mask_dab(io.MousePos);
    return;
  }
  if (ws_.scene() && over_view && !io.KeyAlt && ImGui::IsMouseClicked(0) && sets_panel_.painting() && ws_.view.mode == SelectMode::kSkinVertices) {
    ws_.begin_set_stroke();
    paint_dab(io.MousePos);
    return;
  }
  if (ws_.scene() && rot_handle_ != RotateHandle::kNone) {  // a joint rotation in progress
    if (!io.MouseDown[0]) {
      rot_handle_ = RotateHandle::kNone;
    } else if (io.MouseDelta.x != 0 || io.MouseDelta.y != 0) {
      auto a = rotate_gizmo_angle(ws_.view.camera, Viewport{view_w_, view_h_}, rot_layout_, rot_handle_, rot_from_, to_view(io.MousePos));
      if (a) apply_rotate(*a);
    }
    return;
  }
  if (ws_.scene() && drag_handle_ != GizmoHandle::kNone) {  // a gizmo drag in progress
    if (!io.MouseDown[0]) {
      end_move();
    } else if (io.MouseDelta.x != 0 || io.MouseDelta.y != 0) {
      auto d = gizmo_drag(ws_.view.camera, Viewport{view_w_, view_h_}, drag_handle_, drag_centre_, drag_from_, to_view(io.MousePos));
      if (d) apply_move(*d);
    }
    return;
  }
  if (over_view && ws_.scene()) {
    const bool alt = io.KeyAlt;
    const glm::dvec2 d(io.MouseDelta.x, io.MouseDelta.y);
    if (alt && io.MouseDown[1]) ws_.view.camera.zoom(-0.02 * d.y);
    else if ((alt && io.MouseDown[0]) || io.MouseDown[1]) ws_.view.camera.orbit(d.x, d.y);
    else if (io.MouseDown[2]) ws_.view.camera.pan(d.x, d.y, view_h_);
    if (io.MouseWheel != 0) ws_.view.camera.zoom(io.MouseWheel);
    if (!alt && ImGui::IsMouseClicked(0)) {
      const GizmoHandle hit = gizmo_hit(gizmo(), to_view(io.MousePos));
      const RotateHandle ring = rotate_gizmo_hit(rotate_gizmo(), to_view(io.MousePos));
      if (ring != RotateHandle::kNone) {
        begin_rotate(ring, to_view(io.MousePos));
      } else if (hit != GizmoHandle::kNone) {
        begin_move(hit, to_view(io.MousePos));
      } else {
        box_selecting_ = true;
        box_start_ = io.MousePos;
      }
    }
  }
  if (box_selecting_ && !io.MouseDown[0]) {
    box_selecting_ = false;
    ImVec2 m = io.MousePos;
    const bool add = io.KeyShift, remove = io.KeyCtrl;
    if (!ws_.scene()) return;
    if (std::abs(m.x - box_start_.x) < 4 && std::abs(m.y - box_start_.y) < 4) click_select(m, add, remove);
    else box_select_in_mode(box_start_, m, add, remove);
  }
  if (!io.WantCaptureKeyboard && ws_.scene()) {
    const bool ctrl = io.KeyCtrl, shift = io.KeyShift;
    if (ctrl && ImGui::IsKeyPressed(GLFW_KEY_Z)) ws_.run(shift ? "redo" : "undo");
    if (ctrl && ImGui::IsKeyPressed(GLFW_KEY_Y)) ws_.run("redo");
    if (ctrl && ImGui::IsKeyPressed(GLFW_KEY_S)) request_save();
    if (ctrl && ImGui::IsKeyPressed(GLFW_KEY_O)) open_open_popup_ = true;
    if (ctrl && ImGui::IsKeyPressed(GLFW_KEY_Q)) quit_requested_ = true;
    if (ctrl && ImGui::IsKeyPressed(GLFW_KEY_A)) ws_.run(std::string("select ") + select_op_name(SelectOp::kAll));
    if (ctrl && ImGui::IsKeyPressed(GLFW_KEY_I)) ws_.run(std::string("select ") + select_op_name(SelectOp::kInvert));
    if (ctrl && ImGui::IsKeyPressed(GLFW_KEY_M)) ws_.run(std::string("select ") + select_op_name(SelectOp::kMirror));
    if (!ctrl && (ImGui::IsKeyPressed(GLFW_KEY_KP_ADD) || ImGui::IsKeyPressed(GLFW_KEY_PERIOD))) ws_.run(std::string("select ") + select_op_name(SelectOp::kGrow));
    if (!ctrl && (ImGui::IsKeyPressed(GLFW_KEY_KP_SUBTRACT) || ImGui::IsKeyPressed(GLFW_KEY_COMMA))) ws_.run(std::string("select ") + select_op_name(SelectOp::kShrink));
    if (ImGui::IsKeyPressed(GLFW_KEY_ESCAPE)) ws_.run(std::string("select ") + select_op_name(SelectOp::kNone));
    for (int k = 0; k < 4; ++k)
      if (ImGui::IsKeyPressed(GLFW_KEY_F5 + k)) ws_.view.mode = static_cast<SelectMode>(k);
    if (!ctrl && ImGui::IsKeyPressed(GLFW_KEY_B)) ws_.view.soft.enabled = !ws_.view.soft.enabled;
    if (ImGui::IsKeyPressed(GLFW_KEY_LEFT_BRACKET)) ws_.view.soft.radius = std::max(ws_.view.soft.radius / 1.25, 1e-4 * ws_.scene_size());
    if (ImGui::IsKeyPressed(GLFW_KEY_RIGHT_BRACKET)) ws_.view.soft.radius = std::min(ws_.view.soft.radius * 1.25, 2.0 * ws_.scene_size());
    if (shift && !ctrl && ImGui::IsKeyPressed(GLFW_KEY_X)) ws_.view.mirror.enabled = !ws_.view.mirror.enabled;
    if (!ctrl && ImGui::IsKeyPressed(GLFW_KEY_F)) frame_all();
    if (ImGui::IsKeyPressed(GLFW_KEY_SPACE)) ws_.run(ws_.view.playback.player.playing() ? "pause" : "play");
    if (ImGui::IsKeyPressed(GLFW_KEY_KP_1) || ImGui::IsKeyPressed(GLFW_KEY_1)) ws_.view.camera.set_preset(ctrl ? ViewPreset::kBack : ViewPreset::kFront);
    if (ImGui::IsKeyPressed(GLFW_KEY_KP_3) || ImGui::IsKeyPressed(GLFW_KEY_3)) ws_.view.camera.set_preset(ctrl ? ViewPreset::kLeft : ViewPreset::kRight);
    if (ImGui::IsKeyPressed(GLFW_KEY_KP_7) || ImGui::IsKeyPressed(GLFW_KEY_7)) ws_.view.camera.set_preset(ctrl ? ViewPreset::kBottom : ViewPreset::kTop);
    if (ImGui::IsKeyPressed(GLFW_KEY_L) && !ctrl) ws_.run(ws_.view.playback.show_file_skinning ? "file_skinning off" : "file_skinning on");
    if (ImGui::IsKeyPressed(GLFW_KEY_C) && !ctrl) color_by_bone_ = !color_by_bone_;
    if (ImGui::IsKeyPressed(GLFW_KEY_K) && !ctrl) rig_panel_.visible() = !rig_panel_.visible();
    if (ImGui::IsKeyPressed(GLFW_KEY_J) && !ctrl) sets_panel_.visible() = !sets_panel_.visible();
    if (ImGui::IsKeyPressed(GLFW_KEY_W) && !ctrl) style_.wireframe = !style_.wireframe;
    if (ImGui::IsKeyPressed(GLFW_KEY_X) && io.KeyAlt) style_.xray = !style_.xray;
    if (ImGui::IsKeyPressed(GLFW_KEY_F1)) show_help_ = !show_help_;
  }
}

// One brush dab where the mouse ray meets the skin.
void Editor::paint_dab(const ImVec2& mouse) {
  const glm::dvec2 px = to_view(mouse);
  const Ray ray = ws_.view.camera.ray(px.x, px.y, view_w_, view_h_);
  if (auto hit = pick_triangle(ray, skin_occluder())) {
    const glm::dvec3 at = ray.at(hit->t);
    if (sets_panel_.screen_radius()) {  // pixels -> scene units at the hit's depth
      const ScreenPoint sp = ws_.view.camera.project(at, view_w_, view_h_);
      const double depth = ws_.view.camera.mode() == ProjectionMode::kPerspective ? sp.view_depth / ws_.view.camera.distance() : 1.0;
      ws_.view.sets.brush_radius = sets_panel_.radius_pixels() * ws_.view.camera.world_per_pixel(view_h_) * depth;
    }
    ws_.set_stroke_dab(hit->triangle, at);
  }
}

// One mask brush dab where the mouse ray meets the skin.
void Editor::mask_dab(const ImVec2& mouse) {
  const glm::dvec2 px = to_view(mouse);
  const Ray ray = ws_.view.camera.ray(px.x, px.y, view_w_, view_h_);
  if (auto hit = pick_triangle(ray, skin_occluder())) ws_.mask_stroke_dab(hit->triangle, ray.at(hit->t));
}

// The joint the rotation gizmo acts on: the one selected joint in joint mode.
int Editor::posed_joint() const {
  if (!ws_.scene() || ws_.view.mode != SelectMode::kJoints || ws_.view.selection.joints.size() != 1) return -1;
  const uint32_t j = ws_.view.selection.joints.indices()[0];
  return j < ws_.scene()->joint_globals.size() ? static_cast<int>(j) : -1;
}

RotateGizmoLayout Editor::rotate_gizmo() const {
  const int j = posed_joint();
  if (j < 0) return {};
  if (rot_handle_ != RotateHandle::kNone) return rot_layout_;
  const glm::mat4& g = ws_.scene()->joint_globals[static_cast<size_t>(j)];
  const glm::dmat3 axes{glm::dvec3(g[0]), glm::dvec3(g[1]), glm::dvec3(g[2])};
  return rotate_gizmo_layout(ws_.view.camera, Viewport{view_w_, view_h_}, glm::dvec3(g[3]), axes);
}

void Editor::begin_rotate(RotateHandle handle, glm::dvec2 from) {
  const int j = posed_joint();
  if (j < 0) return;
  rot_layout_ = rotate_gizmo();
  rot_handle_ = handle;
  rot_from_ = from;
  rot_angle_ = 0.0;
  const auto& o = ws_.view.playback.pose_override;
  rot_start_ = static_cast<size_t>(j) < o.size() ? o[static_cast<size_t>(j)] : glm::quat(1, 0, 0, 0);
  // local = clip * override and global = parent * local: turning the joint by angle a about a world
  // axis w is override' = override * angleAxis(a, inverse(global rotation) * w)
  const glm::mat4& g = ws_.scene()->joint_globals[static_cast<size_t>(j)];
  const glm::mat3 rot(glm::normalize(glm::vec3(g[0])), glm::normalize(glm::vec3(g[1])), glm::normalize(glm::vec3(g[2])));
  const glm::vec3 w(rotate_handle_axis(ws_.view.camera, rot_layout_, handle));
  rot_local_axis_ = glm::normalize(glm::transpose(rot) * w);
}

void Editor::apply_rotate(double angle) {
  const int j = posed_joint();
  if (j < 0) return;
  if (ImGui::GetIO().KeyCtrl) angle = snap_angle(angle, glm::radians(5.0));
  rot_angle_ = angle;
  ws_.set_pose_override(static_cast<uint32_t>(j), rot_start_ * glm::angleAxis(static_cast<float>(angle), rot_local_axis_));
}

void Editor::draw_gizmo() {
  ImDrawList* dl = ImGui::GetForegroundDrawList();
  if (box_selecting_) {
    ImVec2 m = ImGui::GetIO().MousePos;
    dl->AddRectFilled(box_start_, m, IM_COL32(255, 160, 40, 40));
    dl->AddRect(box_start_, m, IM_COL32(255, 160, 40, 200));
  }
  if (!ws_.scene()) return;
  if (ws_.scene()->doc().cage) {  // a selected skin point's member faces, labelled with their weights
    const PolyMesh& m = ws_.scene()->doc().cage->polygons;
    for (auto [f, w] : sets_panel_.member_face_weights(*ws_.scene(), ws_.view.selection)) {
      if (f >= m.num_faces()) continue;
      glm::dvec3 c(0.0);
      for (uint32_t v : m.face(f)) c += glm::dvec3(ws_.scene()->cage_posed[v]);
      const ScreenPoint sp = ws_.view.camera.project(c / double(m.face(f).size()), view_w_, view_h_);
      if (!sp.in_clip_range) continue;
      char buf[16];
      std::snprintf(buf, sizeof buf, "%.2f", w);
      const ImVec2 at(view_x_ + static_cast<float>(sp.pixel.x) - 12, view_y_ + static_cast<float>(sp.pixel.y) - 7);
      dl->AddRectFilled(ImVec2(at.x - 2, at.y - 1), ImVec2(at.x + 30, at.y + 14), IM_COL32(20, 20, 20, 170), 3.0f);
      dl->AddText(at, IM_COL32(255, 220, 120, 255), buf);
    }
  }
  if (const RotateGizmoLayout r = rotate_gizmo(); r.visible) {
    const ImVec2 o(view_x_, view_y_);
    auto at = [&](glm::dvec2 p) { return ImVec2(o.x + static_cast<float>(p.x), o.y + static_cast<float>(p.y)); };
    const ImU32 colours[3] = {IM_COL32(235, 70, 70, 255), IM_COL32(90, 220, 90, 255), IM_COL32(80, 130, 255, 255)};
    for (int k = 0; k < 3; ++k) {
      const bool on = static_cast<int>(rot_handle_) == k;
      const size_t n = r.rings[k].size();
      for (size_t i = 0; i < n; ++i) {
        const size_t i2 = (i + 1) % n;
        const bool front = r.front[k][i] && r.front[k][i2];
        const ImU32 c = on ? IM_COL32(255, 230, 80, 255) : (front ? colours[k] : (colours[k] & 0x00FFFFFF) | 0x50000000);
        dl->AddLine(at(r.rings[k][i]), at(r.rings[k][i2]), c, front ? 2.5f : 1.0f);
      }
    }
    for (size_t i = 0; i < r.view_ring.size(); ++i)
      dl->AddLine(at(r.view_ring[i]), at(r.view_ring[(i + 1) % r.view_ring.size()]),
                  rot_handle_ == RotateHandle::kView ? IM_COL32(255, 230, 80, 255) : IM_COL32(220, 220, 220, 160), 1.5f);
    if (rot_handle_ != RotateHandle::kNone) {
      char buf[48];
      std::snprintf(buf, sizeof buf, "%+.1f deg", glm::degrees(rot_angle_));
      dl->AddText(ImVec2(at(r.centre).x + 14, at(r.centre).y + 12), IM_COL32(255, 255, 255, 230), buf);
    }
    return;
  }
  const GizmoLayout g = gizmo();
  if (!g.visible) return;
  const ImU32 active = IM_COL32(255, 230, 80, 255);
  const ImU32 colours[3] = {IM_COL32(235, 70, 70, 255), IM_COL32(90, 220, 90, 255), IM_COL32(80, 130, 255, 255)};
  const ImVec2 o(view_x_, view_y_);
  auto at = [&](glm::dvec2 p) { return ImVec2(o.x + static_cast<float>(p.x), o.y + static_cast<float>(p.y)); };
  for (int p = 0; p < 3; ++p) {  // plane squares, coloured by their normal axis
    const bool on = static_cast<int>(drag_handle_) == 3 + p;
    ImVec2 q[4];
    for (int k = 0; k < 4; ++k) q[k] = at(g.plane[p][k]);
    dl->AddConvexPolyFilled(q, 4, on ? IM_COL32(255, 230, 80, 150) : (colours[p] & 0x00FFFFFF) | 0x60000000);
    dl->AddPolyline(q, 4, on ? active : colours[p], ImDrawFlags_Closed, 1.5f);
  }
  for (int a = 0; a < 3; ++a) {
    const bool on = static_cast<int>(drag_handle_) == a;
    dl->AddLine(at(g.centre), at(g.axis_end[a]), on ? active : colours[a], 3.0f);
    dl->AddCircleFilled(at(g.axis_end[a]), 5.0f, on ? active : colours[a]);
  }
  const ImVec2 c = at(g.centre);
  dl->AddRect(ImVec2(c.x - 6, c.y - 6), ImVec2(c.x + 6, c.y + 6), drag_handle_ == GizmoHandle::kScreen ? active : IM_COL32(230, 230, 230, 255), 0, 0, 2.0f);
  if (drag_handle_ != GizmoHandle::kNone) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%+.4f %+.4f %+.4f", ws_.move_total().x, ws_.move_total().y, ws_.move_total().z);
    dl->AddText(ImVec2(c.x + 12, c.y + 10), IM_COL32(255, 255, 255, 230), buf);
  }
  if (ws_.view.soft.enabled) {  // the soft radius as a circle at the centre's depth
    const double px = ws_.view.soft.radius / std::max(g.world_length / kGizmoAxisPixels, 1e-12);
    dl->AddCircle(c, static_cast<float>(px), IM_COL32(255, 240, 90, 110), 64, 1.0f);
  }
}

}  // namespace cagewrap::app

#endif
