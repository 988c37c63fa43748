#include "core/rig/deformer_stack.h"

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

Status combine_document_stack(const Document& doc, std::span<const glm::vec3> rest,
                              const std::function<const std::vector<glm::vec3>*(size_t)>& skin_of, std::vector<glm::vec3>& out) {
  const std::vector<glm::vec3>* base = deformer_muted(doc, 0) ? nullptr : skin_of(0);
  if (base) out = *base;
  else out.assign(rest.begin(), rest.end());
  std::vector<std::span<const glm::vec3>> layers;
  std::vector<std::span<const float>> masks;
  for (size_t d = 1; d < deformer_count(doc); ++d) {
    const std::vector<glm::vec3>* f = deformer_muted(doc, d) ? nullptr : skin_of(d);
    if (!f) continue;
    layers.emplace_back(*f);
    const auto& m = doc.layers[d - 1].mask;
    masks.emplace_back(m ? std::span<const float>(*m) : std::span<const float>());
  }
  return combine_stack(doc.stack, rest, layers, masks, out);
}

}  // namespace cagewrap
