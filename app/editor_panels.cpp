#include "app/editor_window.h"

#include <cstdio>
#include "app/ui_text.h"

#if CAGEWRAP_GUI

namespace cagewrap::app {

// A docked panel: placed every frame, resized by the artist through its free edges (ImGui's window
// borders; the min and max sizes keep the other edges where they are).
ImVec2 Editor::begin_panel(const char* name, ImVec2 pos, ImVec2 size, ImVec2 min, ImVec2 max) {
  ImGui::SetNextWindowPos(pos, ImGuiCond_Always);
  ImGui::SetNextWindowSize(size, ImGuiCond_Always);
  ImGui::SetNextWindowSizeConstraints(min, ImVec2(std::max(min.x, max.x), std::max(min.y, max.y)));
  ImGui::Begin(name, nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoCollapse);
  return ImGui::GetWindowSize();
}

// Made once per character (app/workspace/joint_tree.h).
const JointTree& Editor::outliner_tree(const Character& ch) {
  if (outliner_for_ != &ch) {
    outliner_tree_ = joint_tree(ch);
    outliner_for_ = &ch;
  }
  return outliner_tree_;
}

void Editor::draw_joint_tree(const Character& ch, const JointTree& tree, uint32_t node) {
  const bool leaf = tree.children[node].empty();
  const bool selected = ws_.view.selection.joints.contains(node);
  ImGuiTreeNodeFlags flags = ImGuiTreeNodeFlags_OpenOnArrow | ImGuiTreeNodeFlags_OpenOnDoubleClick | ImGuiTreeNodeFlags_DefaultOpen |
                             ImGuiTreeNodeFlags_SpanAvailWidth;
  if (leaf) flags |= ImGuiTreeNodeFlags_Leaf | ImGuiTreeNodeFlags_NoTreePushOnOpen;
  if (selected) flags |= ImGuiTreeNodeFlags_Selected;
  const bool open = ImGui::TreeNodeEx(reinterpret_cast<void*>(static_cast<uintptr_t>(node) + 1), flags, "%s", ch.skeleton.node(node).name.c_str());
  if (ImGui::IsItemClicked() && !ImGui::IsItemToggledOpen()) {
    uint32_t idx[1] = {node};
    if (ImGui::GetIO().KeyCtrl) ws_.view.selection.joints.toggle(idx);
    else ws_.view.selection.joints.set(idx);
  }
  if (leaf || !open) return;
  for (uint32_t c : tree.children[node]) draw_joint_tree(ch, tree, c);
  ImGui::TreePop();
}

void Editor::draw_outliner() {
  const ImVec2 d = ImGui::GetIO().DisplaySize;
  const float h = d.y - PanelLayout::kMenuHeight - layout_.bottom;
  layout_.left = begin_panel("Outliner", ImVec2(0, PanelLayout::kMenuHeight), ImVec2(layout_.left, h), ImVec2(PanelLayout::kMinPanel, h),
                             ImVec2(d.x - layout_.right - PanelLayout::kMinView, h)).x;
  if (ws_.scene()) {
    const Character& ch = *ws_.scene()->doc().character;
    if (ImGui::TreeNodeEx("Character", ImGuiTreeNodeFlags_DefaultOpen)) {
      ImGui::TextDisabled("%s", std::filesystem::path(ch.source).filename().string().c_str());
      for (const auto& p : ch.primitives) {
        ImGui::Bullet();
        hint("%s: %zu vertices", p.label().c_str(), p.num_vertices());
      }
      ImGui::TreePop();
    }
    draw_deformers();
    const JointTree& tree = outliner_tree(ch);
    if (ImGui::TreeNodeEx("Skeleton", ImGuiTreeNodeFlags_DefaultOpen, "Skeleton (%zu joints)", tree.joints)) {
      if (tree.joints == 0) ImGui::TextDisabled("no joints: the character is not skinned");
      for (uint32_t r : tree.roots) draw_joint_tree(ch, tree, r);
      ImGui::TreePop();
    }
    if (!tree.other_nodes.empty() &&
        ImGui::TreeNodeEx("Other nodes", 0, "Other nodes (%zu)", tree.other_nodes.size())) {
      hint("not joints of any skin: meshes, cameras, lights, groups");
      for (uint32_t n : tree.other_nodes)
        ImGui::BulletText("%s%s", ch.skeleton.node(n).name.c_str(), tree.mesh_node[n] ? " (mesh)" : "");
      ImGui::TreePop();
    }
    if (ImGui::TreeNodeEx("Binding", ImGuiTreeNodeFlags_DefaultOpen)) {
      if (ws_.scene()->binding) ImGui::Text("%s, %u points", variant_name(ws_.scene()->binding->params.variant), ws_.scene()->binding->num_points);
      else ImGui::TextDisabled(ws_.scene()->job ? "binding..." : "not bound");
      ImGui::TreePop();
    }
  }
  ImGui::End();
}

void Editor::update_other_cages() {
  other_cage_segments_.clear();
  const Scene& scene = *ws_.scene();
  for (const StackRig& r : scene.stack_rigs) {
    if (!r.rig || !r.doc.cage || deformer_hidden(scene.work(), r.deformer)) continue;
    const PolyMesh& m = r.doc.cage->polygons;
    if (r.cage.positions.size() != m.positions.size()) continue;  // not posed yet
    for (size_t f = 0; f + 1 < m.face_start.size(); ++f)
      for (uint32_t k = m.face_start[f]; k < m.face_start[f + 1]; ++k) {
        const uint32_t next = k + 1 < m.face_start[f + 1] ? k + 1 : m.face_start[f];
        other_cage_segments_.push_back(r.cage.positions[m.face_vertices[k]]);
        other_cage_segments_.push_back(r.cage.positions[m.face_vertices[next]]);
      }
  }
  renderer_->update_other_cages(other_cage_segments_);
}

// The deformer stack (issue 21): every deformer with its cage, its bind, and its switches; the radio
// button makes it the one edited. Each switch runs the workspace's action (one undo step).
void Editor::draw_deformers() {
  Scene& scene = *ws_.scene();
  const Document& w = scene.work();
  const size_t n = deformer_count(w);
  const size_t nd = driver_count(w);
  if (!ImGui::TreeNodeEx("Deformers", ImGuiTreeNodeFlags_DefaultOpen, "Deformers (%zu%s)", n,
                         nd == 0 ? "" : nd == 1 ? " and a driver" : (" and " + std::to_string(nd) + " drivers").c_str()))
    return;
  for (size_t d = 0; d < n; ++d) {
    ImGui::PushID(static_cast<int>(d));
    const std::string ds = std::to_string(d);
    if (ImGui::RadioButton("##active", scene.active_deformer() == d)) ws_.run("deformer_active " + ds);
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("edit this deformer: selection, gizmo, sets, keyposes and Rebind act on it");
    ImGui::SameLine();
    const bool muted = deformer_muted(w, d);
    const std::string name = deformer_name(w, d);
    if (muted) ImGui::TextDisabled("%s", name.c_str());
    else ImGui::TextUnformatted(name.c_str());
    // its state: the active one's bind is the scene's; the others' are their stack rigs
    std::string state;
    if (d == scene.active_deformer()) {
      state = scene.job ? "binding" : scene.binding ? "bound" : "not bound";
    } else if (muted) {
      state = (w.stack.solo >= 0 && static_cast<size_t>(w.stack.solo) != d) || soloed_driver(w) ? "not soloed" : "muted";
    } else {
      for (const StackRig& r : scene.stack_rigs)
        if (r.deformer == d) state = r.job ? "binding " + std::to_string(int(100 * r.job->progress())) + "%" : r.rig ? "bound" : r.error;
    }
    const Cage* cage = d == 0 ? w.cage.get() : w.layers[d - 1].cage.get();
    hint("%s%s%s", cage ? (std::to_string(cage->num_vertices()) + " vertices, " + std::to_string(cage->polygons.num_faces()) + " faces").c_str() : "no cage",
         state.empty() ? "" : ", ", state.c_str());
    const bool hidden = deformer_hidden(w, d);
    if (ImGui::SmallButton(hidden ? "show" : "hide")) ws_.run("deformer_hide " + ds + (hidden ? " off" : " on"));
    const bool own_mute = d == 0 ? w.stack.base_muted : w.layers[d - 1].muted;
    same_line_for(own_mute ? "unmute" : "mute");
    if (ImGui::SmallButton(own_mute ? "unmute" : "mute")) ws_.run("deformer_mute " + ds + (own_mute ? " off" : " on"));
    const bool solo = w.stack.solo == static_cast<int32_t>(d);
    same_line_for(solo ? "unsolo" : "solo");
    if (ImGui::SmallButton(solo ? "unsolo" : "solo")) ws_.run(solo ? std::string("deformer_solo off") : "deformer_solo " + ds);
    if (d >= 2) {
      same_line_for("up");
      if (ImGui::SmallButton("up")) ws_.run("deformer_move " + ds + " " + std::to_string(d - 1));
    }
    if (d >= 1 && d < n - 1) {
      same_line_for("down");
      if (ImGui::SmallButton("down")) ws_.run("deformer_move " + ds + " " + std::to_string(d + 1));
    }
    if (d >= 1) {
      same_line_for("remove");
      if (ImGui::SmallButton("remove")) ws_.run("deformer_remove " + ds);
      // its skin mask: what it is, and a field to make another (joints a,b,-c | primitives 0,2 | none)
      const DeformerLayer& l = w.layers[d - 1];
      const bool open = ImGui::SmallButton("mask...");
      same_line_for("paint");
      if (ImGui::SmallButton("paint")) {  // the mask brush on this layer (made active: the brush paints the active layer)
        ws_.run("deformer_active " + ds);
        ws_.run("mask_paint on");
      }
      hint("mask: %s", l.mask ? (l.mask_source.empty() ? std::string("painted") : l.mask_source).c_str() : "none");
      if (open) {
        std::snprintf(mask_field_, sizeof mask_field_, "%s", l.mask_source.c_str());
        ImGui::OpenPopup("mask");
      }
      if (ImGui::BeginPopup("mask")) {
        ImGui::TextUnformatted("joints a,b,-c  |  primitives 0,2  |  meshes body  |  none");
        ImGui::InputText("##mask", mask_field_, sizeof mask_field_);
        if (ImGui::Button("Apply")) {
          const std::string source = mask_field_;
          ws_.run("deformer_mask " + ds + " " + (source.empty() ? std::string("none") : source));
          ImGui::CloseCurrentPopup();
        }
        ImGui::EndPopup();
      }
    }
    ImGui::PopID();
    for (size_t i = 0; i < nd; ++i)
      if (driver_position(w, *driver_at(w, i).place) == d) draw_driver_row(i);
  }
  if (n > 1) {
    int mode = static_cast<int>(w.stack.mode);
    const char* modes[] = {"in order", "sum", "blend"};
    ImGui::PushItemWidth(-(ImGui::CalcTextSize("exponent m").x + 2 * ImGui::GetStyle().ItemInnerSpacing.x));
    if (combo("combine", &mode, modes, 3)) ws_.run(std::string("deformer_stack ") + stack_mode_name(static_cast<StackMode>(mode)));
    if (w.stack.mode == StackMode::kBlend) {
      float m = static_cast<float>(w.stack.exponent);
      if (ImGui::InputFloat("exponent m", &m, 0.5f, 1.0f, "%.2f", ImGuiInputTextFlags_EnterReturnsTrue))
        ws_.run("deformer_stack blend " + std::to_string(m));
    }
    ImGui::PopItemWidth();
  }
  bool binding = false, failed = false;
  for (const StackRig& r : scene.stack_rigs) {
    binding |= r.job != nullptr;
    failed |= !r.job && !r.rig;
  }
  for (const DriverRig& r : scene.driver_rigs) {
    binding |= r.job != nullptr;
    failed |= !r.job && !r.layer;
  }
  if (binding) {
    if (ImGui::SmallButton("Cancel binds")) ws_.run("deformer_cancel");
  } else if (failed) {
    if (ImGui::SmallButton("Bind again")) ws_.run("deformer_bind");
  }
  draw_mask_brush();
  if (ImGui::SmallButton("Add a cage as a layer...")) browse(FilePurpose::kAddDeformer);
  if (ImGui::SmallButton("Add a parametric driver...")) browse(FilePurpose::kAddDriver);
  ImGui::TreePop();
}

// The mask brush's settings while it paints (view.mask): its target, the weight it paints toward, its
// strength and radius, fill and done. The skin shows the target's weights (0 blue, 1 orange).
void Editor::draw_mask_brush() {
  ViewState::MaskTool& m = ws_.view.mask;
  if (!m.painting) return;
  const auto t = ws_.mask_target(false);
  if (!t) {
    m.painting = false;
    return;
  }
  ImGui::Separator();
  ImGui::TextWrapped("Painting the mask of %s", t->name.c_str());
  hint("drag on the skin; blue: not moved by it, orange: moved in full");
  ImGui::PushItemWidth(ImGui::GetContentRegionAvail().x * 0.55f);
  ImGui::SliderFloat("toward", &m.value, 0.0f, 1.0f, "%.2f");
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("the weight the brush paints toward: 1 in, 0 out");
  ImGui::SliderFloat("strength", &m.strength, 0.01f, 1.0f, "%.2f");
  if (m.radius <= 0.0) m.radius = 0.03 * ws_.scene()->skin_diagonal;
  float r = static_cast<float>(m.radius);
  const float size = static_cast<float>(ws_.scene()->skin_diagonal);
  if (ImGui::SliderFloat("radius", &r, 1e-3f * size, 0.3f * size, "%.4f", ImGuiSliderFlags_Logarithmic)) m.radius = r;
  ImGui::PopItemWidth();
  if (ImGui::SmallButton("fill 1")) ws_.run("mask_fill 1");
  same_line_for("fill 0");
  if (ImGui::SmallButton("fill 0")) ws_.run("mask_fill 0");
  same_line_for("done");
  if (ImGui::SmallButton("done")) ws_.run("mask_paint off");
  ImGui::Separator();
}

// A parametric driver's row among the deformers (DriverPlacement): its place, mute and state. The first
// (i = 0) is the one the Parametric driver window edits (control points, mask, keyposes); "edit" on another
// makes it the first.
void Editor::draw_driver_row(size_t i) {
  Scene& scene = *ws_.scene();
  const Document& w = scene.work();
  const DriverRef r = driver_at(w, i);
  const PatchDriver& p = *r.driver;
  const DriverPlacement& place = *r.place;
  const size_t pos = driver_position(w, place);
  const std::string is = std::to_string(i);
  ImGui::PushID(("driver" + is).c_str());
  if (ImGui::SmallButton("edit")) ws_.run(i == 0 ? std::string("patch_panel") : "driver_edit " + is);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip(i == 0 ? "edit its control points, mask and keyposes in the Parametric driver window"
                             : "make it the driver the Parametric driver window edits (the skin does not change)");
  ImGui::SameLine();
  const bool moves = driver_moves_skin(w, i);
  const std::string title = "driver '" + driver_name(w, i) + "'";
  if (moves) ImGui::TextUnformatted(title.c_str());
  else ImGui::TextDisabled("%s", title.c_str());
  std::string state;
  if (!p.drive_skin) state = "muted";
  else if (!moves) state = "not soloed";
  else if (i == 0) state = ws_.binding_patch_driver() ? "binding" : scene.driving() ? "bound" : "not bound";
  else {
    state = "not bound";
    for (const DriverRig& d : scene.driver_rigs)
      if (d.index == i)
        state = d.job ? "binding " + std::to_string(int(d.job->progress() * 100)) + "%" : d.layer ? "bound" : d.error;
  }
  if (moves && soloed_driver(w) == i) state += ", soloed";
  const std::string mask = place.mask ? "mask " + (place.mask_source.empty() ? std::string("painted") : place.mask_source) : "no mask";
  std::string attached = place.attachment ? std::string(", attached ") + attachment_mode_name(place.attachment->mode) : "";
  if (!place.set_edits.empty()) attached += ", " + std::to_string(place.set_edits.size()) + " set edits";
  hint("parametric, %zu control points, %zu keypose set%s, %s%s, %s", p.rest.num_control_points(), place.keyposes.size(),
       place.keyposes.size() == 1 ? "" : "s", mask.c_str(), attached.c_str(), state.c_str());
  if (ImGui::SmallButton(place.hidden ? "show" : "hide")) ws_.run("driver_hide " + is + (place.hidden ? " off" : " on"));
  same_line_for(p.drive_skin ? "mute" : "unmute");
  if (ImGui::SmallButton(p.drive_skin ? "mute" : "unmute")) ws_.run("driver_mute " + is + (p.drive_skin ? " on" : " off"));
  const bool soloed = soloed_driver(w) == i;
  same_line_for(soloed ? "unsolo" : "solo");
  if (ImGui::SmallButton(soloed ? "unsolo" : "solo")) ws_.run(soloed ? std::string("driver_solo off") : "driver_solo " + is);
  same_line_for("remove");
  if (ImGui::SmallButton("remove")) ws_.run("driver_remove " + is);
  same_line_for("paint mask");
  if (ImGui::SmallButton("paint mask")) ws_.run("mask_paint on driver " + is);
  // its place among the layers
  if (pos > 0) {
    same_line_for("up");
    if (ImGui::SmallButton("up")) ws_.run("driver_after " + is + " " + std::to_string(pos - 1));
  }
  if (pos < w.layers.size()) {
    same_line_for("down");
    if (ImGui::SmallButton("down"))
      ws_.run("driver_after " + is + " " + (pos + 1 == w.layers.size() ? std::string("last") : std::to_string(pos + 1)));
  }
  ImGui::PopID();
}

void Editor::draw_properties() {
  const ImVec2 d = ImGui::GetIO().DisplaySize;
  const float h = d.y - PanelLayout::kMenuHeight - layout_.bottom;
  // dragging its left edge moves the left edge: the right edge stays at the window's
  layout_.right = begin_panel("Properties", ImVec2(d.x - layout_.right, PanelLayout::kMenuHeight), ImVec2(layout_.right, h),
                              ImVec2(PanelLayout::kMinPanel, h), ImVec2(d.x - layout_.left - PanelLayout::kMinView, h)).x;
  if (ImGui::GetWindowPos().x + layout_.right < d.x - 0.5f) layout_.right = d.x - ImGui::GetWindowPos().x;
  // the fields take what the longest label leaves, so that no label is cut at any panel width
  ImGui::PushItemWidth(-(ImGui::CalcTextSize("K (max elements)").x + 2 * ImGui::GetStyle().ItemInnerSpacing.x));
  draw_move_tool();
  draw_pose_panel();
  if (ws_.scene() && ws_.scene()->doc().cage) {
    BindParams& p = ws_.scene()->params;
    ImGui::TextUnformatted("Binding");
    ImGui::Separator();
    int variant = static_cast<int>(p.variant);
    const char* variants[] = {"basic", "clamped", "extended"};
    if (combo("variant", &variant, variants, 3)) p.variant = static_cast<Variant>(variant);
    float local = static_cast<float>(p.local), eps = static_cast<float>(p.epsilon), scale = static_cast<float>(p.scale),
          maxd = static_cast<float>(p.max_distance);
    int k = static_cast<int>(p.max_elements);
    // live binding (Scene::drag_params): while a slider is held the skin binds with what it shows,
    // on release the values become the document's (one undo step)
    bool dragging = false, released = false;
    auto track = [&] {
      dragging = dragging || ImGui::IsItemActive();
      released = released || ImGui::IsItemDeactivatedAfterEdit();
    };
    if (ImGui::SliderFloat("local", &local, 0.5f, 12.0f, "%.2f")) p.local = local;
    track();
    if (ImGui::SliderFloat("epsilon", &eps, 0.005f, 1.0f, "%.3f", ImGuiSliderFlags_Logarithmic)) p.epsilon = eps;
    track();
    if (ImGui::SliderInt("K (max elements)", &k, 1, 32)) p.max_elements = static_cast<uint32_t>(k);
    track();
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("The most cage elements that drive one skin point");
    if (ImGui::DragFloat("scale h", &scale, 0.001f, 0.0f, 100.0f, scale > 0 ? "%.4f" : "auto")) p.scale = std::max(0.f, scale);
    track();
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("The distance scale of the weights; 0 = auto (from the cage's mean edge length)");
    if (ImGui::DragFloat("max distance", &maxd, 0.001f, 0.0f, 100.0f, maxd > 0 ? "%.4f" : "none")) p.max_distance = std::max(0.f, maxd);
    track();
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("Elements farther than this from a point never drive it; 0 = no limit");
    ImGui::Checkbox("separate unrelated parts", &p.separate);
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("An element drives a point only when the bones they follow are the same or neighbours\n"
                        "(within the steps below): the right thigh's cage does not pull the left thigh");
    int steps = static_cast<int>(p.separation_steps);
    ImGui::BeginDisabled(!p.separate);
    if (ImGui::SliderInt("separation steps", &steps, 0, 4)) p.separation_steps = static_cast<uint32_t>(steps);
    track();
    ImGui::EndDisabled();
    Scene& scene = *ws_.scene();
    if (scene.live_params_possible()) {
      if (dragging) scene.drag_params();
      else if (released || scene.live_params) scene.commit_params();
    }
    if (ws_.scene()->job) {
      ImGui::ProgressBar(static_cast<float>(ws_.scene()->job->progress()), ImVec2(-70, 0), "binding");
      ImGui::SameLine();
      if (ImGui::Button("Cancel")) ws_.scene()->job->cancel();
    } else {
      if (ws_.scene()->needs_rebind()) {
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.75f, 0.2f, 1));
        ImGui::TextWrapped("%s", scene.live_params_possible()
                                     ? "Parameters changed: rebind to apply (sliders apply live while held)"
                                     : "Parameters changed: rebind to apply (sliders apply live on skins up to "
                                       "200,000 points)");
        ImGui::PopStyleColor();
      }
      if (ImGui::Button(ws_.scene()->binding ? "Rebind" : "Bind", ImVec2(-1, 0))) ws_.scene()->rebind();
    }
    if (ws_.scene()->binding) {
      const Binding& b = *ws_.scene()->binding;
      ImGui::Spacing();
      ImGui::TextUnformatted("Result");
      ImGui::Separator();
      ImGui::Text("mean set %.2f, max %u", b.num_points ? double(b.total_set_size) / b.num_points : 0.0, b.max_set_size);
      ImGui::Text("%.1f bytes per skin vertex", double(b.bytes()) / std::max(1u, b.num_points));
      ImGui::Text("cage quality %.1f%%", 100.0 * b.quality());
      if (!b.invalid_elements.empty())
        ImGui::TextColored(ImVec4(1, 0.6f, 0.3f, 1), "%zu elements skipped (see log)", b.invalid_elements.size());
      if (!b.rigid_points.empty())
        ImGui::TextColored(ImVec4(1, 0.6f, 0.3f, 1), "%zu points follow their nearest element", b.rigid_points.size());
      if (b.separation_applied) ImGui::Text("separation kept %zu element-point pairs apart", static_cast<size_t>(b.total_separated));
      ImGui::Text("bound in %.2f s", b.seconds);
      fidelity_panel_.draw(ws_);
    }
  } else if (ws_.scene()) {
    ImGui::TextWrapped("No cage: the skin shows the file's own linear blend skinning. Open with --cage to bind a cage.");
  }
  ImGui::PopItemWidth();
  ImGui::End();
}

// Selection mode buttons along the top of the 3-D view.
void Editor::draw_toolbar() {
  ImGui::SetNextWindowPos(ImVec2(view_x_ + view_w_ - 10, view_y_ + 10), ImGuiCond_Always, ImVec2(1, 0));
  ImGui::SetNextWindowBgAlpha(0.55f);
  ImGui::Begin("toolbar", nullptr, ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoSavedSettings |
                                       ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav);
  toolbar_rect_ = ImVec4(ImGui::GetWindowPos().x, ImGui::GetWindowPos().y, ImGui::GetWindowSize().x, ImGui::GetWindowSize().y);
  const char* labels[] = {"Vertices", "Faces", "Skin", "Joints"};
  const char* tips[] = {"Select cage vertices (F5)", "Select cage faces (F6)", "Select skin vertices (F7)", "Select joints (F8)"};
  for (int k = 0; k < 4; ++k) {
    if (k) ImGui::SameLine();
    const bool on = ws_.view.mode == static_cast<SelectMode>(k);
    if (on) ImGui::PushStyleColor(ImGuiCol_Button, ImVec4(0.85f, 0.5f, 0.1f, 1));
    if (ImGui::Button(labels[k])) ws_.view.mode = static_cast<SelectMode>(k);
    if (on) ImGui::PopStyleColor();
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", tips[k]);
  }
  if (view_w_ >= 900.0f) {  // one row; two in a narrower view, beside the stats rather than over them
    ImGui::SameLine();
    ImGui::TextDisabled("|");
    ImGui::SameLine();
  }
  ImGui::Checkbox("Soft", &ws_.view.soft.enabled);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Soft selection (B); radius with [ and ]");
  ImGui::SameLine();
  ImGui::Checkbox("Mirror X", &ws_.view.mirror.enabled);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("X-mirror editing (Shift+X)");
  ImGui::SameLine();
  ImGui::Checkbox("Edit rest", &ws_.view.move_rest);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("Moves edit the reference (rest) cage: the skin stays, and only the skin points\n"
                      "near the moved vertices are registered again");
  if (ws_.scene()) {
    const IndexSet& s = ws_.active_set();
    ImGui::TextDisabled("%zu %s selected", s.size(), select_mode_name(ws_.view.mode));
  }
  ImGui::End();
}

// Posing: the selected joint's rotation on top of the clip as angles, reset buttons, comparison.
void Editor::draw_pose_panel() {
  if (!ws_.scene()) return;
  if (!ImGui::CollapsingHeader("Pose", ImGuiTreeNodeFlags_DefaultOpen)) return;
  const Character& ch = *ws_.scene()->doc().character;
  if (ws_.view.selection.joints.size() == 1 && ws_.view.selection.joints.indices()[0] < ch.skeleton.size()) {
    const uint32_t j = ws_.view.selection.joints.indices()[0];
    ImGui::Text("%s", ch.skeleton.node(j).name.c_str());
    const auto& o = ws_.view.playback.pose_override;
    const glm::quat q = j < o.size() ? o[j] : glm::quat(1, 0, 0, 0);
    glm::vec3 euler = glm::degrees(glm::eulerAngles(q));
    if (ImGui::DragFloat3("rotate (deg)", &euler.x, 0.5f, -180.0f, 180.0f, "%.1f")) ws_.set_pose_override(j, glm::quat(glm::radians(euler)));
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("About the joint's local X, Y, Z, on top of the clip");
    if (ImGui::Button("Reset joint")) ws_.set_pose_override(j, glm::quat(1, 0, 0, 0));
    ImGui::SameLine();
  } else {
    ImGui::PushTextWrapPos(0.0f);
    ImGui::TextDisabled("Select one joint (F8) to pose it with the rings or here.");
    ImGui::PopTextWrapPos();
  }
  if (ImGui::Button("Reset pose")) ws_.run("reset_pose");
  ImGui::Checkbox("show the file's own skinning (L)", &ws_.view.playback.show_file_skinning);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Compare the cage deformation with the character's linear blend skinning");
  ImGui::Spacing();
}

// Settings of the move tool: soft selection and X-mirror.
void Editor::draw_move_tool() {
  if (!ws_.scene() || !ws_.scene()->doc().cage) return;
  if (!ImGui::CollapsingHeader("Move tool", ImGuiTreeNodeFlags_DefaultOpen)) return;
  ImGui::Checkbox("soft selection (B)", &ws_.view.soft.enabled);
  ImGui::BeginDisabled(!ws_.view.soft.enabled);
  float r = static_cast<float>(ws_.view.soft.radius);
  const float size = static_cast<float>(ws_.scene_size());
  if (ImGui::SliderFloat("radius", &r, 1e-3f * size, size, "%.4f", ImGuiSliderFlags_Logarithmic)) ws_.view.soft.radius = r;
  int falloff = static_cast<int>(ws_.view.soft.falloff);
  const char* falloffs[] = {"smooth", "linear", "sharp", "constant"};
  if (combo("falloff", &falloff, falloffs, 4)) ws_.view.soft.falloff = static_cast<Falloff>(falloff);
  int dist = static_cast<int>(ws_.view.soft.distance);
  const char* dists[] = {"volume (straight line)", "surface (along edges)"};
  if (combo("distance", &dist, dists, 2)) ws_.view.soft.distance = static_cast<FalloffDistance>(dist);
  ImGui::EndDisabled();
  ImGui::Checkbox("X-mirror editing (Shift+X)", &ws_.view.mirror.enabled);
  ImGui::BeginDisabled(!ws_.view.mirror.enabled);
  float tol = static_cast<float>(ws_.view.mirror_tolerance_share * 100.0);
  if (ImGui::SliderFloat("tolerance %", &tol, 0.01f, 2.0f, "%.2f", ImGuiSliderFlags_Logarithmic))
    ws_.view.mirror_tolerance_share = tol / 100.0;
  ImGui::EndDisabled();
  ImGui::TextDisabled("snap step (Ctrl while dragging): %g", ws_.grid_spacing());
  ImGui::Spacing();
}

void Editor::draw_timeline() {
  const ImVec2 d = ImGui::GetIO().DisplaySize;
  const float w = d.x * (1.0f - layout_.log_share), top = d.y - layout_.bottom;
  // its top edge sets the bottom row's height, its right edge the log's share
  const ImVec2 size = begin_panel("Timeline", ImVec2(0, top), ImVec2(w, layout_.bottom), ImVec2(d.x * 0.15f, PanelLayout::kMinBottom),
                                  ImVec2(d.x * 0.85f, d.y - PanelLayout::kMenuHeight - PanelLayout::kMinView * 0.5f));
  if (ImGui::GetWindowPos().y != top) layout_.bottom = d.y - ImGui::GetWindowPos().y;
  layout_.log_share = 1.0f - size.x / d.x;
  if (ws_.scene() && !ws_.scene()->doc().character->clips.empty()) {
    const auto& clips = ws_.scene()->doc().character->clips;
    const int32_t clip = ws_.view.playback.clip;
    const ClipPlayer& pl = ws_.view.playback.player;
    if (ImGui::BeginCombo("clip", clip >= 0 ? clips[static_cast<size_t>(clip)].name.c_str() : "(rest pose)")) {
      if (ImGui::Selectable("(rest pose)", clip < 0)) ws_.select_clip("rest");
      for (size_t i = 0; i < clips.size(); ++i)
        if (ImGui::Selectable(clips[i].name.c_str(), clip == static_cast<int>(i))) {
          const bool playing = pl.playing();  // another clip keeps playing as this one did
          ws_.select_clip(clips[i].name);
          if (playing) ws_.run("play");
        }
      ImGui::EndCombo();
    }
    // the transport runs the action table's play, pause, time and loop, as scripts do
    auto scrub = [&](double t) { ws_.run("time " + std::to_string(t)); };
    if (ImGui::Button("|<")) scrub(0.0);
    ImGui::SameLine();
    if (ImGui::Button("<")) scrub(pl.time() - 1.0 / 30.0);
    ImGui::SameLine();
    if (ImGui::Button(pl.playing() ? "Pause" : "Play", ImVec2(60, 0))) ws_.run(pl.playing() ? "pause" : "play");
    ImGui::SameLine();
    if (ImGui::Button(">")) scrub(pl.time() + 1.0 / 30.0);
    ImGui::SameLine();
    bool loop = pl.looping();
    if (ImGui::Checkbox("loop", &loop)) ws_.run(loop ? "loop on" : "loop off");
    float t = static_cast<float>(pl.time());
    if (ImGui::SliderFloat("time", &t, 0.0f, static_cast<float>(std::max(pl.duration(), 1e-3)), "%.3f s")) scrub(t);
  } else {
    ImGui::TextDisabled("no clips");
  }
  ImGui::End();
}

void Editor::draw_log() {
  const ImVec2 d = ImGui::GetIO().DisplaySize;
  ImGui::SetNextWindowPos(ImVec2(d.x * (1.0f - layout_.log_share), d.y - layout_.bottom), ImGuiCond_Always);
  ImGui::SetNextWindowSize(ImVec2(d.x * layout_.log_share, layout_.bottom), ImGuiCond_Always);
  ImGui::Begin("Log", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
  ImGui::PushTextWrapPos(0.0f);  // long paths wrap instead of running off the panel
  for (const auto& l : ws_.log_lines()) {
    ImVec4 c = l.error ? ImVec4(1, 0.4f, 0.35f, 1) : (l.text.rfind("warning", 0) == 0 ? ImVec4(1, 0.8f, 0.3f, 1) : ImVec4(0.85f, 0.85f, 0.85f, 1));
    if (l.repeats > 1) ImGui::TextColored(c, "%s (and %d similar)", l.text.c_str(), l.repeats - 1);
    else ImGui::TextColored(c, "%s", l.text.c_str());
  }
  ImGui::PopTextWrapPos();
  if (ImGui::GetScrollY() >= ImGui::GetScrollMaxY()) ImGui::SetScrollHereY(1.0f);
  ImGui::End();
  if (!error_modal_.empty()) {
    ImGui::OpenPopup("Error");
    if (ImGui::BeginPopupModal("Error", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
      ImGui::TextUnformatted(error_modal_.c_str());
      ImGui::TextDisabled("The current document is unchanged.");
      if (ImGui::Button("OK", ImVec2(120, 0)) || std::exchange(script_error_ok_, false)) {
        error_modal_.clear();
        ImGui::CloseCurrentPopup();
      }
      ImGui::EndPopup();
    }
  }
}

void Editor::draw_stats() {
  ImGuiIO& io = ImGui::GetIO();
  // top left of the view; below the toolbar (top right) when the view is too narrow for both
  const bool overlap = view_x_ + 10 + stats_width_ + 10 > toolbar_rect_.x;
  ImGui::SetNextWindowPos(ImVec2(view_x_ + 10, overlap ? toolbar_rect_.y + toolbar_rect_.w + 6 : view_y_ + 10), ImGuiCond_Always);
  ImGui::SetNextWindowBgAlpha(0.35f);
  ImGui::Begin("stats", nullptr, ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoInputs |
                                     ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav);
  if (!ws_.scene()) ImGui::Text("%.0f fps", fps_);
  if (ws_.scene()) {
    ImGui::Text("skin %zu vertices", ws_.scene()->skin_rest.size());
    if (ws_.scene()->doc().cage) ImGui::Text("cage %zu vertices, %zu faces", ws_.scene()->doc().cage->num_vertices(), ws_.scene()->doc().cage->polygons.num_faces());
    skin_display_.draw_stats(*ws_.scene());
  }
  (void)io;
  stats_width_ = ImGui::GetWindowSize().x;
  ImGui::End();
}

void Editor::draw_help() {
  if (!show_help_) return;
  ImGui::Begin("Shortcuts", &show_help_, ImGuiWindowFlags_AlwaysAutoResize);
  const char* rows[][2] = {{"Alt+LMB drag / RMB drag", "orbit"},
                           {"MMB drag (Alt optional)", "pan"},
                           {"wheel / Alt+RMB drag", "zoom"},
                           {"F", "frame everything"},
                           {"1 / 3 / 7 (numpad too)", "front / side / top view (Ctrl: opposite)"},
                           {"F5 F6 F7 F8", "select cage vertices / cage faces / skin vertices / joints"},
                           {"click, drag a box", "select (Shift adds, Ctrl removes)"},
                           {"Ctrl+A / Esc / Ctrl+I", "select all / none / invert"},
                           {"Num+ Num- (or . ,)", "grow / shrink selection"},
                           {"Ctrl+M", "add the mirror (X) of the selection"},
                           {"gizmo: arrow / square / centre", "move along an axis / in a plane / in the view"},
                           {"Ctrl while dragging", "snap to the grid"},
                           {"B, [ ]", "soft selection on/off, smaller/larger radius"},
                           {"Shift+X", "X-mirror editing on/off"},
                           {"Ctrl+Z / Ctrl+Shift+Z, Ctrl+Y", "undo / redo"},
                           {"Ctrl+O / Ctrl+S / Ctrl+Q", "open / save / quit"},
                           {"F12", "screenshot"},                           {"L", "show the file's own skinning"},                   {"C", "colour the cage by bone (joint mode: the selected joints' vertices light up)"},
                           {"Space", "play / pause"},
                           {"W", "wireframe"},
                           {"Alt+X", "X-ray"},
                           {"F1", "this window"}};
  for (auto& r : rows) {
    ImGui::TextUnformatted(r[0]);
    ImGui::SameLine(250);
    ImGui::TextDisabled("%s", r[1]);
  }
  ImGui::End();
}

}  // namespace cagewrap::app

#endif
