// The mask brush (issue 21: a deformer's skin mask painted, as well as picked by joints or primitives):
// strokes on the skin move the weights of a deformer layer's or a parametric driver's mask toward
// view.mask.value, by view.mask.strength at the brush's centre and less toward its rim, within
// view.mask.radius along the skin (core/document/skin_brush.h, like the set-edit brush). The frame shows
// the stroke as it goes (Scene::mask_preview); the stroke is one undo step, and the mask is then the
// document's, which pose, check and the exports use. Actions: mask_paint, mask_brush,
// mask_paint_at_skin_vertex, mask_fill (workspace_actions.cpp).
#include <algorithm>
#include <cmath>

#include "app/workspace/workspace.h"

namespace cagewrap::app {

std::optional<Workspace::MaskTarget> Workspace::mask_target(bool say) {
  if (!scene_) return std::nullopt;
  const Document& w = scene_->work();
  MaskTarget t;
  if (view.mask.driver >= 0) {
    if (static_cast<size_t>(view.mask.driver) >= driver_count(w)) {
      if (say) log("error: mask: no parametric driver " + std::to_string(view.mask.driver), true);
      return std::nullopt;
    }
    t.driver = view.mask.driver;
    t.name = "driver '" + driver_name(w, static_cast<size_t>(t.driver)) + "'";
    return t;
  }
  const size_t d = scene_->active_deformer();
  if (d == 0 || d >= deformer_count(w)) {
    if (say)
      log("error: mask: the project's own cage is the base of the stack and has no mask: make a layer active (or paint a "
          "parametric driver's mask)",
          true);
    return std::nullopt;
  }
  t.layer = d;
  t.name = "deformer '" + deformer_name(w, d) + "'";
  return t;
}

const std::shared_ptr<const std::vector<float>>& Workspace::target_mask(const Document& w, const MaskTarget& t) const {
  if (t.driver >= 0) return driver_at(w, static_cast<size_t>(t.driver)).place->mask;
  return w.layers[t.layer - 1].mask;
}

Document Workspace::with_target_mask(const Document& w, const MaskTarget& t, std::shared_ptr<const std::vector<float>> mask) {
  if (t.driver >= 0) {
    DriverPlacement place = *driver_at(w, static_cast<size_t>(t.driver)).place;
    place.mask = std::move(mask);
    place.mask_source.clear();
    return with_driver_place(w, static_cast<size_t>(t.driver), std::move(place));
  }
  std::vector<DeformerLayer> layers = w.layers;
  layers[t.layer - 1].mask = std::move(mask);
  layers[t.layer - 1].mask_source.clear();
  return with_layers(w, std::move(layers));
}

void Workspace::begin_mask_stroke() {
  if (!scene_ || mask_stroke_) return;
  auto t = mask_target(true);
  if (!t) return;
  const Document& w = scene_->work();
  const auto& m = target_mask(w, *t);
  const size_t n = scene_->skin_rest.size();
  MaskStroke s{SkinBrush(scene_->skin_posed(), scene_->skin_triangles()), *t,
               m && m->size() == n ? *m : std::vector<float>(n, 1.0f)};  // no mask: every point moved in full
  mask_stroke_.emplace(std::move(s));
}

bool Workspace::mask_stroke_dab(uint32_t triangle, const glm::dvec3& hit) {
  if (!mask_stroke_) return false;
  if (view.mask.radius <= 0.0) view.mask.radius = 0.03 * scene_->skin_diagonal;
  auto pts = mask_stroke_->brush.points_within(triangle, hit, view.mask.radius);
  if (!pts) {
    log("error: mask brush: " + pts.error().message, true);
    return false;
  }
  if (pts->points.empty()) return false;
  const double value = std::clamp(double(view.mask.value), 0.0, 1.0), strength = std::clamp(double(view.mask.strength), 0.0, 1.0);
  std::vector<float>& w = mask_stroke_->weights;
  for (size_t k = 0; k < pts->points.size(); ++k) {
    const double r = pts->distance[k] / view.mask.radius;
    const double falloff = (1.0 - r * r) * (1.0 - r * r);  // 1 at the centre, 0 at the rim, smooth
    float& v = w[pts->points[k]];
    v = static_cast<float>(std::clamp(v + strength * falloff * (value - v), 0.0, 1.0));
  }
  mask_stroke_->changed = true;
  scene_->mask_preview = with_target_mask(scene_->work(), mask_stroke_->target, std::make_shared<const std::vector<float>>(w));
  return true;
}

void Workspace::end_mask_stroke() {
  if (!mask_stroke_) return;
  MaskStroke s = std::move(*mask_stroke_);
  mask_stroke_.reset();
  scene_->mask_preview.reset();
  if (!s.changed) return;
  const std::string label = "Paint the mask of " + s.target.name;
  if (scene_->apply_work(label, with_target_mask(scene_->work(), s.target, std::make_shared<const std::vector<float>>(std::move(s.weights)))))
    log(label);
}

bool Workspace::fill_mask(float value) {
  auto t = mask_target(true);
  if (!t) return false;
  if (!(value >= 0.0f && value <= 1.0f)) {
    fail("mask: a weight is 0 to 1, not " + std::to_string(value));
    return false;
  }
  const std::string label = "Fill the mask of " + t->name + " with " + std::to_string(value).substr(0, 4);
  auto mask = std::make_shared<const std::vector<float>>(scene_->skin_rest.size(), value);
  if (!scene_->apply_work(label, with_target_mask(scene_->work(), *t, std::move(mask)))) return false;
  log(label);
  return true;
}

const std::vector<glm::vec4>& Workspace::mask_colors() {
  mask_colors_.clear();
  if (!scene_ || !view.mask.painting) return mask_colors_;
  auto t = mask_target(false);
  if (!t) return mask_colors_;
  const auto& m = target_mask(scene_->stack_document(), *t);
  const size_t n = scene_->skin_rest.size();
  mask_colors_.resize(n);
  const glm::vec4 out(0.16f, 0.22f, 0.48f, 1.0f), in(1.0f, 0.55f, 0.15f, 1.0f);
  for (size_t i = 0; i < n; ++i) {
    const float w = m && m->size() == n ? (*m)[i] : 1.0f;
    mask_colors_[i] = out + (in - out) * w;
  }
  return mask_colors_;
}

}  // namespace cagewrap::app
