// Several deformers on one skin (issue 21, docs/deformer-stack.md): the document's own cage and its
// layers (core/document/document.h DeformerLayer), each posing the whole skin, made into one skin as
// the document's DeformerStack says, every layer's share scaled per point by its mask.
#pragma once

#include <functional>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "core/base/result.h"
#include "core/document/document.h"

namespace cagewrap {

// `skin` holds the document's cage's skin (f_0) and receives the result. `rest` is the rest skin,
// `layers` each layer's posed skin, `masks` each layer's mask (empty: 1 everywhere); all #P.
// Computed in double. Errors: sizes that differ, a blend exponent that is negative or not finite.
Status combine_stack(const DeformerStack& stack, std::span<const glm::vec3> rest,
                     std::span<const std::span<const glm::vec3>> layers, std::span<const std::span<const float>> masks,
                     std::span<glm::vec3> skin);

// A parametric driver's displacement (#P; core/rig/driver_layer.h) and its placement (where it sits, its
// mask): scaled by the mask, it is added where the driver sits (kInOrder: after driver_position(doc, place)
// layers; sum and blend: to the combined skin).
struct DriverTerm {
  std::span<const glm::vec3> delta;
  const DriverPlacement* place = nullptr;
};

// The layers of a whole document combined into `skin` (#P: the document's cage's skin f_0, or the rest skin
// when it is muted; receives the result): `layer_skins[k]` is layer k's posed skin (#P), or empty when it
// is left out; muted layers are left out whatever it holds. `drivers`: the parametric drivers that move the
// skin (the caller leaves out the muted ones and those with no displacement).
Status combine_layers(const Document& doc, std::span<const glm::vec3> rest, std::span<const std::span<const glm::vec3>> layer_skins,
                      std::span<const DriverTerm> drivers, std::span<glm::vec3> skin);

// The same for a whole document: `skin_of(d)` gives deformer d's posed skin (0: the document's cage, k: layer
// k - 1; null: it has none and is left out). The muted deformers are left out (a muted document cage is the
// rest skin), each layer's mask is its own; `out` (#P) receives the skin. `drivers`: as for combine_layers.
Status combine_document_stack(const Document& doc, std::span<const glm::vec3> rest,
                              const std::function<const std::vector<glm::vec3>*(size_t)>& skin_of, std::vector<glm::vec3>& out,
                              std::span<const DriverTerm> drivers = {});

}  // namespace cagewrap
