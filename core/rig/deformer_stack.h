// Several deformers on one skin (issue 21, docs/deformer-stack.md): the document's own cage and its
// layers (core/document/document.h DeformerLayer), each posing the whole skin, made into one skin as
// the document's DeformerStack says, every layer's share scaled per point by its mask.
#pragma once

#include <span>

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

}  // namespace cagewrap
