#include "core/deform/twist.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

namespace cagewrap {

glm::dvec3 Twist::apply(const glm::dvec3& p) const {
  double t = std::clamp((p[axis] - lo) / (hi - lo), 0.0, 1.0);
  double s = t * t * (3 - 2 * t);
  double theta = degrees * M_PI / 180.0 * s;
  int i = (axis + 1) % 3, j = (axis + 2) % 3;
  glm::dvec3 q = p;
  q[i] = center[i] + (p[i] - center[i]) * std::cos(theta) - (p[j] - center[j]) * std::sin(theta);
  q[j] = center[j] + (p[i] - center[i]) * std::sin(theta) + (p[j] - center[j]) * std::cos(theta);
  return q;
}

Result<Twist> load_twist(const std::string& path) {
  std::ifstream in(path);
  if (!in) return make_error(ErrorCode::kFileNotFound, path + ": cannot be opened");
  try {
    auto j = nlohmann::json::parse(in);
    const auto& tw = j.at("twist");
    Twist t;
    t.axis = tw.at("axis").get<int>();
    auto c = tw.at("center");
    t.center = {c.at(0).get<double>(), c.at(1).get<double>(), c.at(2).get<double>()};
    t.lo = tw.at("lo").get<double>();
    t.hi = tw.at("hi").get<double>();
    t.degrees = tw.at("twist_deg").get<double>();
    if (t.axis < 0 || t.axis > 2 || !(t.hi > t.lo))
      return make_error(ErrorCode::kParse, path + ": twist has a bad axis or an empty [lo, hi] range");
    return t;
  } catch (const std::exception& e) {
    return make_error(ErrorCode::kParse, path + ": " + e.what());
  }
}

Fidelity relative_distance(std::span<const glm::vec3> a, std::span<const glm::vec3> b, double diagonal) {
  // a programming error, not bad data: checked in every build type (b[i] would read past the end)
  if (a.size() != b.size()) {
    std::fprintf(stderr, "relative_distance: point sets of %zu and %zu points; they must be equal\n", a.size(),
                 b.size());
    std::abort();
  }
  Fidelity f;
  double sum = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    double d = glm::length(glm::dvec3(a[i]) - glm::dvec3(b[i]));
    sum += d * d;
    f.max = std::max(f.max, d);
  }
  f.rms = a.empty() ? 0 : std::sqrt(sum / a.size()) / diagonal;
  f.max /= diagonal;
  return f;
}

}  // namespace cagewrap
