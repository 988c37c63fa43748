#include "app/patch_panel.h"

#include <chrono>

#include <imgui.h>

#include "core/patch_fit.h"
#include "core/patch_io.h"

namespace cagewrap::app {

bool PatchPanel::bind(Scene& scene, uint32_t density, const EditorHooks& hooks) {
  const auto t0 = std::chrono::steady_clock::now();
  auto b = bind_skin_to_patches(scene.skin_rest, *rest_, density, scene.doc().params);
  if (!b) {
    hooks.show_error("parametric driver: " + b.error().message);
    return false;
  }
  auto binding = std::make_unique<Binding>(std::move(*b));
  auto d = PatchDeformer::create(*binding, scene.skin_rest, *rest_, density);
  if (!d) {
    hooks.show_error("parametric driver: " + d.error().message);
    return false;
  }
  bind_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  deformer_.reset();
  binding_ = std::move(binding);
  deformer_ = std::make_unique<PatchDeformer>(std::move(*d));
  bound_skin_ = &scene.skin_rest;
  density_ = density;
  skin_dirty_ = true;
  char line[200];
  std::snprintf(line, sizeof line, "parametric driver: bound %u skin points to %u samples (density %u, %zu degenerate) in %.0f ms",
                binding_->num_points, binding_->num_samples, density, binding_->invalid_elements.size(), bind_ms_);
  hooks.log(line, false);
  return true;
}

bool PatchPanel::set_driver(Scene& scene, PatchSurface rest, const std::string& what, const EditorHooks& hooks) {
  std::optional<PatchSurface> previous = std::move(rest_);
  rest_ = std::move(rest);
  if (!bind(scene, density_, hooks)) {
    rest_ = std::move(previous);  // keep the driver it had
    return false;
  }
  posed_ = *rest_;
  selected_ = -1;
  hooks.log("parametric driver: " + what + " (" + std::to_string(rest_->grids.size()) + " grid(s), " +
                std::to_string(rest_->num_control_points()) + " control points)",
            false);
  return true;
}

bool PatchPanel::import(Scene& scene, const std::string& path, const EditorHooks& hooks) {
  auto p = load_patch_any(path);
  if (!p) {
    hooks.show_error(p.error().message);
    return false;
  }
  return set_driver(scene, std::move(*p), "imported " + path, hooks);
}

bool PatchPanel::export_to(const std::string& path, const EditorHooks& hooks) const {
  if (!rest_) {
    hooks.log("error: parametric driver: nothing to export", true);
    return false;
  }
  if (auto s = save_patch_any(path, posed_); !s) {
    hooks.show_error(s.error().message);
    return false;
  }
  hooks.log("parametric driver: wrote " + path, false);
  return true;
}

bool PatchPanel::fit(Scene& scene, const Selection& selection, const EditorHooks& hooks) {
  const Document& doc = scene.doc();
  if (!doc.cage) {
    hooks.show_error("fit a parametric driver: there is no cage");
    return false;
  }
  auto grid = fit_patch_to_faces(doc.cage->polygons, doc.cage_positions(), selection.cage_faces.indices());
  if (!grid) {
    hooks.show_error("fit a parametric driver: " + grid.error().message);
    return false;
  }
  return set_driver(scene, PatchSurface{{*grid}},
                    "fitted a " + std::to_string(grid->rows) + " x " + std::to_string(grid->cols) + " grid to " +
                        std::to_string(selection.cage_faces.size()) + " cage faces",
                    hooks);
}

bool PatchPanel::set_density(Scene& scene, uint32_t density, const EditorHooks& hooks) {
  if (!rest_) {
    hooks.log("error: parametric driver: import or fit one first", true);
    return false;
  }
  return bind(scene, density, hooks);
}

bool PatchPanel::select(int control_point, const EditorHooks& hooks) {
  if (!rest_ || control_point < -1 || control_point >= int(posed_.num_control_points())) {
    hooks.log("error: parametric driver: no control point " + std::to_string(control_point), true);
    return false;
  }
  selected_ = control_point;
  return true;
}

bool PatchPanel::move(const glm::dvec3& delta, const EditorHooks& hooks) {
  if (!rest_ || selected_ < 0) {
    hooks.log("error: parametric driver: select a control point to move", true);
    return false;
  }
  std::vector<glm::dvec3> points = posed_.control_points();
  points[size_t(selected_)] += delta;
  posed_.set_control_points(points);
  skin_dirty_ = true;
  return true;
}

void PatchPanel::update_display(Scene& scene, render::ViewportRenderer& renderer) {
  if (!rest_) {
    renderer.update_control_net({}, {}, -1);
    return;
  }
  if (bound_skin_ != &scene.skin_rest || !deformer_) return;  // another document: rebinds on demand
  if (drive_skin_) {
    if (skin_dirty_) {
      skin_.resize(scene.skin_rest.size());
      if (auto s = deformer_->deform(posed_, skin_); !s) drive_skin_ = false;
      skin_dirty_ = false;
    }
    if (drive_skin_) renderer.update_skin(skin_);
  }
  std::vector<glm::vec3> points;
  for (const glm::dvec3& p : posed_.control_points()) points.push_back(glm::vec3(p));
  renderer.update_control_net(points, control_net_edges(posed_), selected_);
}

void PatchPanel::draw(Scene& scene, const Selection& selection, const EditorHooks& hooks) {
  if (!visible_) return;
  ImGui::SetNextWindowPos(ImVec2(270, 330), ImGuiCond_FirstUseEver);  // over the view's lower left
  ImGui::SetNextWindowSize(ImVec2(360, 0), ImGuiCond_Always);         // as tall as its contents
  if (!ImGui::Begin("Parametric driver", &visible_)) {
    ImGui::End();
    return;
  }
  ImGui::TextWrapped("A surface of bicubic patches driving the rest skin (paper 3.3): samples at the knot values are its control elements.");
  ImGui::InputText("##path", path_field_, sizeof path_field_);
  ImGui::SameLine();
  if (ImGui::Button("Import")) import(scene, path_field_, hooks);
  ImGui::SameLine();
  ImGui::BeginDisabled(!rest_);
  if (ImGui::Button("Export")) export_to(path_field_, hooks);
  ImGui::EndDisabled();
  ImGui::BeginDisabled(selection.cage_faces.empty());
  if (ImGui::Button("Fit patches to selected faces")) fit(scene, selection, hooks);
  ImGui::EndDisabled();
  if (selection.cage_faces.empty()) ImGui::TextDisabled("(select a rectangle of cage quads, F6)");
  if (!rest_) {
    ImGui::TextDisabled("No driver yet.");
    ImGui::End();
    return;
  }
  if (bound_skin_ != &scene.skin_rest && ImGui::Button("Bind to this skin")) bind(scene, density_, hooks);
  int density = int(density_);
  ImGui::SliderInt("density", &density, 1, 16);
  if (ImGui::IsItemDeactivatedAfterEdit()) set_density(scene, uint32_t(density), hooks);
  if (binding_)
    ImGui::Text("%u samples, %zu degenerate; bind %.0f ms; mean set %.2f", binding_->num_samples,
                binding_->invalid_elements.size(), bind_ms_, double(binding_->total_set_size) / std::max(1u, binding_->num_points));
  ImGui::Checkbox("Drive the skin", &drive_skin_);
  int sel = selected_;
  if (ImGui::InputInt("control point", &sel) && sel >= -1 && sel < int(posed_.num_control_points())) selected_ = sel;
  if (selected_ >= 0) {
    glm::dvec3 p = posed_.control_points()[size_t(selected_)];
    float v[3] = {float(p.x), float(p.y), float(p.z)};
    if (ImGui::DragFloat3("position", v, 0.005f)) move(glm::dvec3(v[0], v[1], v[2]) - p, hooks);
  }
  if (ImGui::Button("Reset the control points")) {
    posed_ = *rest_;
    skin_dirty_ = true;
  }
  ImGui::End();
}

bool PatchPanel::script_command(const std::string& cmd, std::istringstream& in, Scene& scene, const Selection& selection,
                                const EditorHooks& hooks) {
  if (cmd == "patch_import" || cmd == "patch_export") {
    std::string p;
    in >> p;
    if (cmd == "patch_import") import(scene, p, hooks);
    else export_to(p, hooks);
  } else if (cmd == "patch_fit") {
    fit(scene, selection, hooks);
  } else if (cmd == "patch_density") {
    uint32_t d = 0;
    in >> d;
    set_density(scene, d, hooks);
  } else if (cmd == "patch_select") {
    int i = -1;
    in >> i;
    select(i, hooks);
  } else if (cmd == "patch_move") {
    glm::dvec3 d(0.0);
    in >> d.x >> d.y >> d.z;
    move(d, hooks);
  } else if (cmd == "patch_reset") {
    if (rest_) posed_ = *rest_;
    skin_dirty_ = true;
  } else if (cmd == "patch_drive") {
    std::string on;
    in >> on;
    drive_skin_ = on != "off";
  } else if (cmd == "patch_panel") {
    visible_ = true;
  } else {
    return false;
  }
  return true;
}

}  // namespace cagewrap::app
