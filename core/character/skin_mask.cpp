#include "core/character/skin_mask.h"

#include <algorithm>
#include <cstdlib>
#include <sstream>

#include "core/character/skinning.h"

namespace cagewrap {

Result<std::vector<float>> joint_region_mask(const Character& character, std::span<const std::string> nodes) {
  const Skeleton& sk = character.skeleton;
  if (nodes.empty()) return make_error(ErrorCode::kInvalidArgument, "a joint region mask needs at least one joint");
  // each node in (1) or out (2) of the region as the nearest named node above it (or itself) says; 0 = none
  std::vector<uint8_t> state(sk.size(), 0);
  bool any_in = false;
  for (const std::string& entry : nodes) {
    const bool out = entry.starts_with('-');
    const std::string name = out ? entry.substr(1) : entry;
    const int32_t n = sk.find(name);
    if (n < 0) {
      std::string known;
      for (size_t i = 0; i < sk.size() && i < 12; ++i) known += std::string(i ? ", " : "") + sk.node(i).name;
      if (sk.size() > 12) known += ", ...";
      return make_error(ErrorCode::kInvalidArgument, character.source + ": has no node '" + name + "' (its nodes: " + known + ")");
    }
    state[static_cast<size_t>(n)] = out ? 2 : 1;
    any_in |= !out;
  }
  if (!any_in)
    return make_error(ErrorCode::kInvalidArgument, "a joint region mask needs a joint to include, not only ones to leave out (-name)");
  // descendants: a node takes its parent's state unless named (parents come before children in the order)
  for (uint32_t i : sk.order())
    if (const int32_t p = sk.node(i).parent; p >= 0 && state[i] == 0) state[i] = state[static_cast<size_t>(p)];
  std::vector<uint8_t> in(sk.size(), 0);
  for (size_t i = 0; i < sk.size(); ++i) in[i] = state[i] == 1;
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

Result<std::vector<float>> skin_mask_from_source(const Character& character, std::string_view source) {
  const size_t space = source.find(' ');
  const std::string_view kind = source.substr(0, space);
  std::vector<std::string> items;
  std::stringstream in(std::string(space == std::string_view::npos ? std::string_view() : source.substr(space + 1)));
  for (std::string item; std::getline(in, item, ',');)
    if (!item.empty()) items.push_back(item);
  if (kind == "joints") return joint_region_mask(character, items);
  if (kind == "primitives") {
    std::vector<size_t> prims;
    for (const std::string& item : items) {
      char* end = nullptr;
      const unsigned long v = std::strtoul(item.c_str(), &end, 10);
      if (*end != '\0' || item.starts_with('-'))
        return make_error(ErrorCode::kInvalidArgument, "'" + item + "' is not a primitive index (0, 1, ...)");
      prims.push_back(v);
    }
    if (prims.empty()) return make_error(ErrorCode::kInvalidArgument, "a primitive mask needs at least one primitive index");
    return primitive_mask(character, prims);
  }
  if (kind == "meshes") {  // every primitive of the glTF meshes named (or numbered)
    std::vector<size_t> prims;
    for (const std::string& item : items) {
      size_t found = 0;
      for (size_t k = 0; k < character.primitives.size(); ++k) {
        const Primitive& p = character.primitives[k];
        if (p.mesh_name == item || std::to_string(p.mesh) == item) prims.push_back(k), ++found;
      }
      if (found == 0) {
        std::string names;
        for (const Primitive& p : character.primitives)
          if (names.find("'" + p.mesh_name + "'") == std::string::npos) names += (names.empty() ? "" : ", ") + std::to_string(p.mesh) + " '" + p.mesh_name + "'";
        return make_error(ErrorCode::kInvalidArgument, character.source + ": has no mesh named or numbered '" + item + "' (its meshes: " + names + ")");
      }
    }
    if (items.empty()) return make_error(ErrorCode::kInvalidArgument, "a mesh mask needs at least one mesh name or index");
    return primitive_mask(character, prims);
  }
  return make_error(ErrorCode::kInvalidArgument,
                    "a mask is \"joints a,b,-c\", \"primitives 0,2\" or \"meshes body,head\", not \"" + std::string(source) + "\"");
}

}  // namespace cagewrap
