#include "core/cage/keyposes.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "core/character/joint_angles.h"
#include "core/character/mirror_names.h"
#include "core/geometry/selection.h"

namespace cagewrap {

namespace {
constexpr double kDeg = 180.0 / std::numbers::pi;
constexpr double kSameValue = 1e-9;  // degrees: keys closer than this are at the same place

bool same_values(std::span<const double> a, std::span<const double> b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (!(std::fabs(a[i] - b[i]) <= kSameValue)) return false;
  return true;
}

bool at_rest(std::span<const double> v) {
  for (double x : v)
    if (!(std::fabs(x) <= kSameValue)) return false;
  return true;
}

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// What evaluation needs to not misbehave; validate_keypose_set checks more.
bool evaluable(const KeyposeSet& set, size_t num_nodes) {
  if (set.drivers.empty()) return false;
  for (const JointDriver& d : set.drivers)
    if (d.node >= num_nodes || !finite(d.axis) || glm::dot(d.axis, d.axis) == 0.0f) return false;
  for (const KeyposeKey& k : set.keys) {
    if (k.values.size() != set.drivers.size() || k.offsets.size() != k.vertices.size()) return false;
    for (double v : k.values)
      if (!std::isfinite(v)) return false;
  }
  return true;
}

void add_scaled(const KeyposeKey& key, double w, std::span<glm::vec3> out) {
  if (w == 0.0) return;
  const float wf = static_cast<float>(w);
  for (size_t i = 0; i < key.vertices.size(); ++i)
    if (key.vertices[i] < out.size()) out[key.vertices[i]] += wf * key.offsets[i];
}
}  // namespace

const char* driver_kind_name(DriverKind k) {
  switch (k) {
    case DriverKind::kRotation: return "rotation";
    case DriverKind::kTwist: return "twist";
    case DriverKind::kSwing: return "swing";
  }
  return "?";
}

bool parse_driver_kind(const std::string& name, DriverKind& out) {
  for (DriverKind k : {DriverKind::kRotation, DriverKind::kTwist, DriverKind::kSwing})
    if (name == driver_kind_name(k)) {
      out = k;
      return true;
    }
  return false;
}

const char* key_interpolation_name(KeyInterpolation i) {
  return i == KeyInterpolation::kSmooth ? "smooth" : "linear";
}

bool parse_key_interpolation(const std::string& name, KeyInterpolation& out) {
  if (name == "linear") out = KeyInterpolation::kLinear;
  else if (name == "smooth") out = KeyInterpolation::kSmooth;
  else return false;
  return true;
}

double driver_value(const JointDriver& driver, const Skeleton& skeleton, const Pose& pose) {
  if (driver.node >= skeleton.size() || driver.node >= pose.local.size()) return 0.0;
  const glm::quat q = rotation_from_rest(skeleton, pose, driver.node);
  const glm::dvec3 axis = glm::normalize(glm::dvec3(driver.axis));
  switch (driver.kind) {
    case DriverKind::kRotation: {
      glm::dquat d(q);
      if (d.w < 0) d = -d;  // the short way round: angle in [0, pi]
      glm::dvec3 v(d.x, d.y, d.z);
      double s = glm::length(v);
      if (s < 1e-15) return 0.0;
      double angle = 2.0 * std::atan2(s, d.w);
      return angle * glm::dot(v / s, axis) * kDeg;
    }
    case DriverKind::kTwist: return swing_twist(q, glm::vec3(axis)).twist_angle * kDeg;
    case DriverKind::kSwing: return swing_twist(q, glm::vec3(axis)).swing_angle * kDeg;
  }
  return 0.0;
}

std::vector<double> driver_values(const KeyposeSet& set, const Skeleton& skeleton, const Pose& pose) {
  std::vector<double> x;
  x.reserve(set.drivers.size());
  for (const JointDriver& d : set.drivers) x.push_back(driver_value(d, skeleton, pose));
  return x;
}

Pose pose_at_driver_values(const KeyposeSet& set, std::span<const double> values, const Skeleton& skeleton,
                           Pose base) {
  // the rotation vector of each driven node, in its rest frame (radians)
  std::vector<std::pair<uint32_t, glm::dvec3>> turns;
  for (size_t d = 0; d < set.drivers.size() && d < values.size(); ++d) {
    const JointDriver& dr = set.drivers[d];
    const glm::dvec3 a(dr.axis);
    const double len = glm::length(a);
    if (dr.node >= skeleton.size() || dr.node >= base.local.size() || !(len > 0.0) || !std::isfinite(len) ||
        !std::isfinite(values[d]))
      continue;
    glm::dvec3 dir = a / len;
    if (dr.kind == DriverKind::kSwing) {  // turn the axis itself: about a perpendicular
      const glm::dvec3 away = std::abs(dir.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
      dir = glm::normalize(glm::cross(dir, away));
    }
    auto it = std::find_if(turns.begin(), turns.end(), [&](const auto& t) { return t.first == dr.node; });
    if (it == turns.end()) it = turns.insert(turns.end(), {dr.node, glm::dvec3(0.0)});
    it->second += values[d] / kDeg * dir;
  }
  for (const auto& [node, r] : turns) {
    const double angle = glm::length(r);
    const glm::dquat q = angle > 0.0 ? glm::angleAxis(angle, r / angle) : glm::dquat(1, 0, 0, 0);
    base.local[node].rotation = glm::normalize(skeleton.node(node).rest.rotation * glm::quat(q));
  }
  return base;
}

bool keypose_set_active(std::span<const KeyposeSet> sets, size_t i) {
  if (i >= sets.size() || sets[i].mute) return false;
  bool any_solo = std::any_of(sets.begin(), sets.end(), [](const KeyposeSet& s) { return s.solo; });
  return !any_solo || sets[i].solo;
}

void add_keypose_set_offsets(const KeyposeSet& set, std::span<const double> x, std::span<glm::vec3> out) {
  const size_t dims = set.drivers.size();
  if (dims == 0 || x.size() != dims) return;
  // the keys, with the implicit rest key (null) unless an explicit key sits at rest
  std::vector<const KeyposeKey*> keys;
  bool explicit_rest = false;
  for (const KeyposeKey& k : set.keys) {
    if (k.values.size() != dims || k.offsets.size() != k.vertices.size()) continue;
    keys.push_back(&k);
    explicit_rest = explicit_rest || at_rest(k.values);
  }
  if (set.rest_key && !explicit_rest) keys.push_back(nullptr);
  if (keys.empty()) return;
  auto value = [](const KeyposeKey* k, size_t d) { return k ? k->values[d] : 0.0; };

  if (dims == 1) {
    std::stable_sort(keys.begin(), keys.end(),
                     [&](const KeyposeKey* a, const KeyposeKey* b) { return value(a, 0) < value(b, 0); });
    // distinct values only (validate_keypose_set rejects duplicates; the first one wins here)
    std::vector<const KeyposeKey*> unique;
    std::vector<double> xs;
    for (const KeyposeKey* k : keys)
      if (xs.empty() || value(k, 0) - xs.back() > kSameValue) {
        unique.push_back(k);
        xs.push_back(value(k, 0));
      }
    const size_t n = unique.size();
    if (set.interpolation == KeyInterpolation::kLinear || n == 1 || x[0] <= xs.front() || x[0] >= xs.back()) {
      std::vector<double> w(n);
      linear_weights(xs, x[0], w);
      for (size_t i = 0; i < n; ++i)
        if (unique[i]) add_scaled(*unique[i], w[i], out);
      return;
    }
    // monotone cubic per vertex and coordinate over the vertices any key moves
    std::vector<uint32_t> touched;
    for (const KeyposeKey* k : unique)
      if (k) touched.insert(touched.end(), k->vertices.begin(), k->vertices.end());
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    std::vector<glm::vec3> table(touched.size() * n, glm::vec3(0.0f));  // #touched x #keys
    for (size_t i = 0; i < n; ++i) {
      if (!unique[i]) continue;
      const KeyposeKey& k = *unique[i];
      for (size_t e = 0; e < k.vertices.size(); ++e) {
        size_t t = static_cast<size_t>(std::lower_bound(touched.begin(), touched.end(), k.vertices[e]) -
                                       touched.begin());
        table[t * n + i] = k.offsets[e];
      }
    }
    std::vector<double> ys(n), m(n);
    for (size_t t = 0; t < touched.size(); ++t) {
      if (touched[t] >= out.size()) continue;
      glm::vec3 r(0.0f);
      for (int c = 0; c < 3; ++c) {
        for (size_t i = 0; i < n; ++i) ys[i] = table[t * n + i][c];
        monotone_slopes(xs, ys, m);
        r[c] = static_cast<float>(hermite_at(xs, ys, m, x[0]));
      }
      out[touched[t]] += r;
    }
    return;
  }

  // several drivers: RBF in driver space
  std::vector<double> centres;
  centres.reserve(keys.size() * dims);
  for (const KeyposeKey* k : keys)
    for (size_t d = 0; d < dims; ++d) centres.push_back(value(k, d));
  auto rbf = RbfInterpolator::create(centres, dims, set.kernel, set.rbf_width);
  if (!rbf) return;
  std::vector<double> w(keys.size());
  rbf->weights(x, w);
  for (size_t i = 0; i < keys.size(); ++i)
    if (keys[i]) add_scaled(*keys[i], w[i], out);
}

void evaluate_keyposes(std::span<const KeyposeSet> sets, const Skeleton& skeleton, const Pose& pose,
                       std::span<glm::vec3> out) {
  std::fill(out.begin(), out.end(), glm::vec3(0.0f));
  for (size_t i = 0; i < sets.size(); ++i) {
    if (!keypose_set_active(sets, i) || !evaluable(sets[i], skeleton.size())) continue;
    std::vector<double> x = driver_values(sets[i], skeleton, pose);
    add_keypose_set_offsets(sets[i], x, out);
  }
}

Status validate_keypose_set(const KeyposeSet& set, size_t num_nodes, size_t num_vertices) {
  const std::string what = "keypose set '" + set.name + "'";
  auto fail = [&](ErrorCode code, const std::string& message) {
    return make_error(code, what + ": " + message);
  };
  if (set.drivers.empty()) return fail(ErrorCode::kInvalidArgument, "has no driver");
  for (size_t d = 0; d < set.drivers.size(); ++d) {
    const JointDriver& dr = set.drivers[d];
    const std::string at = "driver " + std::to_string(d);
    if (dr.node >= num_nodes)
      return fail(ErrorCode::kIndexOutOfRange, at + " reads node " + std::to_string(dr.node) +
                                                   ", but the skeleton has " + std::to_string(num_nodes) +
                                                   " nodes");
    if (!finite(dr.axis) || glm::dot(dr.axis, dr.axis) == 0.0f)
      return fail(ErrorCode::kInvalidArgument, at + " has a zero or non-finite axis");
  }
  if (!std::isfinite(set.rbf_width)) return fail(ErrorCode::kNonFinite, "rbf width is not finite");
  for (size_t i = 0; i < set.keys.size(); ++i) {
    const KeyposeKey& k = set.keys[i];
    const std::string at = "key " + std::to_string(i);
    if (k.values.size() != set.drivers.size())
      return fail(ErrorCode::kInvalidArgument, at + " has " + std::to_string(k.values.size()) +
                                                   " values for " + std::to_string(set.drivers.size()) +
                                                   " drivers");
    for (double v : k.values)
      if (!std::isfinite(v)) return fail(ErrorCode::kNonFinite, at + " has a non-finite driver value");
    if (k.offsets.size() != k.vertices.size())
      return fail(ErrorCode::kInvalidArgument, at + " has " + std::to_string(k.offsets.size()) +
                                                   " offsets for " + std::to_string(k.vertices.size()) +
                                                   " vertices");
    for (size_t e = 0; e < k.vertices.size(); ++e) {
      if (k.vertices[e] >= num_vertices)
        return fail(ErrorCode::kIndexOutOfRange, at + " moves cage vertex " + std::to_string(k.vertices[e]) +
                                                     ", but the cage has " + std::to_string(num_vertices) +
                                                     " vertices");
      if (e > 0 && k.vertices[e] <= k.vertices[e - 1])
        return fail(ErrorCode::kInvalidArgument, at + ": vertices are not sorted and unique (at entry " +
                                                     std::to_string(e) + ")");
      if (!finite(k.offsets[e]))
        return fail(ErrorCode::kNonFinite,
                    at + " has a non-finite offset for cage vertex " + std::to_string(k.vertices[e]));
    }
    for (size_t j = 0; j < i; ++j)
      if (same_values(set.keys[j].values, k.values))
        return fail(ErrorCode::kInvalidArgument,
                    at + " sits at the same driver values as key " + std::to_string(j));
  }
  return Ok{};
}

KeyposeKey make_key(std::vector<double> values, std::span<const glm::vec3> dense) {
  KeyposeKey k;
  k.values = std::move(values);
  for (size_t v = 0; v < dense.size(); ++v)
    if (dense[v] != glm::vec3(0.0f)) {
      k.vertices.push_back(static_cast<uint32_t>(v));
      k.offsets.push_back(dense[v]);
    }
  return k;
}

std::vector<glm::vec3> dense_offsets(const KeyposeKey& key, size_t num_vertices) {
  std::vector<glm::vec3> out(num_vertices, glm::vec3(0.0f));
  for (size_t i = 0; i < key.vertices.size() && i < key.offsets.size(); ++i)
    if (key.vertices[i] < num_vertices) out[key.vertices[i]] = key.offsets[i];
  return out;
}

void set_key(KeyposeSet& set, KeyposeKey key) {
  for (KeyposeKey& k : set.keys)
    if (same_values(k.values, key.values)) {
      k = std::move(key);
      return;
    }
  auto it =
      std::upper_bound(set.keys.begin(), set.keys.end(), key, [](const KeyposeKey& a, const KeyposeKey& b) {
        return std::lexicographical_compare(a.values.begin(), a.values.end(), b.values.begin(),
                                            b.values.end());
      });
  set.keys.insert(it, std::move(key));
}

KeyposeSet key_sculpt(const KeyposeSet& set, std::vector<double> values, std::span<const glm::vec3> delta) {
  std::vector<glm::vec3> dense(delta.begin(), delta.end());
  add_keypose_set_offsets(set, values, dense);
  KeyposeSet out = set;
  set_key(out, make_key(std::move(values), dense));
  return out;
}

bool remove_key(KeyposeSet& set, std::span<const double> values) {
  for (auto it = set.keys.begin(); it != set.keys.end(); ++it)
    if (same_values(it->values, values)) {
      set.keys.erase(it);
      return true;
    }
  return false;
}

size_t upsert_keypose_set(std::vector<KeyposeSet>& sets, KeyposeSet set) {
  for (size_t i = 0; i < sets.size(); ++i)
    if (sets[i].name == set.name && sets[i].drivers == set.drivers) {
      sets[i] = std::move(set);
      return i;
    }
  sets.push_back(std::move(set));
  return sets.size() - 1;
}

void clear_vertex_data(std::vector<KeyposeSet>& sets) {
  for (KeyposeSet& s : sets)
    for (KeyposeKey& k : s.keys) {
      k.vertices.clear();
      k.offsets.clear();
    }
}

Result<MirroredKeyposeSet> mirror_keypose_set(const KeyposeSet& set, const Skeleton& skeleton,
                                              std::span<const glm::vec3> cage_rest, double tolerance) {
  if (auto v = validate_keypose_set(set, skeleton.size(), cage_rest.size()); !v) return v.error();
  const std::vector<glm::mat4> rest = skeleton.global_transforms(skeleton.rest_pose());
  auto rest_rotation = [&](uint32_t node) {
    glm::dmat3 m{glm::mat3(rest[node])};  // braces: clang reads the parentheses as a function declaration
    for (int c = 0; c < 3; ++c) m[c] = glm::normalize(m[c]);
    return m;
  };
  MirroredKeyposeSet out;
  out.set = set;
  out.set.name = mirror_name(set.name);
  std::vector<double> sign(set.drivers.size(), 1.0);
  for (size_t d = 0; d < set.drivers.size(); ++d) {
    const JointDriver& from = set.drivers[d];
    int32_t m = mirror_node(skeleton, from.node);
    if (m < 0) {
      const std::string& name = skeleton.node(from.node).name;
      return make_error(ErrorCode::kInvalidArgument, "keypose set '" + set.name + "': driver node '" + name +
                                                         "' has no mirror: no node is named '" +
                                                         mirror_name(name) + "'");
    }
    JointDriver& to = out.set.drivers[d];
    to.node = static_cast<uint32_t>(m);
    const glm::dvec3 a = glm::normalize(glm::dvec3(from.axis));
    glm::dvec3 world = rest_rotation(from.node) * a;
    world.x = -world.x;
    glm::dvec3 a2 = glm::normalize(glm::inverse(rest_rotation(to.node)) * world);
    if (from.kind == DriverKind::kSwing) {
      to.axis =
          glm::vec3(glm::dot(a2, a) < 0 ? -a2 : a2);  // the swing angle does not depend on the axis' sign
    } else if (glm::dot(-a2, a) >= glm::dot(a2, a)) {
      to.axis = glm::vec3(-a2);  // reads +t where the original read +t
    } else {
      to.axis = glm::vec3(a2);
      sign[d] = -1.0;
    }
    // an axis that is a coordinate axis up to rounding is written as one
    for (int c = 0; c < 3; ++c)
      if (std::fabs(to.axis[c]) < 1e-6f) to.axis[c] = 0.0f;
    to.axis = glm::normalize(to.axis);
  }
  // A name with no side of its own ("forearm.L_X", as the editor names a set after its joint) takes its
  // driver joint's name mirrored; else " (mirrored)" is added, so that the two sets are never one name.
  for (size_t d = 0; d < set.drivers.size() && out.set.name == set.name; ++d) {
    const std::string& from = skeleton.node(set.drivers[d].node).name;
    const std::string& to = skeleton.node(out.set.drivers[d].node).name;
    if (const size_t at = set.name.find(from); from != to && at != std::string::npos)
      out.set.name = set.name.substr(0, at) + to + set.name.substr(at + from.size());
  }
  bool moved = false;  // a set of centre joints (a tail) mirrors onto itself and keeps its name
  for (size_t d = 0; d < set.drivers.size(); ++d) moved |= out.set.drivers[d].node != set.drivers[d].node;
  if (moved && out.set.name == set.name) out.set.name += " (mirrored)";
  // vertices: each vertex takes the offset of the vertex nearest its mirror image, when that one is keyed
  const size_t nv = cage_rest.size();
  std::vector<uint32_t> all(nv);
  for (size_t v = 0; v < nv; ++v) all[v] = static_cast<uint32_t>(v);
  const std::vector<int32_t> source = mirror_x_counterparts(all, cage_rest, tolerance);
  std::vector<uint8_t> keyed(nv, 0), used(nv, 0);
  out.set.keys.clear();
  for (const KeyposeKey& k : set.keys) {
    const std::vector<glm::vec3> from = dense_offsets(k, nv);
    std::vector<uint8_t> in_key(nv, 0);
    for (uint32_t v : k.vertices) in_key[v] = keyed[v] = 1;
    std::vector<glm::vec3> dense(nv, glm::vec3(0.0f));
    for (size_t t = 0; t < nv; ++t) {
      const int32_t src = source[t];
      if (src < 0 || !in_key[src]) continue;
      const glm::vec3 o = from[src];
      dense[t] = glm::vec3(-o.x, o.y, o.z);
      used[src] = 1;
    }
    std::vector<double> values = k.values;
    for (size_t d = 0; d < values.size(); ++d) values[d] = sign[d] * values[d] + 0.0;  // + 0.0: no -0
    set_key(out.set, make_key(std::move(values), dense));
  }
  for (size_t v = 0; v < nv; ++v)
    if (keyed[v] && !used[v]) out.unmatched.push_back(static_cast<uint32_t>(v));
  return out;
}

}  // namespace cagewrap
