#include "core/character/mirror_names.h"

#include <array>
#include <utility>

namespace cagewrap {

namespace {
bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() > suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}
bool starts_with(const std::string& s, const std::string& prefix) {
  return s.size() > prefix.size() && s.compare(0, prefix.size(), prefix) == 0;
}
}  // namespace

std::string mirror_name(const std::string& name) {
  static const std::array<std::pair<const char*, const char*>, 12> kSuffixes = {
      {{".L", ".R"}, {".l", ".r"}, {"_L", "_R"}, {"_l", "_r"}, {"-L", "-R"}, {"-l", "-r"},
       {" L", " R"}, {" l", " r"}, {".Left", ".Right"}, {"_Left", "_Right"}, {".left", ".right"},
       {"_left", "_right"}}};
  for (const auto& [l, r] : kSuffixes) {
    for (int side = 0; side < 2; ++side) {
      const std::string from = side ? r : l, to = side ? l : r;
      if (ends_with(name, from)) return name.substr(0, name.size() - from.size()) + to;
    }
  }
  static const std::array<std::pair<const char*, const char*>, 2> kPrefixes = {{{"L_", "R_"}, {"l_", "r_"}}};
  for (const auto& [l, r] : kPrefixes) {
    for (int side = 0; side < 2; ++side) {
      const std::string from = side ? r : l, to = side ? l : r;
      if (starts_with(name, from)) return to + name.substr(from.size());
    }
  }
  static const std::array<std::pair<const char*, const char*>, 3> kWords = {
      {{"Left", "Right"}, {"left", "right"}, {"LEFT", "RIGHT"}}};
  for (const auto& [l, r] : kWords) {
    for (int side = 0; side < 2; ++side) {
      const std::string from = side ? r : l, to = side ? l : r;
      size_t at = name.find(from);
      if (at != std::string::npos) return name.substr(0, at) + to + name.substr(at + from.size());
    }
  }
  return name;
}

int32_t mirror_node(const Skeleton& skeleton, uint32_t node) {
  if (node >= skeleton.size()) return -1;
  const std::string& name = skeleton.node(node).name;
  std::string other = mirror_name(name);
  if (other == name) return static_cast<int32_t>(node);
  return skeleton.find(other);
}

}  // namespace cagewrap
