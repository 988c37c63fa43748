#include "core/rig/driver_layer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include <glm/geometric.hpp>

#include "core/cage/cage_attachment.h"
#include "core/character/skinning.h"
#include "core/deform/patch_binding.h"
#include "core/deform/set_editing.h"

namespace cagewrap {

struct DriverLayer::State {
  Binding binding;                     // PatchDeformer refers to it and to skin_rest: State never moves
  std::vector<glm::vec3> skin_rest;
  std::optional<PatchDeformer> deformer;
  PatchSurface rest;
  uint32_t density = 0;
  CageAttachment attachment;           // one "vertex" per control point
  std::optional<AttachmentSettings> attached_with;  // null: each to its closest limb
  std::vector<SetEdit> edits;                        // the set edits it was bound with (canonical)
  Skin skin;                           // the attachment's skin (its joints and inverse bind matrices)
  std::vector<glm::vec3> rest_points;  // #C
  // scratch, reused pose to pose
  std::vector<glm::mat4> joints;
  std::vector<glm::vec3> sculpted, carried_rest, carried_sculpted, offsets;
  std::vector<glm::dvec3> points;
  PatchSurface surface;
  std::vector<glm::vec3> with_sculpt, without;
  std::vector<float> reach;  // #P: how much of the sculpt each skin point takes (1 near the surface, 0 far)
};

DriverLayer::DriverLayer() : s_(std::make_unique<State>()) {}
DriverLayer::DriverLayer(DriverLayer&&) noexcept = default;
DriverLayer& DriverLayer::operator=(DriverLayer&&) noexcept = default;
DriverLayer::~DriverLayer() = default;

Result<DriverLayer> DriverLayer::create(const Character& character, std::span<const glm::vec3> skin_rest,
                                        const PatchDriver& driver, const BindParams& params, const BindProgress& progress,
                                        std::span<const SetEdit> edits) {
  if (character.skins.empty())
    return make_error(ErrorCode::kInvalidArgument, "the character has no skin for the parametric driver to follow");
  auto b = bind_skin_to_patches(skin_rest, driver.rest, driver.density, params, progress, edits);
  if (!b) return b.error();
  return create(character, skin_rest, driver, std::move(b).value(), edits);
}

Result<DriverLayer> DriverLayer::create(const Character& character, std::span<const glm::vec3> skin_rest,
                                        const PatchDriver& driver, Binding binding, std::span<const SetEdit> edits) {
  if (character.skins.empty())
    return make_error(ErrorCode::kInvalidArgument, "the character has no skin for the parametric driver to follow");
  DriverLayer layer;
  State& s = *layer.s_;
  s.binding = std::move(binding);
  s.edits = canonical_set_edits(edits);
  s.skin_rest.assign(skin_rest.begin(), skin_rest.end());
  auto d = PatchDeformer::create(s.binding, s.skin_rest, driver.rest, driver.density);
  if (!d) return d.error();
  s.deformer.emplace(std::move(d).value());
  s.rest = driver.rest;
  s.density = driver.density;
  for (const glm::dvec3& p : driver.rest.control_points()) s.rest_points.emplace_back(p);
  auto att = attach_to_closest_limb(character, s.rest_points);
  if (!att) return make_error(att.error().code, "attaching the driver's control points: " + att.error().message);
  s.attachment = std::move(att).value();
  s.skin = character.skins[s.attachment.skin];
  s.surface = driver.rest;
  // The reach: every skin point is bound to some samples, however far (a point that no sample reaches
  // follows its nearest), so a sculpt would pull the whole body a little (5 mm at the demo's feet for a
  // 6 cm push on its chest). The sculpt is taken in full within 1.5 h of the nearest sample (h: the
  // control net's scale, the binding's distance unit), fading smoothly to nothing at 3 h.
  auto samples = sample_patch_surface(driver.rest, driver.density);
  if (!samples) return samples.error();
  const std::vector<glm::vec3> at = sample_positions(driver.rest, *samples);
  const double r0 = 1.5 * s.binding.h, r1 = 3.0 * s.binding.h;
  s.reach.resize(s.skin_rest.size());
  for (size_t i = 0; i < s.skin_rest.size(); ++i) {
    double d2 = std::numeric_limits<double>::infinity();
    for (const glm::vec3& q : at) d2 = std::min(d2, double(glm::dot(q - s.skin_rest[i], q - s.skin_rest[i])));
    const double d = std::sqrt(d2);
    const double t = std::clamp((d - r0) / std::max(r1 - r0, 1e-12), 0.0, 1.0);
    s.reach[i] = static_cast<float>(1.0 - t * t * (3.0 - 2.0 * t));
  }
  return layer;
}

bool DriverLayer::fits(const PatchDriver& driver) const { return driver.density == s_->density && driver.rest == s_->rest; }
bool DriverLayer::fits(const PatchDriver& driver, const BindParams& params) const {
  return fits(driver) && s_->binding.params == patch_bind_params(params);
}
bool DriverLayer::fits(const PatchDriver& driver, const BindParams& params, std::span<const SetEdit> edits) const {
  return fits(driver, params) && std::equal(s_->edits.begin(), s_->edits.end(), edits.begin(), edits.end());
}

size_t DriverLayer::num_control_points() const { return s_->rest_points.size(); }
const Binding& DriverLayer::binding() const { return s_->binding; }

Status DriverLayer::attach(const Character& character, const AttachmentSettings* settings) {
  State& s = *s_;
  if (attached_by(settings)) return Ok{};
  if (settings && settings->mode == AttachmentMode::kFitted)
    return make_error(ErrorCode::kInvalidArgument, "a parametric driver's control points are attached rigid, smooth or by skin weights, "
                                                   "not fitted (that fits a cage's attachment to its binding)");
  for (const AttachmentOverride& o : settings ? settings->overrides : std::vector<AttachmentOverride>())
    if (o.vertex >= s.rest_points.size())
      return make_error(ErrorCode::kIndexOutOfRange, "the attachment names control point " + std::to_string(o.vertex) + ", but the driver has " +
                                                         std::to_string(s.rest_points.size()));
  auto att = settings ? attach_cage(character, s.rest_points, *settings) : attach_to_closest_limb(character, s.rest_points);
  if (!att) return make_error(att.error().code, "attaching the driver's control points: " + att.error().message);
  s.attachment = std::move(att).value();
  s.skin = character.skins[s.attachment.skin];
  s.attached_with = settings ? std::optional<AttachmentSettings>(*settings) : std::nullopt;
  return Ok{};
}

bool DriverLayer::attached_by(const AttachmentSettings* settings) const {
  return settings ? s_->attached_with && *s_->attached_with == *settings : !s_->attached_with;
}

Result<bool> DriverLayer::displacement(const PatchDriver& driver, std::span<const KeyposeSet> keyposes, const Skeleton& skeleton,
                                       const Pose& pose, std::span<const glm::mat4> globals, std::span<glm::vec3> delta) {
  s_->offsets.assign(keyposes.empty() ? 0 : s_->rest_points.size(), glm::vec3(0.0f));
  if (!keyposes.empty()) evaluate_keyposes(keyposes, skeleton, pose, s_->offsets);
  return displacement(driver, s_->offsets, globals, delta);
}

Result<bool> DriverLayer::displacement(const PatchDriver& driver, std::span<const glm::vec3> offsets,
                                       std::span<const glm::mat4> globals, std::span<glm::vec3> delta) {
  State& s = *s_;
  if (!fits(driver)) return make_error(ErrorCode::kInvalidArgument, "the parametric driver changed since it was bound");
  if (delta.size() != s.skin_rest.size())
    return make_error(ErrorCode::kTopologyMismatch, "the skin has " + std::to_string(delta.size()) + " points, the driver's binding " +
                                                        std::to_string(s.skin_rest.size()));
  const std::vector<glm::dvec3> posed = driver.posed.control_points();
  const size_t nc = s.rest_points.size();
  if (posed.size() != nc)
    return make_error(ErrorCode::kTopologyMismatch, "the driver's posed surface has another number of control points");
  if (!offsets.empty() && offsets.size() != nc)
    return make_error(ErrorCode::kTopologyMismatch, "the driver's keyposes give " + std::to_string(offsets.size()) +
                                                        " offsets for " + std::to_string(nc) + " control points");
  const bool keyed = std::any_of(offsets.begin(), offsets.end(), [](const glm::vec3& o) { return o != glm::vec3(0.0f); });
  if (driver.posed == driver.rest && !keyed) {  // no sculpt
    std::fill(delta.begin(), delta.end(), glm::vec3(0.0f));
    return false;
  }
  s.sculpted.resize(nc);
  for (size_t c = 0; c < nc; ++c) s.sculpted[c] = glm::vec3(posed[c]) + (offsets.empty() ? glm::vec3(0.0f) : offsets[c]);
  s.joints.resize(s.skin.joints.size());
  joint_matrices(s.skin, globals, s.joints);
  s.carried_rest.resize(nc);
  s.carried_sculpted.resize(nc);
  pose_cage(s.attachment, s.joints, s.rest_points, s.carried_rest);
  pose_cage(s.attachment, s.joints, s.sculpted, s.carried_sculpted);
  const size_t np = delta.size();
  s.with_sculpt.resize(np);
  s.without.resize(np);
  s.points.resize(nc);
  for (size_t c = 0; c < nc; ++c) s.points[c] = glm::dvec3(s.carried_sculpted[c]);
  s.surface.set_control_points(s.points);
  if (auto st = s.deformer->deform(s.surface, s.with_sculpt); !st) return st.error();
  for (size_t c = 0; c < nc; ++c) s.points[c] = glm::dvec3(s.carried_rest[c]);
  s.surface.set_control_points(s.points);
  if (auto st = s.deformer->deform(s.surface, s.without); !st) return st.error();
  for (size_t i = 0; i < np; ++i)
    delta[i] = glm::vec3(double(s.reach[i]) * (glm::dvec3(s.with_sculpt[i]) - glm::dvec3(s.without[i])));
  return true;
}

}  // namespace cagewrap
