#include "core/io/gltf_quantize.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace cagewrap {
namespace {

struct Box {
  glm::dvec3 lo{1e300}, hi{-1e300};
  void add(const glm::vec3& p) {
    lo = glm::min(lo, glm::dvec3(p));
    hi = glm::max(hi, glm::dvec3(p));
  }
  GlbQuantization::Dequant dequant() const {
    GlbQuantization::Dequant d;
    if (lo.x > hi.x) return d;
    d.offset = 0.5 * (lo + hi);
    const double half = 0.5 * std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
    d.step = half > 0.0 ? half / kQuantizedRange : 1.0;
    return d;
  }
};

}  // namespace

const GlbQuantization::Dequant& GlbQuantization::positions_of(const Primitive& p) const {
  static const Dequant identity;
  if (p.skin >= 0) return size_t(p.skin) < skins.size() ? skins[p.skin] : identity;
  auto it = nodes.find(p.node);
  return it == nodes.end() ? identity : it->second;
}

std::span<const double> GlbQuantization::target_scales(uint32_t node) const {
  auto it = target_scale.find(node);
  return it == target_scale.end() ? std::span<const double>() : std::span<const double>(it->second);
}

double GlbQuantization::target_step(const Primitive& p, size_t t) const {
  const std::span<const double> scales = target_scales(p.node);
  return positions_of(p).step * (t < scales.size() ? scales[t] : 1.0);
}

int16_t quantize_short(double value, double step) {
  const double q = std::round(value / step);
  return static_cast<int16_t>(std::clamp(q, -kQuantizedRange, kQuantizedRange));
}

std::vector<uint16_t> quantized_weights(std::span<const float> weights) {
  std::vector<uint16_t> out(weights.size(), 0);
  if (weights.empty()) return out;
  double sum = 0.0;
  for (float w : weights) sum += std::max(0.0f, w);
  if (!(sum > 0.0)) {
    out[0] = 65535;
    return out;
  }
  std::vector<double> remainder(weights.size());
  long total = 0;
  for (size_t k = 0; k < weights.size(); ++k) {
    const double x = std::max(0.0f, weights[k]) / sum * 65535.0;
    const double whole = std::floor(x);
    out[k] = static_cast<uint16_t>(whole);
    remainder[k] = x - whole;
    total += long(whole);
  }
  std::vector<size_t> order(weights.size());
  std::iota(order.begin(), order.end(), size_t(0));
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return remainder[a] > remainder[b]; });
  for (size_t i = 0; total < 65535; ++i, ++total) out[order[i % order.size()]]++;
  return out;
}

GlbQuantization plan_glb_quantization(const Character& c) {
  GlbQuantization q;
  std::vector<Box> skin_box(c.skins.size());
  std::map<uint32_t, Box> node_box;
  for (const Primitive& p : c.primitives) {
    Box* box = p.skin >= 0 ? (size_t(p.skin) < skin_box.size() ? &skin_box[p.skin] : nullptr) : &node_box[p.node];
    if (box)
      for (const glm::vec3& x : p.positions) box->add(x);
  }
  for (const Box& b : skin_box) q.skins.push_back(b.dequant());
  for (const auto& [node, b] : node_box) q.nodes[node] = b.dequant();
  // each target's largest offset in position steps, over the primitives of its mesh
  for (const Primitive& p : c.primitives) {
    if (p.morph_targets.empty()) continue;
    std::vector<double>& scale = q.target_scale[p.node];
    scale.resize(std::max(scale.size(), p.morph_targets.size()), 0.0);
    const double step = q.positions_of(p).step;
    for (size_t t = 0; t < p.morph_targets.size(); ++t)
      for (const glm::vec3& d : p.morph_targets[t])
        scale[t] = std::max({scale[t], std::abs(double(d.x)) / step, std::abs(double(d.y)) / step, std::abs(double(d.z)) / step});
  }
  for (auto& [node, scale] : q.target_scale)
    for (double& s : scale) s = s > 0.0 ? s / kQuantizedRange : 1.0;
  return q;
}

void snap_to_glb_quantization(Character& c, const GlbQuantization& q) {
  for (Primitive& p : c.primitives) {
    const GlbQuantization::Dequant& d = q.positions_of(p);
    for (glm::vec3& x : p.positions)
      for (int k = 0; k < 3; ++k) x[k] = float(d.offset[k] + d.step * quantize_short(double(x[k]) - d.offset[k], d.step));
    for (size_t t = 0; t < p.morph_targets.size(); ++t) {
      const double step = q.target_step(p, t);
      for (glm::vec3& x : p.morph_targets[t])
        for (int k = 0; k < 3; ++k) x[k] = float(step * quantize_short(double(x[k]), step));
    }
    if (p.influence_start.empty()) continue;
    for (size_t v = 0; v < p.num_vertices(); ++v) {
      std::span<float> w(p.influence_weight.data() + p.influence_start[v], p.num_influences(v));
      const std::vector<uint16_t> n = quantized_weights(w);
      for (size_t k = 0; k < w.size(); ++k) w[k] = float(n[k] / 65535.0);
    }
  }
}

}  // namespace cagewrap
