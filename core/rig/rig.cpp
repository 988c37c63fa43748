#include "core/rig/rig.h"
#include "core/rig/deformer_stack.h"
#include "core/rig/driver_layer.h"

#include <optional>

#include "core/deform/attachment_fit.h"
#include "core/rig/clip_sim.h"
#include "core/deform/part_labels.h"

#include <chrono>
#include <cmath>
#include <algorithm>
#include <cstring>
#include <numbers>

#include "core/base/check.h"
#include "core/character/skinning.h"

namespace cagewrap {

Pose compose_pose(const Character& character, int32_t clip, double t, bool loop,
                  std::span<const glm::quat> overrides) {
  Pose pose = sample_pose(character, clip, t, loop);
  for (size_t i = 0; i < overrides.size() && i < pose.local.size(); ++i)
    pose.local[i].rotation = glm::normalize(pose.local[i].rotation * overrides[i]);
  return pose;
}

glm::quat rotation_xyz_degrees(double rx, double ry, double rz) {
  constexpr double kRad = std::numbers::pi / 180.0;
  glm::dquat q = glm::angleAxis(rz * kRad, glm::dvec3(0, 0, 1)) *
                 glm::angleAxis(ry * kRad, glm::dvec3(0, 1, 0)) *
                 glm::angleAxis(rx * kRad, glm::dvec3(1, 0, 0));
  return glm::quat(glm::normalize(q));
}

void pose_document_cage(const Document& doc, const CageAttachment* attachment, const Pose& pose,
                        PosedCage& out) {
  CAGEWRAP_CHECK(doc.cage && doc.character, "posing a cage needs a document with a character and a cage");
  const Character& ch = *doc.character;
  const size_t nv = doc.cage->num_vertices();
  out.globals.resize(ch.skeleton.size());
  ch.skeleton.global_transforms(pose, out.globals);
  out.keypose_offsets.resize(nv);
  evaluate_keyposes(doc.keyposes, ch.skeleton, pose, out.keypose_offsets);
  const auto rest = doc.cage_positions();
  out.driver_rest.resize(nv);
  for (size_t v = 0; v < nv; ++v) {
    out.driver_rest[v] = rest[v] + out.keypose_offsets[v];
    if (v < doc.cage_offsets.size()) out.driver_rest[v] += doc.cage_offsets[v];
  }
  out.positions.resize(nv);
  out.linear.resize(nv);
  out.skinning.resize(nv);
  out.attached = attachment && attachment->joint.size() == nv && attachment->skin < ch.skins.size();
  if (out.attached) {
    const Skin& skin = ch.skins[attachment->skin];
    std::vector<glm::mat4> joints(skin.joints.size());
    joint_matrices(skin, out.globals, joints);
    pose_cage(*attachment, joints, out.driver_rest, out.positions, out.linear, out.skinning);
  } else {
    out.positions = out.driver_rest;
    std::fill(out.linear.begin(), out.linear.end(), glm::dmat3(1.0));
    std::fill(out.skinning.begin(), out.skinning.end(), glm::mat4(1.0f));
  }
}

std::span<const glm::dmat3> cage_vertex_frames(const Binding& binding, const PosedCage& cage) {
  const bool frames = binding.params.variant == Variant::kExtended && cage.attached;
  return frames ? std::span<const glm::dmat3>(cage.linear) : std::span<const glm::dmat3>();
}

Status deform_through_cage(Deformer& deformer, const PosedCage& cage, std::span<glm::vec3> skin_out) {
  return deformer.deform(cage.positions, skin_out, cage_vertex_frames(deformer.binding(), cage));
}

struct Rig::State {
  Document doc;  // the document the rig was made for (its cage, parameters, set edits, attachment)
  std::vector<glm::vec3> skin_rest;  // #P
  std::optional<CageAttachment> attachment;
  Binding binding;                   // the registration (sets, the cache)
  std::optional<Binding> fitted;     // the stencil the deformer reads when fit_rig smoothed it
  std::optional<Deformer> deformer;  // refers to fitted or binding and skin_rest: State never moves
  SimCache sims;                     // the simulated clips (pose_clip)
  // the document's deformer layers that are not muted (issue 21): each a rig of its own
  // (layer_document), combined with this one's skin by the document's stack
  std::vector<size_t> layer_index;
  std::vector<std::unique_ptr<Rig>> layers;
  std::vector<std::vector<glm::vec3>> layer_skins;  // #P each, reused frame to frame
  PosedCage layer_cage;
  // the parametric drivers that drive the skin (core/rig/driver_layer.h): their sculpts, carried by the
  // skeleton, added where each sits in the stack
  std::vector<size_t> driver_index;        // which of the document's drivers (driver_at)
  std::vector<DriverLayer> drivers;
  std::vector<std::vector<glm::vec3>> driver_deltas;  // #P each, reused frame to frame
  // Each layer's skin posed by `pose_layer(layer rig, layer document, out)`, the parametric driver's displacement
  // at `pose` (node world transforms `globals`), then all combined with `skin_out` (f_0) by the document's stack.
  template <class PoseLayer>
  Status pose_stack(const Document& doc, const Pose& pose, std::span<const glm::mat4> globals, std::span<glm::vec3> skin_out,
                    PoseLayer pose_layer);
};

template <class PoseLayer>
Status Rig::State::pose_stack(const Document& doc, const Pose& pose, std::span<const glm::mat4> globals,
                              std::span<glm::vec3> skin_out, PoseLayer pose_layer) {
  if (layers.empty() && drivers.empty()) return Ok{};
  std::vector<std::span<const glm::vec3>> skins(doc.layers.size());
  for (size_t k = 0; k < layers.size(); ++k) {
    const DeformerLayer& l = doc.layers[layer_index[k]];
    if (auto s = pose_layer(*layers[k], layer_document(doc, layer_index[k]), layer_skins[k]); !s)
      return make_error(s.error().code, "deformer '" + l.name + "': " + s.error().message);
    skins[layer_index[k]] = layer_skins[k];
  }
  std::vector<DriverTerm> terms;
  for (size_t k = 0; k < drivers.size(); ++k) {
    const DriverRef d = driver_at(doc, driver_index[k]);
    driver_deltas[k].resize(skin_rest.size());
    auto any = drivers[k].displacement(*d.driver, d.place->keyposes, doc.character->skeleton, pose, globals, driver_deltas[k]);
    if (!any) return make_error(any.error().code, "parametric driver '" + driver_name(doc, driver_index[k]) + "': " + any.error().message);
    if (*any) terms.push_back({driver_deltas[k], d.place});
  }
  return combine_layers(doc, skin_rest, skins, terms, skin_out);
}

Rig::Rig() = default;
Rig::Rig(Rig&&) noexcept = default;
Rig& Rig::operator=(Rig&&) noexcept = default;
Rig::~Rig() = default;

namespace {
std::optional<PartLabels> document_labels(const Document& doc, const CageAttachment* attachment) {
  if (!doc.params.separate || !attachment || !doc.character) return std::nullopt;
  auto l = skeleton_part_labels(*doc.character, *attachment);
  if (!l) return std::nullopt;  // without labels the bind simply does not separate
  return std::move(l).value();
}
}  // namespace

Result<Binding> bind_document(const Document& doc, std::span<const glm::vec3> skin_rest, const CageAttachment* attachment,
                              const BindProgress& progress) {
  if (!doc.cage) return make_error(ErrorCode::kInvalidArgument, "the document has no cage to bind to");
  const std::optional<PartLabels> labels = document_labels(doc, attachment);
  return bind_skin(skin_rest, *doc.cage, doc.cage_positions(), doc.params, doc.set_edits, progress, labels ? &*labels : nullptr);
}

Result<Binding> bind_document_cached(const Document& doc, std::span<const glm::vec3> skin_rest, const CageAttachment* attachment,
                                     CandidateCacheSlot& slot, bool make, const BindProgress& progress) {
  slot.last_from_cache = false;
  slot.made_seconds = -1;
  if (!doc.cage) return make_error(ErrorCode::kInvalidArgument, "the document has no cage to bind to");
  const std::optional<PartLabels> labels = document_labels(doc, attachment);
  const PartLabels* l = labels ? &*labels : nullptr;
  const auto rest = doc.cage_positions();
  if (slot.cache && !slot.cache->fits(skin_rest, *doc.cage, rest, l)) slot.cache.reset();  // another skin, cage or labels
  if (!slot.cache && make) {
    // the cache's making is most of the first bind: its progress, then the re-weighting's
    BindProgress first = progress;
    if (progress.on_progress) first.on_progress = [&progress](double f) { progress.on_progress(0.8 * f); };
    auto made = CandidateCache::create(skin_rest, *doc.cage, rest, doc.params, l, first);
    if (!made) return made.error();
    slot.made_seconds = made->seconds();
    slot.cache = std::make_shared<const CandidateCache>(std::move(made).value());
  }
  if (!slot.cache) return bind_skin(skin_rest, *doc.cage, rest, doc.params, doc.set_edits, progress, l);
  BindProgress rest_of = progress;
  if (progress.on_progress && slot.made_seconds >= 0)
    rest_of.on_progress = [&progress](double f) { progress.on_progress(0.8 + 0.2 * f); };
  auto b = slot.cache->bind(doc.params, doc.set_edits, rest_of);
  slot.last_from_cache = b.ok();
  return b;
}

bool rest_edit_params_fit(const BindParams& bound, double h, const BindParams& now) {
  if (!(now.scale > 0)) return false;
  BindParams b = bound;
  if (b.scale <= 0) b.scale = h;
  return b == now;
}

Result<Binding> rebind_document(const Document& doc, std::span<const glm::vec3> skin_rest, const CageAttachment* attachment,
                                Binding previous, const CageAttachment* previous_attachment,
                                const BindProgress& progress, RestRebindReport* report,
                                const std::vector<SetEdit>* previous_edits) {
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  if (doc.cage && rest_edit_params_fit(previous.params, previous.h, doc.params) && previous.num_points == skin_rest.size()) {
    previous.params.scale = previous.h;  // the same binding: h came out as this scale
    const auto labels = document_labels(doc, attachment);
    // the labels the previous binding was made with: the same unless the attachment changed (each
    // labelling is a pass over the whole skin)
    const bool same_attachment = attachment == previous_attachment ||
                                 (attachment && previous_attachment && *attachment == *previous_attachment);
    const auto before = same_attachment ? std::nullopt : document_labels(doc, previous_attachment);
    const PartLabels* before_labels = same_attachment ? (labels ? &*labels : nullptr) : (before ? &*before : nullptr);
    if (previous.elements == doc.cage->elements && previous.rest_cage.size() == doc.cage->num_vertices()) {
      auto r = rebind_moved_rest(previous, skin_rest, *doc.cage, doc.cage_positions(), doc.set_edits,
                                 labels ? &*labels : nullptr, before_labels);
      if (r) {
        if (report) *report = *r, report->seconds = elapsed();
        if (progress.on_progress) progress.on_progress(1.0);
        return previous;
      }
    } else {
      auto r = rebind_new_topology(previous, skin_rest, *doc.cage, doc.cage_positions(), doc.set_edits,
                                   previous_edits ? std::span<const SetEdit>(*previous_edits) : std::span<const SetEdit>(doc.set_edits),
                                   labels ? &*labels : nullptr, before_labels);
      if (r) {
        if (report) {
          *report = RestRebindReport{};
          report->points = r->points;
          report->seconds = elapsed();
          report->topology = true;
          report->added_elements = r->added_elements;
          report->removed_elements = r->removed_elements;
        }
        if (progress.on_progress) progress.on_progress(1.0);
        return previous;
      }
    }
  }
  auto full = bind_document(doc, skin_rest, attachment, progress);
  if (full && report) *report = {doc.cage ? doc.cage->num_vertices() : 0, full->num_points, elapsed()};
  return full;
}

Result<Rig> Rig::create(const Document& doc, const BindProgress& progress) {
  return make(doc, {}, progress);
}

Result<Rig> Rig::create(const Document& doc, Binding binding) {
  std::vector<std::optional<Binding>> bindings(1);
  bindings[0] = std::move(binding);
  return make(doc, std::move(bindings), {});
}

Result<Rig> Rig::create(const Document& doc, std::vector<std::optional<Binding>> bindings, const BindProgress& progress,
                        std::vector<std::optional<Binding>> driver_bindings) {
  return make(doc, std::move(bindings), progress, std::move(driver_bindings));
}

Result<Rig> Rig::make(const Document& doc, std::vector<std::optional<Binding>> bindings, const BindProgress& progress,
                      std::vector<std::optional<Binding>> driver_bindings) {
  if (!doc.character) return make_error(ErrorCode::kInvalidArgument, "the document has no character");
  if (!doc.cage)
    return make_error(ErrorCode::kInvalidArgument, "the document has no cage to pose the skin with");
  Rig rig;
  rig.state_ = std::make_unique<State>();
  State& s = *rig.state_;
  s.doc = doc;
  const Character& ch = *doc.character;
  if (!ch.skins.empty()) {
    auto att = attach_cage(ch, doc.cage_positions(), doc.attachment, doc.cage->elements);
    if (!att) return make_error(att.error().code, "attachment: " + att.error().message);
    s.attachment = std::move(att).value();
  }
  for (const Primitive& p : ch.primitives)
    s.skin_rest.insert(s.skin_rest.end(), p.positions.begin(), p.positions.end());
  if (!bindings.empty() && bindings[0]) {
    s.binding = std::move(*bindings[0]);
  } else {
    auto bound = bind_document(doc, s.skin_rest, s.attachment ? &*s.attachment : nullptr, progress);
    if (!bound) return make_error(bound.error().code, "bind: " + bound.error().message);
    s.binding = std::move(bound).value();
  }
  if (s.attachment && doc.attachment.mode == AttachmentMode::kFitted) {
    auto f = fit_rig(ch, s.binding, doc.attachment, *s.attachment);
    if (!f) return make_error(f.error().code, "attachment: " + f.error().message);
    s.fitted = std::move(f).value();
  }
  auto deformer = Deformer::create(s.fitted ? *s.fitted : s.binding, s.skin_rest);
  if (!deformer) return make_error(deformer.error().code, "bind: " + deformer.error().message);
  s.deformer.emplace(std::move(deformer).value());
  for (size_t i = 0; i < doc.layers.size(); ++i) {
    const DeformerLayer& l = doc.layers[i];
    if (deformer_muted(doc, i + 1)) continue;  // muted, or another deformer soloed
    if (l.mask && l.mask->size() != s.skin_rest.size())
      return make_error(ErrorCode::kTopologyMismatch, "deformer '" + l.name + "': its mask has " + std::to_string(l.mask->size()) +
                                                          " weights but the skin has " + std::to_string(s.skin_rest.size()) + " points");
    auto layer = i + 1 < bindings.size() && bindings[i + 1] ? Rig::create(layer_document(doc, i), std::move(*bindings[i + 1]))
                                                            : Rig::create(layer_document(doc, i), progress);
    if (!layer) return make_error(layer.error().code, "deformer '" + l.name + "': " + layer.error().message);
    s.layer_index.push_back(i);
    s.layers.push_back(std::make_unique<Rig>(std::move(layer).value()));
    s.layer_skins.emplace_back(s.skin_rest.size());
  }
  for (size_t i = 0; i < driver_count(doc); ++i) {
    if (!driver_moves_skin(doc, i)) continue;
    const DriverRef r = driver_at(doc, i);
    if (r.place->mask && r.place->mask->size() != s.skin_rest.size())
      return make_error(ErrorCode::kTopologyMismatch, "parametric driver '" + driver_name(doc, i) + "': its mask has " +
                                                          std::to_string(r.place->mask->size()) + " weights but the skin has " +
                                                          std::to_string(s.skin_rest.size()) + " points");
    auto d = i < driver_bindings.size() && driver_bindings[i]
                 ? DriverLayer::create(ch, s.skin_rest, *r.driver, std::move(*driver_bindings[i]), r.place->set_edits)
                 : DriverLayer::create(ch, s.skin_rest, *r.driver, driver_params(doc, *r.place), progress, r.place->set_edits);
    if (!d) return make_error(d.error().code, "parametric driver '" + driver_name(doc, i) + "': " + d.error().message);
    if (r.place->attachment)
      if (auto a = d->attach(ch, &*r.place->attachment); !a)
        return make_error(a.error().code, "parametric driver '" + driver_name(doc, i) + "': " + a.error().message);
    s.driver_index.push_back(i);
    s.drivers.push_back(std::move(d).value());
    s.driver_deltas.emplace_back();
  }
  return rig;
}

const Binding* Rig::layer_binding(size_t layer) const {
  for (size_t k = 0; k < state_->layers.size(); ++k)
    if (state_->layer_index[k] == layer) return &state_->layers[k]->binding();
  return nullptr;
}

const Binding* Rig::driver_binding(size_t driver) const {
  for (size_t k = 0; k < state_->drivers.size(); ++k)
    if (state_->driver_index[k] == driver) return &state_->drivers[k].binding();
  return nullptr;
}

bool Rig::fits(const Document& doc) const {
  const Document& mine = state_->doc;
  if (!doc.cage || !doc.character) return false;
  if (doc.character != mine.character && doc.character_hash != mine.character_hash) return false;
  if (doc.cage != mine.cage) {
    const PolyMesh &a = doc.cage->polygons, &b = mine.cage->polygons;
    if (a.face_start != b.face_start || a.face_vertices != b.face_vertices ||
        a.positions.size() != b.positions.size() ||
        std::memcmp(a.positions.data(), b.positions.data(), a.positions.size() * sizeof(glm::vec3)) != 0)
      return false;
  }
  if (!same_params(doc.params, mine.params) || !same_set_edits(doc.set_edits, mine.set_edits) ||
      !(doc.attachment == mine.attachment))
    return false;
  // the same layers, bound the same way (their offsets, keyposes, masks and the stack may differ)
  if (doc.layers.size() != mine.layers.size()) return false;
  for (size_t i = 0; i < doc.layers.size(); ++i)
    if (deformer_muted(doc, i + 1) != deformer_muted(mine, i + 1)) return false;
  for (size_t k = 0; k < state_->layers.size(); ++k)
    if (!state_->layers[k]->fits(layer_document(doc, state_->layer_index[k]))) return false;
  // the same parametric driver surfaces and densities, for those that drive the skin (their sculpts may differ)
  size_t k = 0;
  for (size_t i = 0; i < driver_count(doc); ++i) {
    if (!driver_moves_skin(doc, i)) continue;
    if (k >= state_->drivers.size() || state_->driver_index[k] != i) return false;
    const DriverRef r = driver_at(doc, i);
    if (!state_->drivers[k].fits(*r.driver, driver_params(doc, *r.place), r.place->set_edits)) return false;
    if (!state_->drivers[k].attached_by(r.place->attachment ? &*r.place->attachment : nullptr)) return false;
    ++k;
  }
  return k == state_->drivers.size();
}

Status Rig::pose(const Document& doc, const Pose& pose, PosedCage& cage, std::span<glm::vec3> skin_out) {
  CAGEWRAP_CHECK(fits(doc),
                 "Rig::pose: the document has another cage, binding parameters or attachment than the rig");
  CAGEWRAP_CHECK(skin_out.size() == state_->skin_rest.size(), "one output position per skin point");
  pose_document_cage(doc, state_->attachment ? &*state_->attachment : nullptr, pose, cage);
  if (auto s = deform_through_cage(*state_->deformer, cage, skin_out); !s) return s;
  if (deformer_muted(doc, 0)) std::copy(state_->skin_rest.begin(), state_->skin_rest.end(), skin_out.begin());  // f_0 = p
  return state_->pose_stack(doc, pose, cage.globals, skin_out, [&](Rig& layer, const Document& d, std::vector<glm::vec3>& out) {
    return layer.pose(d, pose, state_->layer_cage, out);
  });
}

Status Rig::pose_clip(const Document& doc, int32_t clip, double t, std::span<const glm::quat> overrides,
                      PosedCage& cage, std::span<glm::vec3> skin_out) {
  CAGEWRAP_CHECK(fits(doc),
                 "Rig::pose_clip: the document has another cage, binding parameters or attachment than the rig");
  CAGEWRAP_CHECK(skin_out.size() == state_->skin_rest.size(), "one output position per skin point");
  const Character& ch = *doc.character;
  if (clip >= 0) t = clip_time(t, ch.clips[static_cast<size_t>(clip)].duration, false);
  const Pose pose = compose_pose(ch, clip, t, false, overrides);
  if (auto s = pose_simulated_cage(state_->sims, doc, attachment(), clip, t, pose, cage); !s) return s;
  if (auto s = deform_through_cage(*state_->deformer, cage, skin_out); !s) return s;
  if (deformer_muted(doc, 0)) std::copy(state_->skin_rest.begin(), state_->skin_rest.end(), skin_out.begin());  // f_0 = p
  return state_->pose_stack(doc, pose, cage.globals, skin_out, [&](Rig& layer, const Document& d, std::vector<glm::vec3>& out) {
    return layer.pose_clip(d, clip, t, overrides, state_->layer_cage, out);
  });
}

size_t Rig::num_skin_points() const { return state_->skin_rest.size(); }
std::span<const glm::vec3> Rig::skin_rest() const { return state_->skin_rest; }
const Binding& Rig::binding() const { return state_->binding; }
const Binding& Rig::deformer_binding() const { return state_->fitted ? *state_->fitted : state_->binding; }
const CageAttachment* Rig::attachment() const { return state_->attachment ? &*state_->attachment : nullptr; }

Status Rig::pose_clip_cage(const Document& doc, int32_t clip, double t, std::span<const glm::quat> overrides,
                           PosedCage& cage) {
  CAGEWRAP_CHECK(fits(doc),
                 "Rig::pose_clip_cage: the document has another cage, binding parameters or attachment than the rig");
  const Character& ch = *doc.character;
  if (clip >= 0) t = clip_time(t, ch.clips[static_cast<size_t>(clip)].duration, false);
  return pose_simulated_cage(state_->sims, doc, attachment(), clip, t, compose_pose(ch, clip, t, false, overrides),
                             cage);
}

Deformer& Rig::deformer() { return *state_->deformer; }

}  // namespace cagewrap
