#include "app/patch_panel.h"
#include "app/ui_text.h"

#include <utility>

#if CAGEWRAP_GUI
#include <imgui/imgui.h>
#endif

#include "core/deform/patch_fit.h"
#include "core/io/patch_io.h"

namespace cagewrap::app {

namespace {
std::vector<glm::vec3> float_points(const PatchSurface& surface) {
  std::vector<glm::vec3> points;
  for (const glm::dvec3& p : surface.control_points()) points.push_back(glm::vec3(p));
  return points;
}
}  // namespace

bool PatchPanel::bound_to(const Scene& scene) const {
  const PatchDriver* want = scene.doc().patch_driver.get();
  return want && deformer_ && bound_driver_ && bound_character_ == scene.doc().character &&
         (bound_driver_.get() == want || (bound_driver_->density == want->density && bound_driver_->rest == want->rest));
}

void PatchPanel::start_bind(Scene& scene, std::shared_ptr<const PatchDriver> driver, std::string label) {
  job_.reset();  // a bind still running is cancelled: the newer request wins
  job_driver_ = driver;
  job_character_ = scene.doc().character;
  job_label_ = std::move(label);
  script_nowait_ = false;
  job_ = std::make_unique<BackgroundTask<Binding>>(
      "binding to the parametric driver",
      [skin = scene.skin_rest, driver, params = scene.doc().params](const BindJob::Progress& progress,
                                                                     const std::atomic<bool>& cancel) {
        return bind_skin_to_patches(skin, driver->rest, driver->density, params, job_progress(progress, cancel));
      });
}

void PatchPanel::poll(Scene& scene, const EditorHooks& hooks) {
  if (job_ && job_->done()) {
    auto job = std::move(job_);
    auto driver = std::move(job_driver_);
    const std::string label = std::move(job_label_);
    if (std::exchange(job_character_, nullptr) != scene.doc().character) return;  // another character opened meanwhile
    Result<Binding>& b = job->result();
    if (!b) {
      if (b.error().code == ErrorCode::kCancelled) {
        hooks.log("parametric driver: bind cancelled" + std::string(label.empty() ? "" : "; the driver is unchanged"), false);
      } else {
        hooks.show_error("parametric driver: " + b.error().message);
      }
      if (label.empty()) failed_ = scene.doc().patch_driver;  // not retried until the driver changes
      return;
    }
    auto binding = std::make_unique<Binding>(std::move(*b));
    auto d = PatchDeformer::create(*binding, scene.skin_rest, driver->rest, driver->density);
    if (!d) {
      hooks.show_error("parametric driver: " + d.error().message);
      if (label.empty()) failed_ = scene.doc().patch_driver;
      return;
    }
    deformer_.reset();
    binding_ = std::move(binding);
    deformer_ = std::make_unique<PatchDeformer>(std::move(*d));
    bound_driver_ = driver;
    bound_character_ = scene.doc().character;
    shown_.reset();
    char line[200];
    std::snprintf(line, sizeof line,
                  "parametric driver: bound %u skin points to %u samples (density %u, %zu degenerate) in %.0f ms",
                  binding_->num_points, binding_->num_samples, driver->density, binding_->invalid_elements.size(), binding_->seconds * 1e3);
    hooks.log(line, false);
    if (!label.empty()) {
      commit(scene, driver, label);
      hooks.log("parametric driver: " + label, false);
    }
    return;
  }
  const auto& want = scene.doc().patch_driver;
  if (!job_ && want && want != failed_ && !bound_to(scene)) start_bind(scene, want, "");
}

void PatchPanel::new_driver(Scene& scene, PatchSurface rest, const std::string& label) {
  PatchDriver d;
  if (const auto& old = scene.doc().patch_driver) d.density = old->density;
  d.posed = rest;
  d.rest = std::move(rest);
  selected_ = -1;
  start_bind(scene, std::make_shared<const PatchDriver>(std::move(d)), label);
}

void PatchPanel::commit(Scene& scene, std::shared_ptr<const PatchDriver> driver, const std::string& label) {
  scene.apply(label, with_patch_driver(scene.doc(), std::move(driver)));
}

bool PatchPanel::change_driver(Scene& scene, const std::function<void(PatchDriver&)>& change, const std::string& label,
                               const EditorHooks& hooks) {
  const auto& old = scene.doc().patch_driver;
  if (!old) {
    hooks.log("error: parametric driver: import or fit one first", true);
    return false;
  }
  PatchDriver d = *old;
  change(d);
  commit(scene, std::make_shared<const PatchDriver>(std::move(d)), label);
  return true;
}

bool PatchPanel::set_drive(Scene& scene, bool drive, const EditorHooks& hooks) {
  return change_driver(scene, [drive](PatchDriver& d) { d.drive_skin = drive; },
                       drive ? "Drive the skin by the parametric driver" : "Stop driving the skin by the parametric driver",
                       hooks);
}

bool PatchPanel::reset(Scene& scene, const EditorHooks& hooks) {
  return change_driver(scene, [](PatchDriver& d) { d.posed = d.rest; }, "Reset the control points", hooks);
}

bool PatchPanel::import(Scene& scene, const std::string& path, const EditorHooks& hooks) {
  auto p = load_patch_any(path);
  if (!p) {
    hooks.show_error(p.error().message);
    return false;
  }
  const size_t grids = p->grids.size(), points = p->num_control_points();
  new_driver(scene, std::move(*p),
             "Import parametric driver " + path + " (" + std::to_string(grids) + " grid(s), " +
                 std::to_string(points) + " control points)");
  return true;
}

bool PatchPanel::export_to(const std::string& path, const Scene& scene, const EditorHooks& hooks) const {
  const auto& driver = scene.doc().patch_driver;
  if (!driver) {
    hooks.log("error: parametric driver: nothing to export", true);
    return false;
  }
  if (auto s = save_patch_any(path, driver->posed); !s) {
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
  const std::string label = "Fit a " + std::to_string(grid->rows) + " x " + std::to_string(grid->cols) +
                            " parametric driver to " + std::to_string(selection.cage_faces.size()) + " cage faces";
  new_driver(scene, PatchSurface{{std::move(*grid)}}, label);
  return true;
}

bool PatchPanel::set_density(Scene& scene, uint32_t density, const EditorHooks& hooks) {
  const auto& old = scene.doc().patch_driver;
  if (!old) {
    hooks.log("error: parametric driver: import or fit one first", true);
    return false;
  }
  if (density < 1 || density > 1024) {
    hooks.log("error: parametric driver: density " + std::to_string(density) + " (use 1 to 1024)", true);
    return false;
  }
  PatchDriver d = *old;
  d.density = density;
  start_bind(scene, std::make_shared<const PatchDriver>(std::move(d)), "Driver density " + std::to_string(density));
  return true;
}

bool PatchPanel::select(const Scene& scene, int control_point, const EditorHooks& hooks) {
  const auto& driver = scene.doc().patch_driver;
  if (!driver || control_point < -1 || control_point >= int(driver->posed.num_control_points())) {
    hooks.log("error: parametric driver: no control point " + std::to_string(control_point), true);
    return false;
  }
  selected_ = control_point;
  return true;
}

bool PatchPanel::move(Scene& scene, const glm::dvec3& delta, const EditorHooks& hooks) {
  const auto& old = scene.doc().patch_driver;
  if (!old || selected_ < 0 || selected_ >= int(old->posed.num_control_points())) {
    hooks.log("error: parametric driver: select a control point to move", true);
    return false;
  }
  scene.apply("Move control point " + std::to_string(selected_), moved(scene.doc(), delta));
  return true;
}

Document PatchPanel::moved(const Document& from, const glm::dvec3& total) const {
  if (!from.patch_driver || selected_ < 0 || selected_ >= int(from.patch_driver->posed.num_control_points())) return from;
  PatchDriver d = *from.patch_driver;
  std::vector<glm::dvec3> points = d.posed.control_points();
  points[size_t(selected_)] += total;
  d.posed.set_control_points(points);
  return with_patch_driver(from, std::make_shared<const PatchDriver>(std::move(d)));
}

std::optional<glm::dvec3> PatchPanel::selected_position(const Scene& scene) const {
  const auto& driver = scene.doc().patch_driver;
  if (!visible_ || !driver || selected_ < 0 || selected_ >= int(driver->posed.num_control_points())) return std::nullopt;
  return driver->posed.control_points()[size_t(selected_)];
}

bool PatchPanel::pick(const Scene& scene, const Camera& camera, Viewport viewport, glm::dvec2 pixel) {
  const auto& driver = scene.doc().patch_driver;
  if (!visible_ || !driver) return false;
  const auto hit = pick_vertex(camera, viewport, pixel, float_points(driver->posed), 8.0);
  if (hit) selected_ = int(*hit);
  return hit.has_value();
}

void PatchPanel::drive_skin(Scene& scene) {
  const auto& driver = scene.doc().patch_driver;
  if (!driver || !driver->drive_skin || !bound_to(scene)) {
    scene.driven_skin.reset();
    return;
  }
  if (shown_ != driver) {
    auto skin = std::make_shared<std::vector<glm::vec3>>(scene.skin_rest.size());
    skin_ = deformer_->deform(driver->posed, *skin).ok() ? std::move(skin) : nullptr;
    shown_ = driver;
  }
  scene.driven_skin = skin_;
}

#if CAGEWRAP_GUI  // the renderer and the window
void PatchPanel::update_display(Scene& scene, render::ViewportRenderer& renderer) {
  const auto& driver = scene.doc().patch_driver;
  if (!driver) {
    renderer.update_control_net({}, {}, -1);
    return;
  }
  if (selected_ >= int(driver->posed.num_control_points())) selected_ = -1;
  renderer.update_control_net(float_points(driver->posed), control_net_edges(driver->posed), selected_);
}

void PatchPanel::draw(Scene& scene, const Selection& selection, const EditorHooks& hooks) {
  if (!visible_) return;
  ImGui::SetNextWindowPos(ImVec2(270, 330), ImGuiCond_FirstUseEver);  // over the view's lower left
  ImGui::SetNextWindowSize(ImVec2(360, 0), ImGuiCond_Always);         // as tall as its contents
  if (!ImGui::Begin("Parametric driver", &visible_)) {
    ImGui::End();
    return;
  }
  const std::shared_ptr<const PatchDriver> driver = scene.doc().patch_driver;
  ImGui::TextWrapped("A surface of bicubic patches driving the rest skin (paper 3.3): samples at the knot values are its control elements.");
  ImGui::InputText("##path", path_field_, sizeof path_field_);
  ImGui::SameLine();
  if (ImGui::Button("Import")) import(scene, path_field_, hooks);
  ImGui::SameLine();
  ImGui::BeginDisabled(!driver);
  if (ImGui::Button("Export")) export_to(path_field_, scene, hooks);
  ImGui::EndDisabled();
  ImGui::BeginDisabled(selection.cage_faces.empty());
  if (ImGui::Button("Fit patches to selected faces")) fit(scene, selection, hooks);
  ImGui::EndDisabled();
  if (selection.cage_faces.empty()) hint("(select a rectangle of cage quads, F6)");
  if (job_) {
    ImGui::ProgressBar(static_cast<float>(job_->progress()), ImVec2(-70, 0), "binding");
    ImGui::SameLine();
    if (ImGui::Button("Cancel")) job_->cancel();
  }
  if (!driver) {
    hint("No driver yet.");
    ImGui::End();
    return;
  }
  if (!job_ && !bound_to(scene) && ImGui::Button("Bind to this skin")) start_bind(scene, driver, "");
  int density = int(driver->density);
  ImGui::SliderInt("density", &density, 1, 16);
  if (ImGui::IsItemDeactivatedAfterEdit() && uint32_t(density) != driver->density) set_density(scene, uint32_t(density), hooks);
  if (binding_ && bound_to(scene))
    ImGui::Text("%u samples, %zu degenerate; bind %.0f ms; mean set %.2f", binding_->num_samples,
                binding_->invalid_elements.size(), binding_->seconds * 1e3, double(binding_->total_set_size) / std::max(1u, binding_->num_points));
  bool drive = driver->drive_skin;
  if (ImGui::Checkbox("Drive the skin", &drive)) set_drive(scene, drive, hooks);
  int sel = selected_;
  if (ImGui::InputInt("control point", &sel) && sel >= -1 && sel < int(driver->posed.num_control_points())) selected_ = sel;
  if (selected_ >= 0) {
    glm::dvec3 p = driver->posed.control_points()[size_t(selected_)];
    float v[3] = {float(p.x), float(p.y), float(p.z)};
    // one drag of the fields = one undo step
    if (ImGui::DragFloat3("position", v, 0.005f)) {
      if (!scene.dragging()) scene.begin_drag();
      scene.drag(moved(scene.doc(), glm::dvec3(v[0], v[1], v[2]) - p));
    }
    if (ImGui::IsItemDeactivated() && scene.dragging()) scene.commit_drag("Move control point " + std::to_string(selected_));
  }
  if (ImGui::Button("Reset the control points")) reset(scene, hooks);
  ImGui::End();
}
#endif  // CAGEWRAP_GUI

bool PatchPanel::script_command(const std::string& cmd, std::istringstream& in, Scene& scene, const Selection& selection,
                                const EditorHooks& hooks) {
  if (cmd == "patch_import" || cmd == "patch_export") {
    std::string p;
    in >> p;
    if (cmd == "patch_import") import(scene, p, hooks);
    else export_to(p, scene, hooks);
  } else if (cmd == "patch_cancel") {  // and the script waits for the bind to stop
    if (job_) job_->cancel();
    script_nowait_ = false;
  } else if (cmd == "patch_fit") {
    fit(scene, selection, hooks);
  } else if (cmd == "patch_density") {
    uint32_t d = 0;
    std::string wait;
    in >> d >> wait;
    set_density(scene, d, hooks);
    script_nowait_ = wait == "nowait";
  } else if (cmd == "patch_select") {
    int i = -1;
    in >> i;
    select(scene, i, hooks);
  } else if (cmd == "patch_move") {
    glm::dvec3 d(0.0);
    in >> d.x >> d.y >> d.z;
    move(scene, d, hooks);
  } else if (cmd == "patch_reset") {
    reset(scene, hooks);
  } else if (cmd == "patch_drive") {
    std::string on;
    in >> on;
    set_drive(scene, on != "off", hooks);
  } else if (cmd == "patch_panel") {
    visible_ = true;
  } else {
    return false;
  }
  return true;
}

}  // namespace cagewrap::app
