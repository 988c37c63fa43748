#include "app/workspace/scene.h"

#include "core/deform/attachment_fit.h"

#include <unistd.h>

#include <algorithm>
#include <filesystem>

#include "core/document/binding_cache.h"
#include "core/io/gltf_loader.h"
#include "core/geometry/mesh_io.h"
#include "core/document/project_io.h"
#include "core/deform/part_labels.h"
#include "core/rig/deformer_stack.h"
#include "core/rig/rig.h"
#include "core/character/skinning.h"

namespace cagewrap::app {

BindProgress job_progress(const BindJob::Progress& progress, const std::atomic<bool>& cancel) {
  BindProgress p;
  p.on_progress = [&progress](double f) { progress("bind", f); };
  p.cancel = &cancel;
  return p;
}

namespace {
// The fit a job makes after its bind (on its worker thread).
void fit_after_bind(const Document& doc, const Binding& binding, const FitRequest& fit) {
  if (!fit.out || !fit.transferred || doc.attachment.mode != AttachmentMode::kFitted) return;
  CageAttachment a = *fit.transferred;
  auto f = fit_rig(*doc.character, binding, doc.attachment, a);
  if (f) *fit.out = RigFit{std::move(a), std::move(f).value(), *fit.transferred};
}
}  // namespace

std::unique_ptr<BindJob> start_bind_job(std::vector<glm::vec3> skin, Document doc, std::optional<CageAttachment> attachment,
                                        FitRequest fit, std::shared_ptr<CandidateCacheSlot> cache, bool make_cache) {
  return std::make_unique<BindJob>("binding", [skin = std::move(skin), doc = std::move(doc), attachment = std::move(attachment),
                                               fit = std::move(fit), cache = std::move(cache),
                                               make_cache](const BindJob::Progress& progress, const std::atomic<bool>& cancel) {
    const CageAttachment* a = attachment ? &*attachment : nullptr;
    auto b = cache ? bind_document_cached(doc, skin, a, *cache, make_cache, job_progress(progress, cancel))
                   : bind_document(doc, skin, a, job_progress(progress, cancel));
    if (b && !cancel) fit_after_bind(doc, *b, fit);
    return b;
  });
}

std::unique_ptr<BindJob> start_rest_edit_job(std::vector<glm::vec3> skin, Document doc,
                                             std::optional<CageAttachment> attachment, Binding previous,
                                             std::optional<CageAttachment> previous_attachment,
                                             std::shared_ptr<RestRebindReport> report, FitRequest fit,
                                             std::vector<SetEdit> previous_edits) {
  return std::make_unique<BindJob>(
      "rest edit", [skin = std::move(skin), doc = std::move(doc), attachment = std::move(attachment),
                    previous = std::move(previous), previous_attachment = std::move(previous_attachment),
                    report = std::move(report), fit = std::move(fit), previous_edits = std::move(previous_edits)](
                       const BindJob::Progress& progress, const std::atomic<bool>& cancel) mutable {
        auto b = rebind_document(doc, skin, attachment ? &*attachment : nullptr, std::move(previous),
                                 previous_attachment ? &*previous_attachment : nullptr, job_progress(progress, cancel),
                                 report.get(), &previous_edits);
        if (b && !cancel) fit_after_bind(doc, *b, fit);
        return b;
      });
}

bool Scene::rest_edit_possible() const {
  const auto& cage = doc().cage;
  if (!binding || !bound_cage || !cage || bound_cage == cage || binding->reach.empty()) return false;
  // a topology edit carries the set edits to the new elements (rebind_document re-registers the points
  // that have one); a rest edit keeps them
  const bool same_topology = bound_cage->elements == cage->elements && bound_cage->num_vertices() == cage->num_vertices();
  return (!same_topology || same_set_edits(bound_edits_, doc().set_edits)) &&
         rest_edit_params_fit(binding->params, binding->h, params) && bound_attachment_ == doc().attachment;
}

bool Scene::needs_rebind() const {
  if (!doc().cage) return false;
  if (!binding || bound_cage != doc().cage || !same_set_edits(bound_edits_, doc().set_edits)) return true;
  if (params.separate && !(bound_attachment_ == doc().attachment)) return true;  // other part labels
  return !(params == binding->params);
}

void Scene::adopt_binding(Binding b) {
  auto owned = std::make_unique<Binding>(std::move(b));
  std::swap(binding, owned);
  if (!make_deformer().ok()) {  // the previous binding and deformer stay; a fresh bind follows
    binding = std::move(owned);
    return;
  }
  bound_cage = doc().cage;
  bound_edits_ = doc().set_edits;
  bound_attachment_ = doc().attachment;
  bound_attachment_data_ = attachment;
  params = doc().params;
}

bool Scene::fits_attachment() const {
  return attachment && binding && doc().attachment.mode == AttachmentMode::kFitted &&
         binding->num_cage_vertices == attachment->joint.size();
}

Status Scene::make_deformer(RigFit* fit) {
  if (!binding) return make_error(ErrorCode::kInvalidArgument, "no binding");
  // all or nothing: the fit and the deformer are made aside, and taken only when both worked
  std::optional<CageAttachment> fitted_attachment;
  std::unique_ptr<Binding> fitted;
  if (fits_attachment()) {
    const CageAttachment& from = transferred_ ? *transferred_ : *attachment;  // as Rig::create: the transferred weights
    if (fit && fit->transferred == from) {  // the bind job's fit, of this binding and attachment
      fitted_attachment = std::move(fit->attachment);
      if (fit->smoothed) fitted = std::make_unique<Binding>(std::move(*fit->smoothed));
    } else {
      CageAttachment a = from;
      if (auto f = fit_rig(*doc().character, *binding, doc().attachment, a); f.ok()) {
        fitted_attachment = std::move(a);
        if (*f) fitted = std::make_unique<Binding>(std::move(**f));
      }
    }
  }
  // refers to the binding: made from its final place (the heap object `fitted` owns, or `binding`'s)
  auto d = Deformer::create(fitted ? *fitted : *binding, skin_rest);
  if (!d) return make_error(d.error().code, d.error().message);
  deformer.reset();
  rig_binding = std::move(fitted);
  deformer.emplace(std::move(d).value());
  binding_revision = next_revision();
  if (fitted_attachment) {
    attachment = std::move(*fitted_attachment);
    attachment_revision = next_revision();
    sim_cache.clear();  // the simulated clips keep a copy of the attachment
  }
  return Ok{};
}

void Scene::start_bind() {
  if (!doc().cage || job) return;
  pending_rest_report_.reset();
  pending_fit_ = std::make_shared<std::optional<RigFit>>();
  FitRequest fit{doc().attachment.mode == AttachmentMode::kFitted ? transferred_ : std::nullopt, pending_fit_};
  if (rest_edit_possible()) {
    pending_rest_report_ = std::make_shared<RestRebindReport>();
    job = start_rest_edit_job(skin_rest, with_params(doc(), params), attachment, *binding, bound_attachment_data_,
                              pending_rest_report_, std::move(fit), bound_edits_);
  } else {
    job = start_bind_job(skin_rest, with_params(doc(), params), attachment, std::move(fit), candidate_cache_,
                         live_params && live_params_possible());
  }
  pending_attachment_data_ = attachment;
  pending_cage_ = doc().cage;
  pending_edits_ = doc().set_edits;
  pending_attachment_ = doc().attachment;
}

void Scene::drag_params() {
  if (!live_params_possible()) return;
  live_params = true;
  if (!job && needs_rebind()) start_bind();
}

void Scene::commit_params() {
  live_params = false;
  if (!doc().cage || live) return;
  if (!(params == doc().params))
    history_.push("Change binding parameters", to_work(with_params(doc(), params), history_.current()));
  if (!job && needs_rebind()) start_bind();  // else poll_bind binds them when the running bind ends
}

void Scene::rebind() {
  if (!doc().cage || job || live) return;
  if (!(params == doc().params))
    history_.push("Change binding parameters", to_work(with_params(doc(), params), history_.current()));
  start_bind();
}

const Document& Scene::view() const {
  const Document& w = history_.current();
  if (active_ == 0 || active_ >= deformer_count(w)) return w;
  if (!view_ || view_of_ != w.revision) {
    Document v = deformer_document(w, active_);
    // the document-wide fields stay the document's: the parametric driver, the project's storage
    v.patch_driver = w.patch_driver;
    v.driver_place = w.driver_place;
    v.more_drivers = w.more_drivers;
    v.binding_cache = {};
    v.revision = next_revision();  // not the document's: what is keyed on it (GPU copies, caches) sees another cage
    view_ = std::move(v);
    view_of_ = w.revision;
  }
  view_->project_path = w.project_path;  // a save names it without a new revision
  return *view_;
}

const Document& Scene::work() const {
  if (!live) return history_.current();
  work_live_ = to_work(*live, history_.current());
  return *work_live_;
}

Document Scene::to_work(const Document& next, const Document& base) const {
  if (active_ == 0 || active_ >= deformer_count(base)) return next;
  if (view_ && view_of_ == base.revision && next.revision == view_->revision) return base;  // unchanged
  Document out = base;
  DeformerLayer& l = out.layers[active_ - 1];
  if (next.cage) l.cage = next.cage;  // a layer always has a cage
  l.params = next.params;
  l.set_edits = next.set_edits;
  l.cage_offsets = next.cage_offsets;
  l.attachment = next.attachment;
  l.keyposes = next.keyposes;
  l.sim = next.sim;
  out.character = next.character;
  out.character_path = next.character_path;
  out.character_hash = next.character_hash;
  out.embedded_character = next.embedded_character;
  out.patch_driver = next.patch_driver;
  out.driver_place = next.driver_place;
  out.more_drivers = next.more_drivers;
  out.cache_binding = next.cache_binding;
  out.preserved_fields = next.preserved_fields;
  out.revision = next_revision();
  return out;
}

bool Scene::apply(std::string label, Document next) {
  if (!history_.push(std::move(label), to_work(next, history_.current()))) return false;
  document_changed();
  return true;
}

bool Scene::apply_work(std::string label, Document next) {
  if (!history_.push(std::move(label), std::move(next))) return false;
  document_changed();
  return true;
}

bool Scene::apply_set_edits(std::string label, Document next, std::span<const uint32_t> points) {
  if (!history_.push(std::move(label), to_work(next, history_.current()))) return false;
  if (!update_set_edits_live(doc().set_edits, points)) document_changed();  // a full rebind
  return true;
}

void Scene::begin_drag() {
  live.reset();
  drag_view_ = view();
  history_.begin(history_.current());
}

bool Scene::commit_drag(std::string label, bool refresh) {
  bool changed = false;
  if (live) changed = history_.commit(std::move(label), to_work(*live, history_.current()));
  else history_.cancel();
  live.reset();
  if (changed && refresh) document_changed();
  return changed;
}

void Scene::cancel_drag() {
  const bool had = live.has_value();
  history_.cancel();
  live.reset();
  if (had) document_changed();
}

std::string Scene::undo() {
  if (!history_.can_undo()) return {};
  std::string label = history_.undo_label();
  live.reset();
  history_.undo();
  document_changed();
  return label;
}

std::string Scene::redo() {
  if (!history_.can_redo()) return {};
  std::string label = history_.redo_label();
  live.reset();
  history_.redo();
  document_changed();
  return label;
}

void Scene::update_attachment() {
  const auto& cage = doc().cage;
  if (cage && (!attachment || attachment->joint.size() != cage->num_vertices() || attached_cage_ != cage ||
               attached_settings_ != doc().attachment)) {
    attachment.reset();
    if (!doc().character->skins.empty()) {
      // the document's attachment settings (smooth, overrides); the automatic rigid one if they fail
      auto att = attach_cage(*doc().character, cage->polygons.positions, doc().attachment, cage->elements);
      if (!att) att = attach_to_closest_limb(*doc().character, cage->polygons.positions);
      if (att) attachment = std::move(att).value();
      transferred_ = attachment;
    }
    attached_cage_ = cage;
    attached_settings_ = doc().attachment;
    attachment_revision = next_revision();  // a new attachment (display caches follow it)
    // a binding that stays (adopted from a project's cache, or other attachment settings with
    // separation off) is fitted to the new attachment
    if (binding && !job && !needs_rebind()) static_cast<void>(make_deformer());
  }
}

void Scene::switch_active(size_t d) {
  // the old active deformer's registration becomes its stack rig's (update_stack_rigs), no bind again
  handed_over_.reset();
  if (binding && !job && active_ < deformer_count(history_.current()) && binding_fits(*binding, doc()).ok())
    handed_over_ = HandedOver{active_, std::move(*binding)};
  // the new one's: its stack rig's registration, when it is ready
  std::optional<Binding> reuse;
  for (const StackRig& r : stack_rigs)
    if (r.deformer == d && r.rig) reuse = r.rig->binding();
  job.reset();  // cancels and waits
  binding.reset();
  deformer.reset();
  rig_binding.reset();
  bound_cage.reset();
  bound_edits_.clear();
  rebinder_.reset();
  rebinder_for_ = nullptr;
  attachment.reset();
  attached_cage_.reset();
  transferred_.reset();
  sim_cache.clear();
  binding_revision = next_revision();
  active_ = d;
  view_.reset();
  params = doc().params;
  if (reuse && binding_fits(*reuse, doc()).ok()) {
    update_attachment();
    adopt_binding(std::move(*reuse));
  }
}

bool Scene::set_active_deformer(size_t d) {
  if (d == active_ || d >= deformer_count(history_.current()) || live || history_.dragging()) return false;
  switch_active(d);
  document_changed();
  return true;
}

bool Scene::cage_stack() const {
  const Document& w = history_.current();
  return deformer_count(w) > 1 || deformer_muted(w, 0);
}

void Scene::update_stack_rigs() {
  const Document& w = history_.current();
  std::vector<StackRig> next;
  for (size_t d = 0; d < deformer_count(w); ++d) {
    if (d == active_ || deformer_muted(w, d)) continue;
    Document dd = deformer_document(w, d);
    if (!dd.cage) continue;  // the document has layers but no cage of its own
    const BindingInputs in = binding_inputs(dd);
    StackRig r;
    // the rig (or bind) made from the same inputs, wherever it was in the stack
    auto same = std::find_if(stack_rigs.begin(), stack_rigs.end(), [&](const StackRig& o) {
      return (o.rig || o.job || !o.error.empty()) && o.inputs == in && o.doc.attachment == dd.attachment;
    });
    if (same != stack_rigs.end()) {
      r = std::move(*same);
      same->error.clear();
    } else {
      r.inputs = in;
      const std::string label = "binding deformer '" + deformer_name(w, d) + "'";
      if (handed_over_ && handed_over_->deformer == d && binding_fits(handed_over_->binding, dd).ok()) {
        r.job = std::make_unique<StackRigJob>(label, [dd, b = std::move(handed_over_->binding)](const StackRigJob::Progress&,
                                                                                               const std::atomic<bool>&) mutable {
          return Rig::create(dd, std::move(b));
        });
        handed_over_.reset();
      } else {
        // its cache beside the project when that is still its binding, else a bind
        r.job = std::make_unique<StackRigJob>(label, [dd, note = r.cache_note](const StackRigJob::Progress& progress,
                                                                              const std::atomic<bool>& cancel) {
          if (!dd.binding_cache.file.empty()) {
            auto cached = load_binding_cache(dd);
            if (cached) {
              auto rig = Rig::create(dd, std::move(cached).value());
              if (rig) {
                *note = "used: " + dd.binding_cache.file;
                return rig;
              }
              *note = "not used: " + rig.error().message;
            } else {
              *note = "not used: " + cached.error().message;
            }
          }
          return Rig::create(dd, job_progress(progress, cancel));
        });
      }
    }
    r.deformer = d;
    r.doc = std::move(dd);
    next.push_back(std::move(r));
  }
  handed_over_.reset();
  stack_rigs = std::move(next);  // the rest are dropped (their binds cancelled)
}

std::vector<const Binding*> Scene::driver_bindings() const {
  const Document& w = history_.current();
  std::vector<const Binding*> out(driver_count(w), nullptr);
  for (size_t i = 0; i < out.size(); ++i) {
    const Binding* b = nullptr;
    if (i == 0) {
      if (driver_bound()) b = driver_binding.binding.get();
    } else {
      const DriverRef d = driver_at(w, i);
      for (const DriverRig& r : driver_rigs)
        if (r.index == i && r.layer && r.layer->fits(*d.driver, driver_params(w, *d.place), d.place->set_edits)) b = &r.layer->binding();
    }
    if (b && driver_binding_fits(*b, w, i)) out[i] = b;
  }
  return out;
}

std::vector<const Binding*> Scene::deformer_bindings() const {
  const Document& w = work();
  std::vector<const Binding*> out(deformer_count(w), nullptr);
  for (size_t d = 0; d < out.size(); ++d) {
    const Binding* b = nullptr;
    if (d == active_) {
      if (binding && !job && !needs_rebind()) b = binding.get();
    } else {
      for (const StackRig& r : stack_rigs)
        if (r.deformer == d && r.rig) b = &r.rig->binding();
    }
    if (b && binding_fits(*b, deformer_document(w, d))) out[d] = b;
  }
  return out;
}

std::vector<std::string> Scene::poll_stack() {
  std::vector<std::string> out;
  for (StackRig& r : stack_rigs) {
    if (!r.job || !r.job->done()) continue;
    auto& res = r.job->result();
    const std::string name = deformer_name(history_.current(), r.deformer);
    if (res.ok()) {
      r.rig = std::make_unique<Rig>(std::move(res).value());
      r.revision = next_revision();
      const std::string& note = *r.cache_note;
      if (note.starts_with("used: "))
        out.push_back("deformer '" + name + "': using the cached binding " + note.substr(6) + " (no bind)");
      else
        out.push_back((note.empty() ? "" : "warning: deformer '" + name + "': binding cache " + note + "; ") + "deformer '" + name +
                      "' bound (" + std::to_string(r.rig->binding().num_points) + " points)");
    } else if (res.error().code == ErrorCode::kCancelled) {
      r.error = "bind cancelled";
      out.push_back("deformer '" + name + "': bind cancelled");
    } else {
      r.error = res.error().message;
      out.push_back("error: deformer '" + name + "': " + r.error);
    }
    r.job.reset();
  }
  for (DriverRig& r : driver_rigs) {
    if (!r.job || !r.job->done()) continue;
    auto& res = r.job->result();
    if (res.ok()) {
      r.layer = std::make_unique<DriverLayer>(std::move(res).value());
      const std::string note = r.cache_note ? *r.cache_note : std::string();
      if (note.starts_with("used: "))
        out.push_back("parametric driver '" + r.name + "': using the cached binding " + note.substr(6) + " (no bind)");
      else
        out.push_back((note.empty() ? "" : "warning: parametric driver '" + r.name + "': binding cache " + note + "; ") +
                      "parametric driver '" + r.name + "' bound (" + std::to_string(r.layer->num_control_points()) + " control points)");
    } else {
      r.error = res.error().code == ErrorCode::kCancelled ? "bind cancelled" : res.error().message;
      out.push_back((res.error().code == ErrorCode::kCancelled ? "" : "error: ") + std::string("parametric driver '") + r.name +
                    "': " + r.error);
    }
    r.job.reset();
  }
  return out;
}

void Scene::cancel_stack_binds() {
  for (StackRig& r : stack_rigs)
    if (r.job) r.job->cancel();
  for (DriverRig& r : driver_rigs)
    if (r.job) r.job->cancel();
}

void Scene::retry_stack_binds() {
  std::erase_if(stack_rigs, [](const StackRig& r) { return !r.rig && !r.job; });
  std::erase_if(driver_rigs, [](const DriverRig& r) { return !r.layer && !r.job; });
  update_stack_rigs();
  update_driver_rigs();
}

void Scene::pose_stack(const Playback& pb, bool maps_only, std::span<const DriverTerm> driver) {
  const Document& w = stack_document();
  stack_ready_ = std::all_of(stack_rigs.begin(), stack_rigs.end(), [](const StackRig& r) { return r.rig != nullptr; });
  for (StackRig& r : stack_rigs) {
    if (!stack_ready_) break;  // the active deformer's skin alone (and the driver) until every rig is ready
    Status s = Ok{};
    const bool simulated = r.doc.sim.enabled && pb.clip >= 0;
    if (!r.rig->fits(r.doc)) {
      s = make_error(ErrorCode::kInvalidArgument, "its rig is out of date");
    } else if (maps_only) {  // the cage alone, as pose and pose_clip pose it, and its maps for the GPU
      if (simulated) s = r.rig->pose_clip_cage(r.doc, pb.clip, pb.player.time(), pb.pose_override, r.cage);
      else pose_document_cage(r.doc, r.rig->attachment(), pose_, r.cage);
      Deformer& d = r.rig->deformer();
      if (s) s = d.update_maps(r.cage.positions, cage_vertex_frames(d.binding(), r.cage));
    } else {
      r.skin.resize(skin_rest.size());
      if (simulated) s = r.rig->pose_clip(r.doc, pb.clip, pb.player.time(), pb.pose_override, r.cage, r.skin);
      else s = r.rig->pose(r.doc, pose_, r.cage, r.skin);
    }
    if (!s) {
      r.error = s.error().message;
      r.rig.reset();
      stack_ready_ = false;
    }
  }
  if (!stack_ready_) {
    if (!maps_only) add_drivers_alone(driver);
    return;
  }
  if (!maps_only) {
    stack_ready_ = combine_skins(driver);
    stack_combined_ = stack_ready_;
    return;
  }
  // what combine_document_stack combines, for the GPU: the deformers not muted, each layer with its mask,
  // and the drivers' displacements (made on the CPU) where they sit
  gpu_frame_.stack = w.stack;
  const auto drivers_at = [&](size_t at) {
    for (const DriverTerm& t : driver)
      if (driver_position(w, *t.place) == at) {
        GpuFrame::Deformed f;
        f.mask = t.place->mask;
        f.displacement = t.delta;
        gpu_frame_.layers.push_back(std::move(f));
      }
  };
  for (size_t d = 0; d < deformer_count(w); ++d) {
    if (d >= 1) drivers_at(d - 1);
    if (deformer_muted(w, d)) continue;
    GpuFrame::Deformed f;
    f.index = d;
    if (d == active_) {
      f.deformer = &*deformer;
      f.revision = binding_revision;
    } else {
      auto r = std::find_if(stack_rigs.begin(), stack_rigs.end(), [&](const StackRig& o) { return o.deformer == d; });
      if (r == stack_rigs.end()) continue;  // it has no cage: left out, as on the CPU
      f.deformer = &r->rig->deformer();
      f.revision = r->revision;
    }
    if (d == 0) {
      gpu_frame_.base = std::move(f);
    } else {
      f.mask = w.layers[d - 1].mask;
      gpu_frame_.layers.push_back(std::move(f));
    }
  }
  drivers_at(w.layers.size());
  stack_combined_ = true;
}

bool Scene::combine_skins(std::span<const DriverTerm> driver) {
  const auto skin_of = [&](size_t d) -> const std::vector<glm::vec3>* {
    if (d == active_) return &skin_posed_;
    for (const StackRig& r : stack_rigs)
      if (r.deformer == d) return &r.skin;
    return nullptr;
  };
  std::vector<glm::vec3> out;
  if (!combine_document_stack(stack_document(), skin_rest, skin_of, out, driver).ok()) return false;
  skin_posed_ = std::move(out);
  skin_driven_ = !driver.empty();
  return true;
}

bool Scene::combine_stack_on_cpu(std::span<const DriverTerm> drivers) {
  for (StackRig& r : stack_rigs) {
    if (!r.rig) return false;
    r.skin.resize(skin_rest.size());
    if (!deform_through_cage(r.rig->deformer(), r.cage, r.skin).ok()) return false;
  }
  return combine_skins(drivers);
}

void Scene::add_drivers_alone(std::span<const DriverTerm> drivers) {
  if (drivers.empty()) return;
  // the stack's combination with no layer skins: the drivers alone, with their masks
  const Document& w = stack_document();
  const std::vector<std::span<const glm::vec3>> none(w.layers.size());
  skin_driven_ = combine_layers(w, skin_rest, none, drivers, skin_posed_).ok();
}

std::vector<DriverTerm> Scene::driver_displacements() {
  const Document& w = stack_document();
  std::vector<DriverTerm> out;
  // a driver attached another way than its layer was is attached again (no bind)
  const auto attached = [&](DriverLayer& layer, const DriverPlacement& place) {
    return layer.attach(*w.character, place.attachment ? &*place.attachment : nullptr).ok();
  };
  if (driving() && attached(*driver_binding.layer, w.driver_place)) {
    driver_delta_.resize(skin_rest.size());
    auto any = driver_binding.layer->displacement(*w.patch_driver, w.driver_place.keyposes, w.character->skeleton, pose_, joint_globals,
                                                  driver_delta_);
    if (any.ok() && *any) out.push_back({driver_delta_, &w.driver_place});
  }
  for (size_t i = 1; i < driver_count(w); ++i) {
    if (!driver_moves_skin(w, i)) continue;
    const DriverRef d = driver_at(w, i);
    for (DriverRig& r : driver_rigs) {  // its own (two drivers may share a surface, each with its sculpt)
      if (r.index != i || !r.layer || !r.layer->fits(*d.driver, driver_params(w, *d.place), d.place->set_edits)) continue;
      if (!attached(*r.layer, *d.place)) break;
      r.delta.resize(skin_rest.size());
      auto any = r.layer->displacement(*d.driver, d.place->keyposes, w.character->skeleton, pose_, joint_globals, r.delta);
      if (any.ok() && *any) out.push_back({r.delta, d.place});
      break;
    }
  }
  return out;
}

void Scene::update_driver_rigs() {
  const Document& w = history_.current();
  std::vector<DriverRig> next;
  for (size_t i = 1; i < driver_count(w); ++i) {
    const DriverRef d = driver_at(w, i);
    const BindParams& params = driver_params(w, *d.place);
    // the layer (or bind) made for the same surface, density and parameters, wherever it was in the list
    auto same = std::find_if(driver_rigs.begin(), driver_rigs.end(), [&](const DriverRig& o) {
      return o.driver && o.character == w.character && o.driver->density == d.driver->density && o.driver->rest == d.driver->rest && o.params == params &&
             o.edits == d.place->set_edits && (o.layer || o.job || !o.error.empty());
    });
    // a muted driver keeps the layer it has (unmuting is then immediate) but is not bound
    if (!driver_moves_skin(w, i) && same == driver_rigs.end()) continue;
    DriverRig r;
    if (same != driver_rigs.end()) {
      r = std::move(*same);
      same->driver = nullptr;
    } else {
      r.driver = w.more_drivers[i - 1].driver;
      r.params = params;
      r.edits = d.place->set_edits;
      r.character = w.character;
      // its cache beside the project when that is still its binding, else a bind
      std::optional<Document> cached;
      if (!d.place->binding_cache.file.empty()) cached = w;
      r.cache_note = std::make_shared<std::string>();
      r.job = std::make_unique<DriverRigJob>(
          "binding parametric driver '" + driver_name(w, i) + "'",
          [character = w.character, skin = skin_rest, driver = r.driver, params, edits = r.edits, cached = std::move(cached), i,
           note = r.cache_note](const DriverRigJob::Progress& progress, const std::atomic<bool>& cancel) -> Result<DriverLayer> {
            if (cached) {
              auto b = load_driver_binding_cache(*cached, i);
              if (b) {
                auto layer = DriverLayer::create(*character, skin, *driver, std::move(b).value(), edits);
                *note = layer ? "used: " + driver_at(*cached, i).place->binding_cache.file : "not used: " + layer.error().message;
                if (layer) return layer;
              } else {
                *note = "not used: " + b.error().message;
              }
            }
            return DriverLayer::create(*character, skin, *driver, params, job_progress(progress, cancel), edits);
          });
    }
    r.name = driver_name(w, i);
    r.index = i;
    next.push_back(std::move(r));
  }
  driver_rigs = std::move(next);  // the rest are dropped (their binds cancelled)
}

bool Scene::any_driving() const {
  if (driving()) return true;
  const Document& w = history_.current();
  for (size_t i = 1; i < driver_count(w); ++i) {
    if (!driver_moves_skin(w, i)) continue;
    const DriverRef d = driver_at(w, i);
    for (const DriverRig& r : driver_rigs)
      if (r.index == i && r.layer && r.layer->fits(*d.driver, driver_params(w, *d.place), d.place->set_edits)) return true;
  }
  return false;
}

void Scene::document_changed() {
  if (active_ >= deformer_count(history_.current())) switch_active(0);  // its layer was removed (undo)
  params = doc().params;
  update_attachment();
  const auto& cage = doc().cage;
  if (!cage && deformer) {
    deformer.reset();
    binding.reset();
    binding_revision = next_revision();
  }
  if (needs_rebind() && !job) start_bind();
  update_stack_rigs();
  update_driver_rigs();
}

// Adds the move to `values` (#cage vertices), each vertex's share taken back into its joint's bind
// space (the joint's linear part undone), where offsets and rest positions live.
void Scene::add_move(std::vector<glm::vec3>& values, const MoveWeights& weights, const glm::dvec3& world_delta) const {
  for (size_t i = 0; i < weights.vertices.size(); ++i) {
    const uint32_t v = weights.vertices[i];
    if (v >= values.size()) continue;
    glm::dmat3 lin = v < cage_skinning.size() ? glm::dmat3(glm::mat3(cage_skinning[v])) : glm::dmat3(1.0);
    values[v] += glm::vec3(glm::inverse(lin) * weights.displacement(i, world_delta));
  }
}

Document Scene::moved(const Document& from, const MoveWeights& weights, const glm::dvec3& world_delta) const {
  std::vector<glm::vec3> offsets = from.cage_offsets;
  offsets.resize(from.cage ? from.cage->num_vertices() : 0, glm::vec3(0.f));
  add_move(offsets, weights, world_delta);
  return with_cage_offsets(from, std::move(offsets));
}

Document Scene::moved_rest(const Document& from, const MoveWeights& weights, const glm::dvec3& world_delta) const {
  if (!from.cage) return from;
  std::vector<glm::vec3> rest(from.cage_positions().begin(), from.cage_positions().end());
  add_move(rest, weights, world_delta);
  return keep_bound_scale(with_cage_positions(from, rest));
}

Document Scene::keep_bound_scale(Document d) const {
  if (d.params.scale <= 0 && binding && binding->params == d.params) {
    BindParams p = d.params;
    p.scale = binding->h;  // keep h: the mean edge length would change with the edit, and every weight with it
    d = with_params(d, p);
  }
  return d;
}

bool Scene::update_set_edits_live(const std::vector<SetEdit>& edits, std::span<const uint32_t> points) {
  if (!binding || !deformer || bound_cage != doc().cage || job || !(params == binding->params)) return false;
  if (!rebinder_ || rebinder_for_ != binding.get()) {
    std::optional<PartLabels> labels;
    if (params.separate && attachment) {
      auto l = skeleton_part_labels(*doc().character, *attachment);
      if (l) labels = std::move(l).value();
    }
    auto r = Rebinder::create(skin_rest, *doc().cage, doc().cage_positions(), params, labels ? &*labels : nullptr);
    if (!r) return false;
    rebinder_ = std::make_unique<Rebinder>(std::move(r).value());
    rebinder_for_ = binding.get();
  }
  if (!rebinder_->update(*binding, edits, points).ok()) return false;
  if (fits_attachment()) {
    if (!make_deformer().ok()) return false;  // the fit follows the new sets
  } else {
    if (!deformer->stencil_changed(points).ok()) return false;  // the deformer reads `binding` itself
    binding_revision = next_revision();
  }
  bound_edits_ = edits;
  pending_edits_ = edits;
  return true;
}

std::optional<std::string> Scene::poll_bind() {
  if (!job || !job->done()) return std::nullopt;
  auto& r = job->result();
  const bool bound = r.ok();
  std::string message;
  if (r.ok()) {
    binding = std::make_unique<Binding>(std::move(r).value());
    bound_cage = pending_cage_;
    bound_edits_ = pending_edits_;
    bound_attachment_ = pending_attachment_;
    bound_attachment_data_ = pending_attachment_data_;
    auto d = make_deformer(pending_fit_ && *pending_fit_ ? &**pending_fit_ : nullptr);
    if (d.ok()) {
      char buf[256];
      if (pending_rest_report_ && pending_rest_report_->topology)
        std::snprintf(buf, sizeof buf,
                      "cage topology edit: %zu elements added, %zu removed; %zu of %u skin points registered again in "
                      "%.3f s (the others keep their rows)",
                      pending_rest_report_->added_elements, pending_rest_report_->removed_elements,
                      pending_rest_report_->points, binding->num_points, pending_rest_report_->seconds);
      else if (pending_rest_report_ && pending_rest_report_->points < binding->num_points)
        std::snprintf(buf, sizeof buf, "rest cage edit: %zu moved vertices, %zu of %u skin points registered again in %.3f s",
                      pending_rest_report_->moved_vertices, pending_rest_report_->points, binding->num_points,
                      pending_rest_report_->seconds);
      else if (candidate_cache_->last_from_cache && candidate_cache_->made_seconds >= 0)
        std::snprintf(buf, sizeof buf, "candidate cache made in %.2f s; %u points re-weighted from it in %.3f s",
                      candidate_cache_->made_seconds, binding->num_points, binding->seconds);
      else if (candidate_cache_->last_from_cache)
        std::snprintf(buf, sizeof buf, "%u points re-weighted from the candidate cache in %.3f s (quality %.1f%%)",
                      binding->num_points, binding->seconds, 100 * binding->quality());
      else std::snprintf(buf, sizeof buf, "bound %u points to %zu elements in %.2f s (%zu skipped elements, %zu fallback points, quality %.1f%%)",
                    binding->num_points, binding->elements.size(), binding->seconds, binding->invalid_elements.size(),
                    binding->rigid_points.size(), 100 * binding->quality());
      message = buf;
    } else {
      deformer.reset();  // it read the binding just replaced
      rig_binding.reset();
      binding_revision = next_revision();
      message = "error: " + d.error().message;
    }
  } else {
    message = r.error().code == ErrorCode::kCancelled ? "bind cancelled" : "error: " + r.error().message;
  }
  job.reset();
  // the cage changed while this bind ran (an edit, undo, a new cage): bind the current one; the same
  // for parameters that moved on during a live drag or were committed while it ran
  const bool params_moved =
      bound && binding && !(binding->params == params) && (live_params || params == doc().params);
  if (doc().cage && (pending_cage_ != doc().cage || !same_set_edits(pending_edits_, doc().set_edits) ||
                     (doc().params.separate && !(pending_attachment_ == doc().attachment)) || params_moved))
    start_bind();
  return message;
}

Pose Scene::current_pose(const Playback& pb) const {
  return compose_pose(*doc().character, pb.clip, pb.player.time(), pb.player.looping(), pb.pose_override);
}

std::shared_ptr<const Binding> Scene::binding_for_jobs() const {
  // with several deformers the jobs make the whole stack's rig themselves
  if (!binding || job || active_ != 0 || deformer_count(work()) > 1 || !binding_fits(*binding, doc())) return nullptr;
  return std::make_shared<const Binding>(*binding);
}

bool Scene::driver_bound() const {
  const PatchDriver* want = doc().patch_driver.get();
  const DriverBinding& b = driver_binding;
  // bound with the driver's parameters (its own, or the document cage's: not the active layer's)
  return want && b.deformer && b.driver && b.character == doc().character && b.binding &&
         b.binding->params == patch_bind_params(driver_params(history_.current())) &&
         b.edits == history_.current().driver_place.set_edits &&
         (b.driver.get() == want || (b.driver->density == want->density && b.driver->rest == want->rest));
}

bool Scene::driving() const {
  const auto& d = doc().patch_driver;
  return driver_moves_skin(history_.current()) && d && driver_binding.layer && driver_bound() &&
         driver_binding.layer->fits(*d, driver_params(history_.current()), history_.current().driver_place.set_edits);
}

void Scene::update_pose(const Playback& pb) {
  const Character& ch = *doc().character;
  const bool show_file_skinning = pb.show_file_skinning;
  pose_ = current_pose(pb);
  const Pose& pose = pose_;
  std::vector<glm::mat4> globals = ch.skeleton.global_transforms(pose);
  joint_globals = globals;
  joint_heads.resize(globals.size());
  for (size_t i = 0; i < globals.size(); ++i) joint_heads[i] = glm::vec3(globals[i][3]);
  bones.clear();
  for (size_t i = 0; i < ch.skeleton.size(); ++i)
    if (ch.skeleton.node(i).parent >= 0) bones.push_back({static_cast<uint32_t>(ch.skeleton.node(i).parent), static_cast<uint32_t>(i)});

  skin_from_cage = false;
  skin_driven_ = false;
  gpu_frame_ = {};
  stack_combined_ = false;
  // the parametric driver's displacement (its sculpt and keyposes, carried by the skeleton), added where it
  // sits in the stack as Rig adds it; it is made on the CPU, so a driven skin is made there
  // (made on the CPU; on the GPU path they go up as displacements: GpuFrame)
  const std::vector<DriverTerm> drivers = show_file_skinning ? std::vector<DriverTerm>() : driver_displacements();
  const bool driven = !drivers.empty();
  const bool on_gpu = skin_on_gpu;
  const auto& cage = doc().cage;
  if (cage) {
    // the driver: rest cage + the artist's offsets + keyposes, carried by the skeleton (core/rig/rig.h)
    pose_document_cage(doc(), attachment ? &*attachment : nullptr, pose, posed);
    sim_shown = false;
    if (ClipSimulation* sim = simulation(pb.clip)) {
      const double t = pb.player.time();
      if (sim->frames_done() >= sim->frames_needed(t)) {
        sim->apply(t, posed);
        sim_shown = true;
      }
    }
    cage_posed = posed.positions;
    cage_linear = posed.linear;
    cage_skinning = posed.skinning;
    if (deformer && bound_cage == cage) {
      skin_posed_.resize(skin_rest.size());
      auto t0 = std::chrono::steady_clock::now();
      auto s = on_gpu ? deformer->update_maps(posed.positions, cage_vertex_frames(*binding, posed))
                      : deform_through_cage(*deformer, posed, skin_posed_);
      if (s.ok() && !show_file_skinning && (cage_stack() || driven))
        pose_stack(pb, on_gpu, drivers);
      if (s.ok() && on_gpu && !stack_combined_) {  // the active deformer's skin alone (and the drivers), as the CPU path shows it
        gpu_frame_.base = GpuFrame::Deformed{active_, &*deformer, binding_revision, nullptr, {}};
        gpu_frame_.layers.clear();
        gpu_frame_.stack = stack_document().stack;
        for (const DriverTerm& t : drivers) gpu_frame_.layers.push_back(GpuFrame::Deformed{0, nullptr, 0, t.place->mask, t.delta});
      }
      if (on_gpu) skin_driven_ = s.ok() && driven;
      gpu_frame_.built = s.ok() && on_gpu;
      deform_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      skin_from_cage = s.ok();
    }
  }
  if (show_file_skinning) skin_from_cage = false;
  skin_stale_ = skin_from_cage && on_gpu;
  if (!skin_from_cage) {
    skin_posed_ = skin_character(ch, pose);
    gpu_frame_ = {};
    stack_combined_ = false;
    // no binding yet: the driver's sculpt on the file's own skinning
    if (driven) add_drivers_alone(drivers);
  }
}

ClipSimulation* Scene::simulation(int32_t clip) {
  sim_error.clear();
  if (!doc().sim.enabled || clip < 0 || !doc().cage) return nullptr;
  auto sim = sim_cache.get(doc(), attachment ? &*attachment : nullptr, clip);
  if (!sim) {
    sim_error = sim.error().message;
    return nullptr;
  }
  return *sim;
}

void Scene::fill_simulation(int32_t clip, double budget_ms) {
  ClipSimulation* sim = simulation(clip);
  if (!sim || sim->done()) return;
  sim->advance(sim->frames_total(), budget_ms);
}

const std::vector<glm::vec3>& Scene::skin_posed() {
  if (skin_stale_) {
    skin_stale_ = false;
    skin_posed_.resize(skin_rest.size());
    // the deformer was replaced since update_pose (a bind finished) and no longer fits: the file's skinning
    bool ok = deformer && deform_through_cage(*deformer, posed, skin_posed_).ok();
    // the drivers' displacements at this frame's pose, against the document as it is now (the GPU's went
    // up with the frame)
    const std::vector<DriverTerm> drivers = ok && skin_driven_ ? driver_displacements() : std::vector<DriverTerm>();
    if (ok && stack_combined_) ok = combine_stack_on_cpu(drivers);  // the stack the GPU combined, made here too
    else if (ok) add_drivers_alone(drivers);
    if (!ok) skin_posed_ = skin_character(*doc().character, pose_);
  }
  return skin_posed_;
}

std::span<const Tri> Scene::skin_triangles() const {
  const auto& fv = skin_topology.face_vertices;
  return {reinterpret_cast<const Tri*>(fv.data()), fv.size() / 3};
}

namespace {
std::unique_ptr<Scene> make_scene(Document doc, std::optional<Binding> cached = std::nullopt) {
  auto scene = std::make_unique<Scene>(std::move(doc));
  const Character& ch = *scene->doc().character;
  for (const auto& prim : ch.primitives) scene->skin_rest.insert(scene->skin_rest.end(), prim.positions.begin(), prim.positions.end());
  scene->skin_diagonal = std::max(bounding_box(scene->skin_rest).diagonal(), 1e-9);
  scene->skin_topology = combined_topology(ch);
  if (cached) scene->adopt_binding(std::move(*cached));
  scene->document_changed();
  scene->update_pose(Playback::first_of(ch.clips));
  return scene;
}
}  // namespace

Result<std::unique_ptr<Scene>> load_scene(const std::string& character_path, const std::string& cage_path,
                                          const CharacterLoadOptions& load) {
  auto doc = document_from_files(character_path, cage_path, load);
  if (!doc) return doc.error();
  return make_scene(std::move(doc).value());
}

Result<std::unique_ptr<Scene>> load_project_scene(const std::string& project_path, ProjectOpen& out,
                                                  const std::string& character_override) {
  auto loaded = load_project(project_path, character_override, &out.missing_character);
  if (!loaded) return loaded.error();
  out.warnings.insert(out.warnings.end(), loaded->warnings.begin(), loaded->warnings.end());
  out.recovery = loaded->recovery;
  std::optional<Binding> cached;
  const Document& doc = loaded->document;
  if (!doc.binding_cache.file.empty() && doc.cage) {
    auto b = load_binding_cache(doc);
    if (b) {
      cached = std::move(b).value();
      out.notes.push_back("using the cached binding " + doc.binding_cache.file + " (no bind)");
    } else {
      out.warnings.push_back("binding cache not used: " + b.error().message + "; binding again");
    }
  }
  return make_scene(std::move(loaded->document), std::move(cached));
}

std::string demo_cage_path(const std::string& character_path) {
  std::filesystem::path p = std::filesystem::path(character_path).parent_path() / "demo_cage.obj";
  return std::filesystem::exists(p) ? p.string() : std::string();
}

std::string demo_character_path() {
  namespace fs = std::filesystem;
  std::vector<fs::path> candidates;
  char exe[4096];
  ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (n > 0) {
    exe[n] = 0;
    fs::path dir = fs::path(exe).parent_path();
    candidates.push_back(dir / "assets/demo_character.glb");
    candidates.push_back(dir.parent_path() / "assets/demo_character.glb");
  }
#ifdef CAGEWRAP_SOURCE_DIR_FOR_ASSETS
  candidates.push_back(fs::path(CAGEWRAP_SOURCE_DIR_FOR_ASSETS) / "assets/demo_character.glb");
#endif
  for (const auto& c : candidates)
    if (fs::exists(c)) return c.string();
  return {};
}

}  // namespace cagewrap::app
