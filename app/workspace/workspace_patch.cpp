// The workspace's parametric driver (app/workspace/workspace.h "the parametric driver";
// docs/parametric-drivers.md): import, fit, density, control-point moves, drive on/off, and its bind
// in the background (poll_jobs). The Parametric driver window and the patch_* actions run these.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <utility>

#include "app/workspace/workspace.h"

#include "core/deform/patch_fit.h"
#include "core/document/binding_cache.h"
#include "core/io/patch_io.h"
#include "core/io/set_edits_io.h"

namespace cagewrap::app {

namespace {
constexpr const char* kNoDriver = "parametric driver: import or fit one first";
}  // namespace

void Workspace::start_patch_bind(std::shared_ptr<const PatchDriver> driver, std::string label) {
  patch_.job.reset();  // a bind still running is cancelled: the newer request wins
  patch_.job_driver = driver;
  patch_.job_character = scene_->doc().character;
  patch_.job_label = std::move(label);
  // set edits name samples: they hold for the same surface and density only (a new one drops them: poll_patch)
  const auto& current = scene_->work().patch_driver;
  const bool same_samples = current && current->rest == driver->rest && current->density == driver->density;
  patch_.job_edits = same_samples ? scene_->work().driver_place.set_edits : std::vector<SetEdit>{};
  patch_.nowait = false;
  // the document's own driver (not a new surface): its cache beside the project when that is still its binding
  std::optional<Document> cached;
  if (current == driver && !scene_->work().driver_place.binding_cache.file.empty()) cached = scene_->work();
  patch_.cache_note = std::make_shared<std::string>();
  patch_.job = std::make_unique<BackgroundTask<Binding>>(
      "binding to the parametric driver",
      [skin = scene_->skin_rest, driver, params = driver_params(scene_->work()), edits = patch_.job_edits, cached = std::move(cached),
       note = patch_.cache_note](const BindJob::Progress& progress, const std::atomic<bool>& cancel) -> Result<Binding> {
        if (cached) {
          auto b = load_driver_binding_cache(*cached, 0);
          *note = b ? "used the cached binding " + cached->driver_place.binding_cache.file + " (no bind)"
                    : "the cached binding was not used: " + b.error().message;
          if (b) return b;
        }
        return bind_skin_to_patches(skin, driver->rest, driver->density, params, job_progress(progress, cancel), edits);
      });
}

void Workspace::poll_patch() {
  if (!scene_) return;
  if (patch_.job && patch_.job->done()) {
    auto job = std::move(patch_.job);
    auto driver = std::move(patch_.job_driver);
    const std::string label = std::move(patch_.job_label);
    if (std::exchange(patch_.job_character, nullptr) != scene_->doc().character) return;  // another character opened
    Result<Binding>& b = job->result();
    // a bind of the document's own driver that failed or was cancelled is not retried until the driver changes
    auto failed = [&](const std::string& message, bool cancelled = false) {
      if (cancelled) log("parametric driver: bind cancelled" + std::string(label.empty() ? "" : "; the driver is unchanged"));
      else report_error("parametric driver: " + message);
      if (label.empty()) patch_.failed = scene_->doc().patch_driver;
    };
    if (!b) return failed(b.error().message, b.error().code == ErrorCode::kCancelled);
    auto binding = std::make_unique<Binding>(std::move(*b));
    auto d = PatchDeformer::create(*binding, scene_->skin_rest, driver->rest, driver->density);
    if (!d) return failed(d.error().message);
    Scene::DriverBinding& bound = scene_->driver_binding;
    bound.deformer.reset();
    bound.binding = std::move(binding);
    bound.deformer = std::make_unique<PatchDeformer>(std::move(*d));
    bound.driver = driver;
    bound.character = scene_->doc().character;
    // the driver's sculpt follows the skeleton (core/rig/driver_layer.h): its own copy of the binding
    bound.layer.reset();
    bound.edits = patch_.job_edits;
    auto layer = DriverLayer::create(*bound.character, scene_->skin_rest, *driver, *bound.binding, bound.edits);
    if (layer) bound.layer = std::make_unique<DriverLayer>(std::move(layer).value());
    else report_error("parametric driver: it cannot follow the skeleton: " + layer.error().message);
    char line[200];
    std::snprintf(line, sizeof line,
                  "parametric driver: bound %u skin points to %u samples (density %u, %zu degenerate) in %.0f ms",
                  bound.binding->num_points, bound.binding->num_samples, driver->density,
                  bound.binding->invalid_elements.size(), bound.binding->seconds * 1e3);
    log(line);
    if (patch_.cache_note && !patch_.cache_note->empty()) log("parametric driver: " + *patch_.cache_note);
    if (!label.empty()) {
      Document next = with_patch_driver(scene_->doc(), driver);
      if (next.driver_place.set_edits.size() != patch_.job_edits.size()) {  // other samples: the edits named the old ones
        DriverPlacement place = next.driver_place;
        log("warning: parametric driver: its " + std::to_string(place.set_edits.size()) +
            " set edits named the samples of its old surface or density and were dropped", true);
        place.set_edits.clear();
        next = with_driver_place(next, std::move(place));
      }
      scene_->apply(label, std::move(next));
      log("parametric driver: " + label);
    }
    return;
  }
  // the document's driver is not bound (undo, redo, a project opened): bind it
  const auto& want = scene_->doc().patch_driver;
  if (!patch_.job && want && want != patch_.failed && !scene_->driver_bound()) start_patch_bind(want, "");
}

void Workspace::bind_patch_driver() {
  if (!scene_ || patch_.job) return;
  if (const auto& driver = scene_->doc().patch_driver) {
    patch_.failed.reset();
    start_patch_bind(driver, "");
  }
}

void Workspace::cancel_patch_bind() {
  if (patch_.job) patch_.job->cancel();
  patch_.nowait = false;
}

void Workspace::new_patch_driver(PatchSurface rest, const std::string& label) {
  PatchDriver d;
  if (const auto& old = scene_->doc().patch_driver) d.density = old->density;
  d.posed = rest;
  d.rest = std::move(rest);
  view.patch.point = -1;
  start_patch_bind(std::make_shared<const PatchDriver>(std::move(d)), label);
}

bool Workspace::change_patch_driver(const std::function<void(PatchDriver&)>& change, const std::string& label) {
  const auto& old = scene_ ? scene_->doc().patch_driver : nullptr;
  if (!old) {
    fail(kNoDriver);
    return false;
  }
  PatchDriver d = *old;
  change(d);
  scene_->apply(label, with_patch_driver(scene_->doc(), std::make_shared<const PatchDriver>(std::move(d))));
  return true;
}

bool Workspace::import_patch_driver(const std::string& path) {
  if (!scene_) return false;
  auto p = load_patch_any(path);
  if (!p) {
    report_error(p.error().message);
    return false;
  }
  const size_t grids = p->grids.size(), points = p->num_control_points();
  new_patch_driver(std::move(*p), "Import parametric driver " + path + " (" + std::to_string(grids) + " grid(s), " +
                                      std::to_string(points) + " control points)");
  return true;
}

bool Workspace::export_patch_driver(const std::string& path) {
  const auto& driver = scene_ ? scene_->doc().patch_driver : nullptr;
  if (!driver) {
    fail("parametric driver: nothing to export");
    return false;
  }
  if (auto s = save_patch_any(path, driver->posed); !s) {
    report_error(s.error().message);
    return false;
  }
  log("parametric driver: wrote " + path);
  return true;
}

bool Workspace::fit_patch_driver() {
  if (!scene_) return false;
  const Document& doc = scene_->doc();
  if (!doc.cage) {
    report_error("fit a parametric driver: there is no cage");
    return false;
  }
  const IndexSet& faces = view.selection.cage_faces;
  auto grid = fit_patch_to_faces(doc.cage->polygons, doc.cage_positions(), faces.indices());
  if (!grid) {
    report_error("fit a parametric driver: " + grid.error().message);
    return false;
  }
  const std::string label = "Fit a " + std::to_string(grid->rows) + " x " + std::to_string(grid->cols) +
                            " parametric driver to " + std::to_string(faces.size()) + " cage faces";
  new_patch_driver(PatchSurface{{std::move(*grid)}}, label);
  return true;
}

bool Workspace::set_patch_density(uint32_t density, bool nowait) {
  const auto& old = scene_ ? scene_->doc().patch_driver : nullptr;
  if (!old) {
    fail(kNoDriver);
    return false;
  }
  if (density < 1 || density > 1024) {
    fail("parametric driver: density " + std::to_string(density) + " (use 1 to 1024)");
    return false;
  }
  PatchDriver d = *old;
  d.density = density;
  start_patch_bind(std::make_shared<const PatchDriver>(std::move(d)), "Driver density " + std::to_string(density));
  patch_.nowait = nowait;
  return true;
}

bool Workspace::select_patch_point(int point) {
  const auto& driver = scene_ ? scene_->doc().patch_driver : nullptr;
  if (!driver || point < -1 || point >= int(driver->posed.num_control_points())) {
    fail("parametric driver: no control point " + std::to_string(point));
    return false;
  }
  view.patch.point = point;
  return true;
}

Document Workspace::patch_point_moved(const Document& from, const glm::dvec3& total) const {
  const int i = view.patch.point;
  if (!from.patch_driver || i < 0 || i >= int(from.patch_driver->posed.num_control_points())) return from;
  PatchDriver d = *from.patch_driver;
  std::vector<glm::dvec3> points = d.posed.control_points();
  points[size_t(i)] += total;
  d.posed.set_control_points(points);
  return with_patch_driver(from, std::make_shared<const PatchDriver>(std::move(d)));
}

bool Workspace::move_patch_point(const glm::dvec3& delta) {
  const auto& driver = scene_ ? scene_->doc().patch_driver : nullptr;
  if (!driver || view.patch.point < 0 || view.patch.point >= int(driver->posed.num_control_points())) {
    fail("parametric driver: select a control point to move");
    return false;
  }
  scene_->apply("Move control point " + std::to_string(view.patch.point), patch_point_moved(scene_->doc(), delta));
  return true;
}

std::optional<glm::dvec3> Workspace::patch_point_position() const {
  const auto& driver = scene_ ? scene_->doc().patch_driver : nullptr;
  const int i = view.patch.point;
  if (!view.patch.editing || !driver || i < 0 || i >= int(driver->posed.num_control_points())) return std::nullopt;
  return driver->posed.control_points()[size_t(i)];
}

bool Workspace::set_patch_drive(bool drive) {
  return change_patch_driver([drive](PatchDriver& d) { d.drive_skin = drive; },
                             drive ? "Drive the skin by the parametric driver"
                                   : "Stop driving the skin by the parametric driver");
}

bool Workspace::reset_patch_driver() {
  return change_patch_driver([](PatchDriver& d) { d.posed = d.rest; }, "Reset the control points");
}

// ---- the driver as a deformer of the stack (Document::driver_place): its place, mask and keyposes

bool Workspace::apply_driver_place(size_t i, const std::string& label, DriverPlacement place) {
  if (!scene_->apply_work(label, with_driver_place(scene_->work(), i, std::move(place)))) return false;
  log(label);
  return true;
}

bool Workspace::set_driver_after(int after, size_t i) {
  if (!scene_ || !scene_->doc().patch_driver) {
    fail(kNoDriver);
    return false;
  }
  if (!check_driver(i)) return false;
  const Document& w = scene_->work();
  if (after > static_cast<int>(w.layers.size())) {
    fail("parametric driver: it goes after 0 to " + std::to_string(w.layers.size()) + " layers (-1: after them all)");
    return false;
  }
  DriverPlacement place = *driver_at(w, i).place;
  place.after = after < 0 ? -1 : after;
  const std::string who = i == 0 && driver_count(w) == 1 ? std::string("the driver") : "driver '" + driver_name(w, i) + "'";
  const std::string label = after < 0 ? "Put " + who + " after every layer"
                                      : "Put " + who + " after " + std::to_string(after) + " layer" + (after == 1 ? "" : "s");
  return apply_driver_place(i, label, std::move(place));
}

bool Workspace::set_driver_mask(const std::string& source) {
  if (!scene_ || !scene_->doc().patch_driver) {
    fail(kNoDriver);
    return false;
  }
  const Document& w = scene_->work();
  DriverPlacement place = w.driver_place;
  if (!make_mask(w, source, place.mask, place.mask_source, "parametric driver")) return false;
  const std::string label = source.empty() ? std::string("Remove the driver's mask") : "Mask the driver: " + source;
  return apply_driver_place(0, label, std::move(place));
}

bool Workspace::key_driver_sculpt(int axis) {
  if (!scene_ || !scene_->doc().patch_driver) {
    fail(kNoDriver);
    return false;
  }
  const Document& doc = scene_->doc();
  if (view.selection.joints.size() != 1) {
    fail("parametric driver: select the joint whose rotation keys the sculpt (F8)");
    return false;
  }
  const uint32_t node = view.selection.joints.indices()[0];
  KeyposeSet set;
  set.name = doc.character->skeleton.node(node).name + "_" + "XYZ"[axis % 3];
  JointDriver jd;
  jd.node = node;
  jd.axis = glm::vec3(0.f);
  jd.axis[axis % 3] = 1.f;
  set.drivers.push_back(jd);
  DriverPlacement place = doc.driver_place;
  for (const KeyposeSet& k : place.keyposes)
    if (k.name == set.name && k.drivers == set.drivers) set = k;  // key into the existing set
  std::vector<double> values = driver_values(set, doc.character->skeleton, current_pose());
  for (double& v : values) v = std::round(v * 10.0) / 10.0;  // keys at tenths of a degree
  // the sculpt since the last key (posed minus rest control points, bind space) goes into the key
  const std::vector<glm::dvec3> posed = doc.patch_driver->posed.control_points(), rest = doc.patch_driver->rest.control_points();
  std::vector<glm::vec3> delta(posed.size());
  for (size_t c = 0; c < posed.size(); ++c) delta[c] = glm::vec3(posed[c] - rest[c]);
  upsert_keypose_set(place.keyposes, cagewrap::key_sculpt(set, values, delta));
  PatchDriver d = *doc.patch_driver;
  d.posed = d.rest;
  char label[160];
  std::snprintf(label, sizeof label, "Key the driver's sculpt: %s at %.1f", set.name.c_str(), values.empty() ? 0.0 : values[0]);
  scene_->apply(label, with_driver_place(with_patch_driver(doc, std::make_shared<const PatchDriver>(std::move(d))), std::move(place)));
  log(label);
  return true;
}

bool Workspace::set_driver_params(std::optional<BindParams> params) {
  if (!scene_ || !scene_->doc().patch_driver) {
    fail(kNoDriver);
    return false;
  }
  if (params)
    if (auto v = validate(*params); !v) {
      fail("parametric driver: binding: " + v.error().message);
      return false;
    }
  const Document& w = scene_->work();
  DriverPlacement place = w.driver_place;
  place.params = params;
  char label[128];
  if (params) std::snprintf(label, sizeof label, "The driver's own binding: local %g, epsilon %g, K %u", params->local, params->epsilon, params->max_elements);
  else std::snprintf(label, sizeof label, "The driver binds with the cage's parameters");
  return apply_driver_place(0, label, std::move(place));
}

bool Workspace::remove_driver_keyset(size_t i) {
  const size_t n = scene_ ? scene_->work().driver_place.keyposes.size() : 0;
  if (i >= n) {
    fail("parametric driver: no keypose set " + std::to_string(i) + " (it has " + std::to_string(n) + ")");
    return false;
  }
  DriverPlacement place = scene_->work().driver_place;
  const std::string label = "Remove the driver's keypose set " + place.keyposes[i].name;
  place.keyposes.erase(place.keyposes.begin() + static_cast<long>(i));
  if (!scene_->apply_work(label, with_driver_place(scene_->work(), std::move(place)))) return false;
  log(label);
  return true;
}

// ---- more parametric drivers (Document::more_drivers): the first is the one edited; the others bind in the
// scene's driver rigs (Scene::update_driver_rigs)

bool Workspace::check_driver(size_t i) {
  if (!scene_) return false;
  const Document& w = scene_->work();
  if (i < driver_count(w)) return true;
  fail(driver_count(w) ? "no parametric driver " + std::to_string(i) + " (the drivers are 0 to " + std::to_string(driver_count(w) - 1) + ")"
                          : std::string(kNoDriver));
  return false;
}

bool Workspace::add_driver(const std::string& path) {
  if (!scene_) return false;
  const Document& w = scene_->work();
  if (!w.patch_driver) return import_patch_driver(path);  // the first: bound before it enters the document
  auto p = load_patch_any(path);
  if (!p) {
    report_error(p.error().message);
    return false;
  }
  auto d = std::make_shared<PatchDriver>();
  d->density = w.patch_driver->density;
  d->posed = *p;
  d->rest = std::move(*p);
  std::string name = std::filesystem::path(path).stem().string();
  for (size_t i = 0, k = 2; i < driver_count(w); ++i)  // a name no other driver has
    if (driver_name(w, i) == name) name = std::filesystem::path(path).stem().string() + " " + std::to_string(k++), i = size_t(-1);
  std::vector<DriverDeformer> more = w.more_drivers;
  more.push_back({std::move(d), DriverPlacement{name}});
  const std::string label = "Add parametric driver '" + name + "' (" + std::to_string(more.back().driver->rest.num_control_points()) +
                            " control points)";
  if (!scene_->apply_work(label, with_more_drivers(w, std::move(more)))) return false;
  log(label + "; it binds in the background");
  return true;
}

bool Workspace::make_driver_first(size_t i) {
  if (!check_driver(i)) return false;
  if (i == 0) return true;
  const std::string label = "Edit parametric driver '" + driver_name(scene_->work(), i) + "'";
  view.patch.point = -1;
  if (!scene_->apply_work(label, with_first_driver(scene_->work(), i))) return false;
  log(label);
  return true;
}

bool Workspace::set_driver_muted(size_t i, bool muted) {
  if (!check_driver(i)) return false;
  const Document& w = scene_->work();
  PatchDriver p = *driver_at(w, i).driver;
  p.drive_skin = !muted;
  Document next = with_driver(w, i, std::make_shared<const PatchDriver>(std::move(p)), *driver_at(w, i).place);
  const std::string label = (muted ? "Mute parametric driver '" : "Unmute parametric driver '") + driver_name(w, i) + "'";
  if (!scene_->apply_work(label, std::move(next))) return false;
  log(label);
  return true;
}

bool Workspace::set_driver_hidden(size_t i, bool hidden) {
  if (!check_driver(i)) return false;
  const Document& w = scene_->work();
  DriverPlacement place = *driver_at(w, i).place;
  place.hidden = hidden;
  const std::string label = (hidden ? "Hide parametric driver '" : "Show parametric driver '") + driver_name(w, i) + "'";
  return apply_driver_place(i, label, std::move(place));
}

bool Workspace::set_driver_solo(std::optional<size_t> i) {
  if (i && !check_driver(*i)) return false;
  if (!scene_) return false;
  const Document& w = scene_->work();
  const std::string label = i ? "Solo parametric driver '" + driver_name(w, *i) + "'" : std::string("Unsolo parametric drivers");
  if (!scene_->apply_work(label, with_driver_solo(w, i))) return false;
  log(label);
  return true;
}

bool Workspace::set_driver_set_edits(const std::string& path) {
  if (!scene_ || !scene_->doc().patch_driver) {
    fail(kNoDriver);
    return false;
  }
  const Document& w = scene_->work();
  DriverPlacement place = w.driver_place;
  if (path.empty()) {
    place.set_edits.clear();
  } else {
    auto file = load_set_edits(path);
    if (!file) {
      report_error(file.error().message);
      return false;
    }
    auto edits = resolve_sample_edits(*file, path, scene_->skin_rest.size(),
                                      patch_sample_count(w.patch_driver->rest, w.patch_driver->density));
    if (!edits) {
      report_error(edits.error().message);
      return false;
    }
    place.set_edits = std::move(edits).value();
  }
  const std::string label = path.empty() ? std::string("Clear the driver's set edits")
                                         : "The driver's set edits from " + path + " (" + std::to_string(place.set_edits.size()) + ")";
  return apply_driver_place(0, label, std::move(place));
}

bool Workspace::remove_driver(size_t i) {
  if (!check_driver(i)) return false;
  const Document& w = scene_->work();
  const std::string label = "Remove parametric driver '" + driver_name(w, i) + "'";
  view.patch.point = -1;
  Document next = without_first_driver(with_first_driver(w, i));
  if (soloed_driver(w) == i) next = with_driver_solo(next, std::nullopt);  // its solo goes with it
  if (!scene_->apply_work(label, std::move(next))) return false;
  log(label);
  return true;
}

// ---- the first driver's attachment (DriverPlacement::attachment)

namespace {
// Whether `a` attaches `n` control points of `character` (as DriverLayer::attach will): "" or why not.
std::string attachment_problem(const Character& character, const AttachmentSettings& a, size_t n) {
  if (a.mode == AttachmentMode::kFitted) return "a driver's control points are attached rigid, smooth or by skin weights, not fitted";
  for (const AttachmentOverride& o : a.overrides)
    if (o.vertex >= n) return "no control point " + std::to_string(o.vertex) + " (the driver has " + std::to_string(n) + ")";
  std::vector<glm::vec3> probe(n, glm::vec3(0.0f));
  auto att = attach_cage(character, probe, a);
  return att ? std::string() : att.error().message;
}
}  // namespace

bool Workspace::set_driver_attachment(std::optional<AttachmentMode> mode) {
  if (!scene_ || !scene_->doc().patch_driver) {
    fail(kNoDriver);
    return false;
  }
  const Document& w = scene_->work();
  DriverPlacement place = w.driver_place;
  if (!mode) {
    place.attachment.reset();
  } else {
    AttachmentSettings a = place.attachment ? *place.attachment : AttachmentSettings{};
    a.mode = *mode;
    if (auto why = attachment_problem(*w.character, a, w.patch_driver->rest.num_control_points()); !why.empty()) {
      fail("parametric driver: attachment: " + why);
      return false;
    }
    place.attachment = std::move(a);
  }
  const std::string label = mode ? std::string("Attach the driver's control points: ") + attachment_mode_name(*mode)
                                 : std::string("Attach the driver's control points to their closest limbs");
  return apply_driver_place(0, label, std::move(place));
}

bool Workspace::assign_driver_points(std::span<const uint32_t> points, std::optional<uint32_t> node) {
  if (!scene_ || !scene_->doc().patch_driver) {
    fail(kNoDriver);
    return false;
  }
  const Document& w = scene_->work();
  DriverPlacement place = w.driver_place;
  AttachmentSettings a = place.attachment ? *place.attachment : AttachmentSettings{AttachmentMode::kRigid};
  a = assign_vertices(a, points, node);
  if (auto why = attachment_problem(*w.character, a, w.patch_driver->rest.num_control_points()); !why.empty()) {
    fail("parametric driver: attachment: " + why);
    return false;
  }
  place.attachment = std::move(a);
  const std::string label = std::to_string(points.size()) + " driver control point" + (points.size() == 1 ? "" : "s") +
                            (node ? " attached to " + w.character->skeleton.node(*node).name : std::string(" attached automatically"));
  return apply_driver_place(0, label, std::move(place));
}

}  // namespace cagewrap::app
