#include "app/patch_panel.h"
#include "app/ui_text.h"

#include <algorithm>
#include <vector>

#if CAGEWRAP_GUI
#include <imgui/imgui.h>
#endif

namespace cagewrap::app {

namespace {
std::vector<glm::vec3> float_points(const PatchSurface& surface) {
  std::vector<glm::vec3> points;
  for (const glm::dvec3& p : surface.control_points()) points.push_back(glm::vec3(p));
  return points;
}
}  // namespace

bool PatchPanel::pick(Workspace& ws, const Camera& camera, Viewport viewport, glm::dvec2 pixel, bool add, bool remove) {
  const auto& driver = ws.scene()->doc().patch_driver;
  if (!ws.view.patch.editing || !driver || ws.scene()->work().driver_place.hidden) return false;
  if (ws.view.patch.samples) {  // the sample tool: the driver's set elements, like cage faces in the Sets window
    const auto hit = pick_vertex(camera, viewport, pixel, ws.driver_sample_points(), 6.0);
    if (!hit) return false;  // beside the samples: the click selects as usual (skin vertices with F7)
    const uint32_t s = static_cast<uint32_t>(*hit);
    if (remove) ws.view.patch.picked.remove(std::span<const uint32_t>(&s, 1));
    else if (add) ws.view.patch.picked.add(std::span<const uint32_t>(&s, 1));
    else ws.view.patch.picked.set(std::span<const uint32_t>(&s, 1));
    return true;
  }
  const auto hit = pick_vertex(camera, viewport, pixel, float_points(driver->posed), 8.0);
  if (hit) ws.view.patch.point = int(*hit);
  return hit.has_value();
}

#if CAGEWRAP_GUI  // the renderer and the window
void PatchPanel::update_display(Workspace& ws, render::ViewportRenderer& renderer) {
  const Document& w = ws.scene()->work();
  int& selected = ws.view.patch.point;
  if (!w.patch_driver || selected >= int(w.patch_driver->posed.num_control_points())) selected = -1;
  // every driver's control net that is not hidden, the first's first (the selection indexes its points)
  std::vector<glm::vec3> points;
  std::vector<std::array<uint32_t, 2>> edges;
  for (size_t i = 0; i < driver_count(w); ++i) {
    const DriverRef d = driver_at(w, i);
    if (d.place->hidden) {
      if (i == 0) selected = -1;
      continue;
    }
    const uint32_t base = static_cast<uint32_t>(points.size());
    const std::vector<glm::vec3> p = float_points(d.driver->posed);
    points.insert(points.end(), p.begin(), p.end());
    for (const auto& e : control_net_edges(d.driver->posed)) edges.push_back({e[0] + base, e[1] + base});
  }
  // the sample tool: the first driver's samples, coloured by state (picked, driving the selected skin vertices)
  std::vector<glm::vec3> samples;
  std::vector<uint8_t> states;
  if (ws.view.patch.editing && ws.view.patch.samples && w.patch_driver && !w.driver_place.hidden) {
    samples = ws.driver_sample_points();
    states = ws.driver_sample_states();
  }
  renderer.update_control_net(points, edges, selected, samples, states);
}

void PatchPanel::draw(Workspace& ws) {
  if (!ws.view.patch.editing) return;
  ImGui::SetNextWindowPos(ImVec2(270, 330), ImGuiCond_FirstUseEver);  // over the view's lower left
  ImGui::SetNextWindowSize(ImVec2(360, 0), ImGuiCond_Always);         // as tall as its contents
  if (!ImGui::Begin("Parametric driver", &ws.view.patch.editing)) {
    ImGui::End();
    return;
  }
  Scene& scene = *ws.scene();
  const std::shared_ptr<const PatchDriver> driver = scene.doc().patch_driver;
  const Workspace::PatchState& state = ws.patch_state();
  ImGui::TextUnformatted("Bicubic patches driving the skin (paper 3.3)");
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("samples at the knot values are its control elements");
  if (const size_t n = driver_count(scene.work()); n > 1)  // the others: the outliner's "edit" makes one the first
    ImGui::TextWrapped("Editing driver '%s' (the first of %zu; Deformers > edit picks another)", driver_name(scene.work(), 0).c_str(), n);
  ImGui::InputText("##path", path_field_, sizeof path_field_);
  ImGui::SameLine();
  if (ImGui::Button("Import")) ws.import_patch_driver(path_field_);
  ImGui::SameLine();
  ImGui::BeginDisabled(!driver);
  if (ImGui::Button("Export")) ws.export_patch_driver(path_field_);
  ImGui::EndDisabled();
  const bool no_faces = ws.view.selection.cage_faces.empty();
  ImGui::BeginDisabled(no_faces);
  if (ImGui::Button("Fit patches to selected faces")) ws.fit_patch_driver();
  ImGui::EndDisabled();
  if (no_faces) hint("(select a rectangle of cage quads, F6)");
  if (state.job) {
    ImGui::ProgressBar(static_cast<float>(state.job->progress()), ImVec2(-70, 0), "binding");
    ImGui::SameLine();
    if (ImGui::Button("Cancel")) ws.cancel_patch_bind();
  }
  if (!driver) {
    hint("No driver yet.");
    ImGui::End();
    return;
  }
  if (!state.job && !scene.driver_bound() && ImGui::Button("Bind to this skin")) ws.bind_patch_driver();
  int density = int(driver->density);
  ImGui::SliderInt("density", &density, 1, 16);
  if (ImGui::IsItemDeactivatedAfterEdit() && uint32_t(density) != driver->density) ws.set_patch_density(uint32_t(density));
  if (const Binding* b = scene.driver_binding.binding.get(); b && scene.driver_bound())
    ImGui::TextWrapped("%u samples, %zu degenerate; bind %.0f ms; mean set %.2f", b->num_samples, b->invalid_elements.size(),
                       b->seconds * 1e3, double(b->total_set_size) / std::max(1u, b->num_points));
  bool drive = driver->drive_skin;
  if (ImGui::Checkbox("Drive the skin", &drive)) ws.set_patch_drive(drive);
  int& selected = ws.view.patch.point;
  int sel = selected;
  if (ImGui::InputInt("control point", &sel) && sel >= -1 && sel < int(driver->posed.num_control_points())) selected = sel;
  if (selected >= 0 && selected < int(driver->posed.num_control_points())) {
    glm::dvec3 p = driver->posed.control_points()[size_t(selected)];
    float v[3] = {float(p.x), float(p.y), float(p.z)};
    // one drag of the fields = one undo step (the workspace's move of the control point)
    if (ImGui::DragFloat3("position", v, 0.005f)) {
      if (!ws.moving()) ws.begin_move();
      ws.update_move(ws.move_total() + glm::dvec3(v[0], v[1], v[2]) - p);
    }
    if (ImGui::IsItemDeactivated() && ws.moving()) ws.end_move();
  }
  if (ImGui::Button("Reset the control points")) ws.reset_patch_driver();
  draw_stack_place(ws);
  ImGui::End();
}

// The driver as a deformer of the stack (Document::driver_place): its place among the layers, its mask
// and its keyposes (the sculpt keyed against a joint's rotation).
void PatchPanel::draw_stack_place(Workspace& ws) {
  const Document& w = ws.scene()->work();
  const DriverPlacement& place = w.driver_place;
  ImGui::Separator();
  ImGui::TextUnformatted("In the deformer stack");
  int after = place.after < 0 ? int(w.layers.size()) : std::min(place.after, int(w.layers.size()));
  ImGui::SliderInt("after layers", &after, 0, int(w.layers.size()));
  if (ImGui::IsItemDeactivatedAfterEdit()) ws.set_driver_after(after == int(w.layers.size()) ? -1 : after);
  hint("in order: the layers after it take over their regions; sum and blend add it to the result");
  ImGui::PushItemWidth(-ImGui::CalcTextSize("mask joints Apply").x - 4 * ImGui::GetStyle().ItemInnerSpacing.x);
  ImGui::InputText("##mask", mask_field_, sizeof mask_field_);
  ImGui::PopItemWidth();
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("joints whose region (with their children; -c leaves one out) it may move: a,b,-c; empty: no mask");
  ImGui::SameLine();
  if (ImGui::SmallButton("Apply")) ws.set_driver_mask(mask_field_[0] ? "joints " + std::string(mask_field_) : std::string());
  ImGui::SameLine();
  ImGui::TextUnformatted("mask joints");
  hint("%s", place.mask ? ("mask: " + (place.mask_source.empty() ? std::string("painted") : place.mask_source)).c_str()
                        : "no mask: it may move every skin point it reaches");
  // its own binding parameters (or the cage's): applied as one undo step, then it binds again
  const BindParams& b = driver_params(w);
  if (!params_edited_) params_field_ = {float(b.local), float(b.epsilon), int(b.max_elements)};
  ImGui::PushItemWidth(ImGui::GetFontSize() * 4.0f);
  params_edited_ |= ImGui::InputFloat("local", &params_field_.local, 0, 0, "%.2f");
  ImGui::SameLine();
  params_edited_ |= ImGui::InputFloat("eps", &params_field_.epsilon, 0, 0, "%.3f");
  ImGui::SameLine();
  params_edited_ |= ImGui::InputInt("K", &params_field_.k, 0);
  ImGui::PopItemWidth();
  if (ImGui::SmallButton("Apply binding")) {
    BindParams p = b;
    p.local = params_field_.local;
    p.epsilon = params_field_.epsilon;
    p.max_elements = uint32_t(std::max(params_field_.k, 0));
    ws.set_driver_params(p);
    params_edited_ = false;
  }
  ImGui::SameLine();
  ImGui::BeginDisabled(!place.params);
  if (ImGui::SmallButton("Use the cage's")) {
    ws.set_driver_params(std::nullopt);
    params_edited_ = false;
  }
  ImGui::EndDisabled();
  hint("%s", place.params ? "its own binding parameters" : "binds with the cage's parameters");
  // how its control points follow the skeleton, and the selected one's joint (folded: the window stays short)
  // the sample tool turned on (here or by the action patch_samples) unfolds the row that holds it
  if (ws.view.patch.samples && !samples_shown_) ImGui::SetNextItemOpen(true);
  samples_shown_ = ws.view.patch.samples;
  if (ImGui::TreeNode("attach", "Attachment: %s; %zu set edits", place.attachment ? attachment_mode_name(place.attachment->mode) : "closest limb",
                      place.set_edits.size())) {
    int mode = place.attachment ? int(place.attachment->mode) + 1 : 0;  // 0 closest, 1 rigid, 2 smooth, 3 skin weights
    const char* modes[] = {"closest limb", "rigid", "smooth", "skin weights"};
    if (ImGui::Combo("follow", &mode, modes, 4))
      ws.set_driver_attachment(mode == 0 ? std::nullopt : std::optional<AttachmentMode>(AttachmentMode(mode - 1)));
    const int point = ws.view.patch.point;
    const uint32_t p = uint32_t(std::max(point, 0));
    const auto assigned = point >= 0 && place.attachment ? assigned_node(*place.attachment, p) : std::nullopt;
    if (point < 0) hint("no control point selected");
    else hint("control point %d: %s", point, assigned ? ("attached to " + w.character->skeleton.node(*assigned).name).c_str() : "automatic");
    const auto joints = ws.view.selection.joints.indices();
    ImGui::BeginDisabled(point < 0 || joints.size() != 1);
    if (ImGui::SmallButton("attach it to the selected joint")) ws.assign_driver_points(std::span<const uint32_t>(&p, 1), joints[0]);
    ImGui::EndDisabled();
    ImGui::SameLine();
    ImGui::BeginDisabled(!assigned);
    if (ImGui::SmallButton("automatic")) ws.assign_driver_points(std::span<const uint32_t>(&p, 1), std::nullopt);
    ImGui::EndDisabled();
    // its contributing-set edits (samples): picked in the view, from a set edits file in the path field above, or none
    ImGui::Text("Set edits: %zu", place.set_edits.size());
    ImGui::SameLine();
    if (ImGui::SmallButton("from the file above")) ws.set_driver_set_edits(path_field_);
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("a set edits file (docs/edits-format.md) whose element ids are the driver's samples");
    ImGui::SameLine();
    ImGui::BeginDisabled(place.set_edits.empty());
    if (ImGui::SmallButton("clear")) ws.set_driver_set_edits("");
    ImGui::EndDisabled();
    ImGui::Checkbox("pick samples in the view", &ws.view.patch.samples);
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("clicks pick the driver's samples (its set elements; shift adds, ctrl removes) instead of control points");
    if (ws.view.patch.samples) {
      const size_t skin = ws.view.selection.skin_vertices.size();
      hint("%zu samples picked, %zu skin vertices selected (F7)", ws.view.patch.picked.size(), skin);
      ImGui::BeginDisabled(skin == 0);
      if (ImGui::SmallButton("pick those driving them")) ws.select_driver_set_samples();
      ImGui::EndDisabled();
      ImGui::BeginDisabled(skin == 0 || ws.view.patch.picked.empty());
      for (SetEditMode m : {SetEditMode::kRemove, SetEditMode::kAdd, SetEditMode::kOnly}) {
        ImGui::SameLine();
        if (ImGui::SmallButton(set_edit_mode_name(m))) ws.driver_set_edit(m);
      }
      ImGui::EndDisabled();
      ImGui::BeginDisabled(skin == 0);
      if (ImGui::SmallButton("reset the selected vertices' sets")) ws.driver_set_edit(SetEditMode::kReset);
      ImGui::EndDisabled();
    }
    ImGui::TreePop();
  }
  ImGui::TextUnformatted("Key the sculpt at this pose, against");
  ImGui::TextUnformatted("the selected joint's rotation about");
  for (int a = 0; a < 3; ++a) {
    ImGui::SameLine();
    const char label[2] = {char('X' + a), 0};
    if (ImGui::SmallButton(label)) ws.key_driver_sculpt(a);
  }
  for (size_t i = 0; i < place.keyposes.size(); ++i) {
    ImGui::PushID(static_cast<int>(i));
    ImGui::BulletText("%s: %zu key%s", place.keyposes[i].name.c_str(), place.keyposes[i].keys.size(),
                      place.keyposes[i].keys.size() == 1 ? "" : "s");
    ImGui::SameLine();
    if (ImGui::SmallButton("remove")) ws.remove_driver_keyset(i);
    ImGui::PopID();
  }
}
#endif  // CAGEWRAP_GUI

}  // namespace cagewrap::app
