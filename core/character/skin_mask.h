// Skin masks (issue 21, docs/deformer-stack.md): how much a deformer layer may move each skin point,
// one weight in [0, 1] per skin vertex in skin_character order, made from a region of the character.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/base/result.h"
#include "core/character/character.h"

namespace cagewrap {

// The region of the named skeleton nodes and their descendants, feathered by the character's own
// skinning: each point's weight is the sum of its skin weights on those joints (a point of a
// primitive with no skin: 1 when the node that instances it is in the region). A name written "-name"
// leaves that node and its descendants out ("spine,-neck,-shoulder.L,-shoulder.R": the torso alone);
// each node follows the nearest named node above it. Errors: a name that is no node (naming it and the
// first names), no names, only names left out.
Result<std::vector<float>> joint_region_mask(const Character& character, std::span<const std::string> nodes);
// 1 on the points of the given primitives (file order), 0 elsewhere. Errors: an index past the primitives.
Result<std::vector<float>> primitive_mask(const Character& character, std::span<const size_t> primitives);
// A mask from its description, as the command line and the editor take it and a project records it
// (DeformerLayer::mask_source): "joints a,b,-c" (joint_region_mask), "primitives 0,2" (primitive_mask) or
// "meshes body,1" (every primitive of those glTF meshes, by name or index).
// Errors name what is wrong (an unknown kind, a name that is no node, an index that is no primitive).
Result<std::vector<float>> skin_mask_from_source(const Character& character, std::string_view source);

}  // namespace cagewrap
