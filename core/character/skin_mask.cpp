#include "core/character/skin_mask.h"

#include <algorithm>

#include "core/character/skinning.h"

namespace cagewrap {

Result<std::vector<float>> joint_region_mask(const Character& character, std::span<const std::string> nodes) {
  const Skeleton& sk = character.skeleton;
  if (nodes.empty()) return make_error(ErrorCode::kInvalidArgument, "a joint region mask needs at least one joint");
  std::vector<uint8_t> in(sk.size(), 0);
  for (const std::string& name : nodes) {
    const int32_t n = sk.find(name);
    if (n < 0) {
      std::string known;
      for (size_t i = 0; i < sk.size() && i < 12; ++i) known += std::string(i ? ", " : "") + sk.node(i).name;
      if (sk.size() > 12) known += ", ...";
      return make_error(ErrorCode::kInvalidArgument, character.source + ": has no node '" + name + "' (its nodes: " + known + ")");
    }
    in[static_cast<size_t>(n)] = 1;
  }
  // descendants: a node is in when its parent is (parents come before children in the skeleton's order)
  for (uint32_t i : sk.order())
    if (const int32_t p = sk.node(i).parent; p >= 0 && in[static_cast<size_t>(p)]) in[i] = 1;
  const PointJoints pj = point_joint_nodes(character);
  std::vector<float> mask(pj.start.size() - 1, 0.0f);
  for (size_t p = 0; p < mask.size(); ++p) {
    float w = 0.0f;
    for (uint32_t i = pj.start[p]; i < pj.start[p + 1]; ++i)
      if (in[pj.node[i]]) w += pj.weight[i];
    mask[p] = std::clamp(w, 0.0f, 1.0f);
  }
  return mask;
}

Result<std::vector<float>> primitive_mask(const Character& character, std::span<const size_t> primitives) {
  std::vector<float> mask(character.num_vertices(), 0.0f);
  for (size_t k : primitives)
    if (k >= character.primitives.size())
      return make_error(ErrorCode::kIndexOutOfRange, character.source + ": has no primitive " + std::to_string(k) + " (it has " +
                                                         std::to_string(character.primitives.size()) + ")");
  size_t start = 0;
  for (size_t k = 0; k < character.primitives.size(); ++k) {
    const size_t n = character.primitives[k].num_vertices();
    if (std::find(primitives.begin(), primitives.end(), k) != primitives.end()) std::fill_n(mask.begin() + start, n, 1.0f);
    start += n;
  }
  return mask;
}

}  // namespace cagewrap
