#include "core/rig/deformer_stack.h"

#include <algorithm>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/deform/deformer.h"

namespace cagewrap {

Status combine_stack(const DeformerStack& stack, std::span<const glm::vec3> rest,
                     std::span<const std::span<const glm::vec3>> layers, std::span<const std::span<const float>> masks,
                     std::span<glm::vec3> skin) {
  const size_t n = rest.size();
  if (skin.size() != n)
    return make_error(ErrorCode::kInvalidArgument, "the deformer stack: the skin has " + std::to_string(skin.size()) +
                                                       " points but the rest skin " + std::to_string(n));
  if (masks.size() != layers.size())
    return make_error(ErrorCode::kInvalidArgument, "the deformer stack: one mask per layer");
  for (size_t k = 0; k < layers.size(); ++k) {
    if (layers[k].size() != n)
      return make_error(ErrorCode::kInvalidArgument, "the deformer stack: layer " + std::to_string(k + 1) + " gives " +
                                                         std::to_string(layers[k].size()) + " points but the skin has " +
                                                         std::to_string(n));
    if (!masks[k].empty() && masks[k].size() != n)
      return make_error(ErrorCode::kInvalidArgument, "the deformer stack: layer " + std::to_string(k + 1) + "'s mask has " +
                                                         std::to_string(masks[k].size()) + " weights but the skin has " +
                                                         std::to_string(n) + " points");
  }
  if (layers.empty()) return Ok{};
  auto mask = [&](size_t k, size_t i) { return masks[k].empty() ? 1.0 : static_cast<double>(masks[k][i]); };
  if (stack.mode == StackMode::kBlend) {
    // the layers' displacements scaled by their masks, with f_0's, through the Wires blend
    std::vector<std::vector<glm::vec3>> scaled(layers.size(), std::vector<glm::vec3>(n));
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 8192), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t k = 0; k < layers.size(); ++k)
        for (size_t i = r.begin(); i != r.end(); ++i) {
          const glm::dvec3 p(rest[i]);
          scaled[k][i] = glm::vec3(p + mask(k, i) * (glm::dvec3(layers[k][i]) - p));
        }
    });
    std::vector<glm::vec3> own(skin.begin(), skin.end());
    std::vector<std::span<const glm::vec3>> all{own};
    for (const auto& s : scaled) all.emplace_back(s);
    return combine_displacements(rest, all, CombineMode::kWeighted, stack.exponent, skin);
  }
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 8192), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const glm::dvec3 p(rest[i]);
      glm::dvec3 s(skin[i]);
      for (size_t k = 0; k < layers.size(); ++k) {
        const glm::dvec3 f(layers[k][i]);
        s += stack.mode == StackMode::kInOrder ? mask(k, i) * (f - s) : mask(k, i) * (f - p);
      }
      skin[i] = glm::vec3(s);
    }
  });
  return Ok{};
}

Status combine_layers(const Document& doc, std::span<const glm::vec3> rest, std::span<const std::span<const glm::vec3>> layer_skins,
                      std::span<const DriverTerm> drivers, std::span<glm::vec3> skin) {
  if (layer_skins.size() != doc.layers.size())
    return make_error(ErrorCode::kInvalidArgument, "the deformer stack: " + std::to_string(layer_skins.size()) + " skins for " +
                                                       std::to_string(doc.layers.size()) + " layers");
  for (const DriverTerm& t : drivers) {
    const std::string who = "the parametric driver '" + (t.place && !t.place->name.empty() ? t.place->name : std::string("driver")) + "'";
    if (!t.place) return make_error(ErrorCode::kInvalidArgument, "the deformer stack: a parametric driver without its placement");
    if (t.delta.size() != rest.size())
      return make_error(ErrorCode::kInvalidArgument, "the deformer stack: " + who + " moves " + std::to_string(t.delta.size()) +
                                                         " points but the skin has " + std::to_string(rest.size()));
    const auto& dm = t.place->mask;
    if (dm && dm->size() != rest.size())
      return make_error(ErrorCode::kInvalidArgument, "the deformer stack: " + who + "'s mask has " + std::to_string(dm->size()) +
                                                         " weights but the skin has " + std::to_string(rest.size()) + " points");
  }
  // the drivers whose place is `at` layers in, added to the skin
  const auto add_drivers = [&](size_t at) {
    for (const DriverTerm& t : drivers) {
      const bool here = doc.stack.mode == StackMode::kInOrder ? driver_position(doc, *t.place) == at : at == doc.layers.size();
      if (!here) continue;
      const auto& dm = t.place->mask;
      tbb::parallel_for(tbb::blocked_range<size_t>(0, skin.size(), 8192), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t i = r.begin(); i != r.end(); ++i)
          skin[i] = glm::vec3(glm::dvec3(skin[i]) + (dm ? double((*dm)[i]) : 1.0) * glm::dvec3(t.delta[i]));
      });
    }
  };
  // kInOrder: the layers in runs between the drivers' places, each driver added where it sits; the other
  // modes combine every layer at once and add the drivers to the result
  std::vector<size_t> cuts;
  if (doc.stack.mode == StackMode::kInOrder)
    for (const DriverTerm& t : drivers) cuts.push_back(driver_position(doc, *t.place));
  cuts.push_back(doc.layers.size());
  std::sort(cuts.begin(), cuts.end());
  cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
  size_t from = 0;
  for (size_t to : cuts) {
    std::vector<std::span<const glm::vec3>> layers;
    std::vector<std::span<const float>> masks;
    for (size_t k = from; k < to; ++k) {
      if (deformer_muted(doc, k + 1) || layer_skins[k].empty()) continue;
      layers.push_back(layer_skins[k]);
      const auto& m = doc.layers[k].mask;
      masks.emplace_back(m ? std::span<const float>(*m) : std::span<const float>());
    }
    if (auto s = combine_stack(doc.stack, rest, layers, masks, skin); !s) return s;
    add_drivers(to);
    from = to;
  }
  return Ok{};
}

Status combine_document_stack(const Document& doc, std::span<const glm::vec3> rest,
                              const std::function<const std::vector<glm::vec3>*(size_t)>& skin_of, std::vector<glm::vec3>& out,
                              std::span<const DriverTerm> drivers) {
  const std::vector<glm::vec3>* base = deformer_muted(doc, 0) ? nullptr : skin_of(0);
  if (base) out = *base;
  else out.assign(rest.begin(), rest.end());
  std::vector<std::span<const glm::vec3>> layers(doc.layers.size());
  for (size_t d = 1; d < deformer_count(doc); ++d)
    if (!deformer_muted(doc, d))
      if (const std::vector<glm::vec3>* f = skin_of(d)) layers[d - 1] = *f;
  return combine_layers(doc, rest, layers, drivers, out);
}

}  // namespace cagewrap
