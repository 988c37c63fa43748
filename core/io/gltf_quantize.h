// KHR_mesh_quantization for the glTF writer (an export's --quantize): what the quantized file holds and
// how the float character is snapped to it, so that an export measures the very values a runtime reads.
//
//   POSITION       SHORT (not normalized), q = round((p - offset) / step), one uniform step and offset per
//                  skin (over every primitive it skins) or per unskinned mesh (by its node). The
//                  dequantization p = offset + step * q is folded into the skin's inverse bind matrices
//                  (IBM * translate(offset) * scale(step)), or into the node holding an unskinned mesh. The
//                  step is uniform so that normals, skinned by the same matrices, keep their directions.
//   morph targets  SHORT (not normalized), each target with its own step (its largest offset over 32767,
//                  in the mesh's units), the difference folded into the target's animated and default
//                  weights: weight' = weight * target step / position step.
//   NORMAL         BYTE normalized (the 127 steps a component that every runtime reads).
//   WEIGHTS_n      UNSIGNED_SHORT normalized (core glTF), rounded so that each vertex's sum is 65535 exactly.
// Positions and targets keep 65535 steps over their range: the mannequin's 1.8 m in 27 um steps.
#pragma once

#include <cstdint>
#include <map>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "core/character/character.h"

namespace cagewrap {

struct GlbQuantization {
  struct Dequant {
    glm::dvec3 offset{0.0};
    double step = 1.0;
  };
  std::vector<Dequant> skins;               // per skin of the character (identity for a skin no primitive uses)
  std::map<uint32_t, Dequant> nodes;        // unskinned meshes, by the node instancing them
  // Per mesh node: each morph target's step over its primitives' position steps (a target's step in a
  // primitive is this times the primitive's position step); the factor its weights are multiplied by.
  std::map<uint32_t, std::vector<double>> target_scale;

  const Dequant& positions_of(const Primitive& p) const;
  // The weight factors of the mesh on `node` (empty when it has no targets).
  std::span<const double> target_scales(uint32_t node) const;
  // Target t's step in primitive p (its position step times the target's factor).
  double target_step(const Primitive& p, size_t t) const;
};

inline constexpr double kQuantizedRange = 32767.0;

// The quantization the writer uses for `character`.
GlbQuantization plan_glb_quantization(const Character& character);
// Snaps the character's positions, morph targets and skin weights to the values the quantized file holds
// (in the character's own units): measuring the snapped character measures the file.
void snap_to_glb_quantization(Character& character, const GlbQuantization& q);

// One vertex's weights as normalized UNSIGNED_SHORT summing to exactly 65535 (largest remainders).
std::vector<uint16_t> quantized_weights(std::span<const float> weights);
// The SHORT of value / step, clamped to the range.
int16_t quantize_short(double value, double step);

}  // namespace cagewrap
