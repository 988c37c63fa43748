#include "core/cage/cage_sim.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>

#include "core/base/check.h"
#include "core/character/skinning.h"

namespace cagewrap {

namespace {

bool finite3(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

std::string num(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

glm::dvec3 closest_on_segment(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 ab = b - a;
  const double len2 = glm::dot(ab, ab);
  if (len2 <= 0.0) return a;
  return a + std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) * ab;
}

// Pushes p out of a ball of radius r around c (straight up when p is at the centre).
void push_out_of_ball(glm::dvec3& p, const glm::dvec3& c, double r) {
  const glm::dvec3 d = p - c;
  const double l2 = glm::dot(d, d);
  if (l2 >= r * r) return;
  const double l = std::sqrt(l2);
  p = l > 1e-12 ? c + d * (r / l) : c + glm::dvec3(0.0, r, 0.0);
}

}  // namespace

const char* collider_kind_name(ColliderKind k) {
  switch (k) {
    case ColliderKind::kPlane: return "plane";
    case ColliderKind::kSphere: return "sphere";
    case ColliderKind::kCapsule: return "capsule";
  }
  return "?";
}

bool parse_collider_kind(const std::string& name, ColliderKind& out) {
  for (ColliderKind k : {ColliderKind::kPlane, ColliderKind::kSphere, ColliderKind::kCapsule})
    if (name == collider_kind_name(k)) {
      out = k;
      return true;
    }
  return false;
}

Status validate_sim_settings(const SimSettings& s, size_t num_vertices, size_t num_nodes) {
  auto bad = [](const std::string& m) -> Status { return make_error(ErrorCode::kInvalidArgument, "simulation: " + m); };
  const SimParams& p = s.params;
  if (!(std::isfinite(p.frame_rate) && p.frame_rate >= 1.0 && p.frame_rate <= 1000.0))
    return bad("frame rate " + num(p.frame_rate) + " must be 1..1000 frames per second");
  if (p.substeps < 1 || p.substeps > 100) return bad("substeps " + std::to_string(p.substeps) + " must be 1..100");
  if (p.iterations < 0 || p.iterations > 100)
    return bad("iterations " + std::to_string(p.iterations) + " must be 0..100");
  if (!finite3(p.gravity)) return bad("gravity must be finite");
  if (!(std::isfinite(p.damping) && p.damping >= 0.0)) return bad("damping " + num(p.damping) + " must be >= 0");
  if (!(std::isfinite(p.goal_frequency) && p.goal_frequency >= 0.0))
    return bad("goal frequency " + num(p.goal_frequency) + " must be >= 0 Hz");
  if (!(std::isfinite(p.edge_compliance) && p.edge_compliance >= 0.0))
    return bad("edge compliance " + num(p.edge_compliance) + " must be >= 0");
  if (!(std::isfinite(p.collision_margin) && p.collision_margin >= 0.0))
    return bad("collision margin " + num(p.collision_margin) + " must be >= 0");
  if (!(std::isfinite(p.skeleton_radius_scale) && p.skeleton_radius_scale > 0.0))
    return bad("skeleton radius scale " + num(p.skeleton_radius_scale) + " must be > 0");
  if (!(std::isfinite(p.preroll) && p.preroll >= 0.0 && p.preroll <= 60.0))
    return bad("pre-roll " + num(p.preroll) + " must be 0..60 seconds");
  if (!s.vertices.empty() && s.vertices.size() != num_vertices)
    return bad("the weights are for " + std::to_string(s.vertices.size()) + " vertices, but the cage has " +
               std::to_string(num_vertices));
  for (size_t v = 0; v < s.vertices.size(); ++v) {
    const SimVertex& w = s.vertices[v];
    if (!(std::isfinite(w.mass) && w.mass > 0.0f))
      return bad("cage vertex " + std::to_string(v) + " has mass " + num(w.mass) + "; it must be a positive number");
    if (!(std::isfinite(w.stiffness) && w.stiffness >= 0.0f && w.stiffness <= 1.0f))
      return bad("cage vertex " + std::to_string(v) + " has stiffness " + num(w.stiffness) + "; it must be 0..1");
  }
  for (size_t c = 0; c < s.colliders.size(); ++c) {
    const Collider& k = s.colliders[c];
    const std::string who = "collider " + std::to_string(c) + (k.name.empty() ? "" : " ('" + k.name + "')");
    if (!finite3(k.a) || !finite3(k.b)) return bad(who + " has a non-finite point");
    if (k.kind != ColliderKind::kPlane && !(std::isfinite(k.radius) && k.radius > 0.0))
      return bad(who + " has radius " + num(k.radius) + "; it must be > 0");
    if (k.kind == ColliderKind::kPlane && glm::length(k.b) < 1e-12) return bad(who + " is a plane with a zero normal");
    if (k.node >= 0 && static_cast<size_t>(k.node) >= num_nodes)
      return bad(who + " follows node " + std::to_string(k.node) + ", but the skeleton has " +
                 std::to_string(num_nodes) + " nodes");
    if (k.node < -1) return bad(who + " follows node " + std::to_string(k.node) + "; -1 means the world");
  }
  return Ok{};
}

std::vector<BoneCapsule> skeleton_capsules(const Character& character, uint32_t skin, double radius_scale) {
  std::vector<BoneCapsule> out;
  if (skin >= character.skins.size()) return out;
  const std::vector<Limb> limbs = skin_limbs(character, skin);
  // distances of each joint's points to the nearest of the joint's limbs
  std::vector<std::vector<double>> dist(character.skins[skin].joints.size());
  for (const Primitive& prim : character.primitives) {
    if (prim.skin != static_cast<int32_t>(skin) || prim.influence_start.empty()) continue;
    for (size_t v = 0; v < prim.num_vertices(); ++v) {
      uint32_t best = prim.influence_start[v];
      for (uint32_t i = best; i < prim.influence_start[v + 1]; ++i)
        if (prim.influence_weight[i] > prim.influence_weight[best]) best = i;
      if (best == prim.influence_start[v + 1]) continue;
      const uint32_t j = prim.influence_joint[best];
      if (j >= dist.size()) continue;
      const glm::dvec3 p(prim.positions[v]);
      double d = std::numeric_limits<double>::infinity();
      for (const Limb& l : limbs)
        if (l.joint == j) d = std::min(d, glm::length(p - closest_on_segment(p, l.a, l.b)));
      if (std::isfinite(d)) dist[j].push_back(d);
    }
  }
  for (const Limb& l : limbs) {
    std::vector<double>& d = dist[l.joint];
    if (d.empty()) continue;
    const size_t k = d.size() / 5;
    std::nth_element(d.begin(), d.begin() + static_cast<ptrdiff_t>(k), d.end());
    if (d[k] <= 0.0) continue;
    out.push_back({l.joint, l.a, l.b, d[k] * radius_scale});
  }
  return out;
}

void pose_colliders(std::span<const Collider> colliders, std::span<const BoneCapsule> capsules,
                    std::span<const glm::mat4> globals, std::span<const glm::mat4> rest_globals,
                    std::span<const glm::mat4> joint_skinning, std::vector<ColliderShape>& out) {
  out.resize(colliders.size() + capsules.size());
  for (size_t c = 0; c < colliders.size(); ++c) {
    const Collider& k = colliders[c];
    glm::dmat4 m(1.0);
    if (k.node >= 0 && static_cast<size_t>(k.node) < globals.size() && static_cast<size_t>(k.node) < rest_globals.size())
      m = glm::dmat4(globals[k.node]) * glm::inverse(glm::dmat4(rest_globals[k.node]));
    ColliderShape& s = out[c];
    s.kind = k.kind;
    s.radius = k.radius;
    s.a = glm::dvec3(m * glm::dvec4(k.a, 1.0));
    s.b = k.kind == ColliderKind::kPlane ? glm::normalize(glm::dvec3(m * glm::dvec4(k.b, 0.0)))
                                         : glm::dvec3(m * glm::dvec4(k.b, 1.0));
  }
  for (size_t i = 0; i < capsules.size(); ++i) {
    const BoneCapsule& c = capsules[i];
    const glm::dmat4 m = c.joint < joint_skinning.size() ? glm::dmat4(joint_skinning[c.joint]) : glm::dmat4(1.0);
    out[colliders.size() + i] = {ColliderKind::kCapsule, glm::dvec3(m * glm::dvec4(c.a, 1.0)),
                                 glm::dvec3(m * glm::dvec4(c.b, 1.0)), c.radius};
  }
}

Result<CageSim> CageSim::create(const PolyMesh& topology, std::span<const glm::vec3> rest, const SimSettings& settings) {
  const size_t nv = topology.num_vertices();
  if (rest.size() != nv)
    return make_error(ErrorCode::kTopologyMismatch, "simulation: " + std::to_string(rest.size()) +
                                                        " rest positions for a cage of " + std::to_string(nv) +
                                                        " vertices");
  if (auto s = validate_sim_settings(settings, nv, std::numeric_limits<size_t>::max()); !s) return s.error();
  for (size_t v = 0; v < nv; ++v)
    if (!finite3(glm::dvec3(rest[v])))
      return make_error(ErrorCode::kNonFinite, "simulation: rest cage vertex " + std::to_string(v) + " is not finite");
  CageSim sim;
  sim.params_ = settings.params;
  sim.dt_ = 1.0 / (settings.params.frame_rate * settings.params.substeps);
  sim.x_.assign(nv, glm::dvec3(0.0));
  sim.v_.assign(nv, glm::dvec3(0.0));
  sim.p_.assign(nv, glm::dvec3(0.0));
  sim.target_prev_.assign(nv, glm::dvec3(0.0));
  sim.target_.assign(nv, glm::dvec3(0.0));
  sim.inv_mass_.assign(nv, 0.0);
  sim.goal_.assign(nv, 0.0);
  const double w0 = 2.0 * std::numbers::pi * settings.params.goal_frequency;
  for (size_t v = 0; v < settings.vertices.size(); ++v) {
    const SimVertex& w = settings.vertices[v];
    if (w.pinned || w.stiffness >= 1.0f) continue;  // a hard goal: exactly the target, like a pinned vertex
    sim.inv_mass_[v] = 1.0 / w.mass;
    const double s = w.stiffness;
    sim.goal_[v] = w0 * w0 * s / (1.0 - s) / w.mass;
    sim.free_.push_back(static_cast<uint32_t>(v));
  }
  if (settings.params.edges)
    for (const auto& e : unique_edges(topology))
      if (sim.inv_mass_[e[0]] > 0.0 || sim.inv_mass_[e[1]] > 0.0)
        sim.edge_.push_back({e[0], e[1], glm::length(glm::dvec3(rest[e[0]]) - glm::dvec3(rest[e[1]]))});
  return sim;
}

void CageSim::reset(std::span<const glm::vec3> targets, std::span<const ColliderShape> colliders) {
  CAGEWRAP_CHECK(targets.size() == x_.size(), "CageSim::reset: one target per cage vertex");
  for (size_t v = 0; v < x_.size(); ++v) x_[v] = target_prev_[v] = target_[v] = glm::dvec3(targets[v]);
  std::fill(v_.begin(), v_.end(), glm::dvec3(0.0));
  shape_prev_.assign(colliders.begin(), colliders.end());
  shape_ = shape_prev_;
  shape_now_ = shape_prev_;
}

void CageSim::step_frame(std::span<const glm::vec3> targets, std::span<const ColliderShape> colliders) {
  CAGEWRAP_CHECK(targets.size() == x_.size(), "CageSim::step_frame: one target per cage vertex");
  CAGEWRAP_CHECK(colliders.size() == shape_.size(), "CageSim::step_frame: the colliders of reset");
  std::swap(target_prev_, target_);
  for (size_t v = 0; v < x_.size(); ++v) target_[v] = glm::dvec3(targets[v]);
  std::swap(shape_prev_, shape_);
  std::copy(colliders.begin(), colliders.end(), shape_.begin());
  for (int i = 1; i <= params_.substeps; ++i) substep(static_cast<double>(i) / params_.substeps);
}

void CageSim::substep(double s) {
  const double dt = dt_;
  const bool last = s >= 1.0;
  auto target_at = [&](size_t v) { return last ? target_[v] : target_prev_[v] + (target_[v] - target_prev_[v]) * s; };
  // pinned vertices follow their targets exactly
  for (size_t v = 0; v < x_.size(); ++v)
    if (inv_mass_[v] == 0.0) {
      const glm::dvec3 t = target_at(v);
      v_[v] = (t - x_[v]) / dt;
      x_[v] = p_[v] = t;
    }
  // predict, then the goal spring (XPBD with a fresh multiplier each substep)
  const double decay = std::exp(-params_.damping * dt);
  for (uint32_t v : free_) {
    v_[v] = v_[v] * decay + params_.gravity * dt;
    glm::dvec3 p = x_[v] + v_[v] * dt;
    const glm::dvec3 t = target_at(v);
    const double k = goal_[v];
    if (k > 0.0) {
      const double a = k * dt * dt;
      p += (t - p) * (a / (1.0 + a));
    }
    p_[v] = p;
  }
  // edge lengths, Gauss-Seidel in a fixed order
  const double alpha = params_.edge_compliance / (dt * dt);
  for (int it = 0; it < params_.iterations; ++it)
    for (const Edge& e : edge_) {
      const double wa = inv_mass_[e.a], wb = inv_mass_[e.b];
      const glm::dvec3 d = p_[e.a] - p_[e.b];
      const double len = glm::length(d);
      if (len < 1e-12) continue;
      const double lambda = -(len - e.rest) / (wa + wb + alpha);
      const glm::dvec3 corr = d * (lambda / len);
      p_[e.a] += wa * corr;
      p_[e.b] -= wb * corr;
    }
  // collisions with the colliders where they are at this substep
  const double margin = params_.collision_margin;
  shape_now_.resize(shape_.size());
  for (size_t c = 0; c < shape_.size(); ++c) {
    const ColliderShape &a = shape_prev_[c], &b = shape_[c];
    ColliderShape& n = shape_now_[c];
    n = last ? b : ColliderShape{b.kind, a.a + (b.a - a.a) * s, a.b + (b.b - a.b) * s, b.radius};
    if (n.kind == ColliderKind::kPlane && !last) n.b = glm::normalize(n.b);
  }
  for (const ColliderShape& c : shape_now_) {
    const double r = c.radius + margin;
    switch (c.kind) {
      case ColliderKind::kPlane:
        for (uint32_t v : free_) {
          const double d = glm::dot(p_[v] - c.a, c.b);
          if (d < margin) p_[v] += (margin - d) * c.b;
        }
        break;
      case ColliderKind::kSphere:
        for (uint32_t v : free_) push_out_of_ball(p_[v], c.a, r);
        break;
      case ColliderKind::kCapsule: {
        const glm::dvec3 mid = 0.5 * (c.a + c.b);
        const double reach = 0.5 * glm::length(c.b - c.a) + r;
        for (uint32_t v : free_) {
          const glm::dvec3 d = p_[v] - mid;
          if (glm::dot(d, d) >= reach * reach) continue;  // outside the capsule's bounding ball
          push_out_of_ball(p_[v], closest_on_segment(p_[v], c.a, c.b), r);
        }
        break;
      }
    }
  }
  for (uint32_t v : free_) {
    v_[v] = (p_[v] - x_[v]) / dt;
    x_[v] = p_[v];
  }
}

double CageSim::energy() const {
  double e = 0.0;
  for (uint32_t v : free_) {
    const double m = 1.0 / inv_mass_[v];
    e += 0.5 * m * glm::dot(v_[v], v_[v]);
    const glm::dvec3 d = x_[v] - target_[v];
    e += 0.5 * goal_[v] * m * glm::dot(d, d);
  }
  return e;
}

double CageSim::max_edge_strain() const {
  double worst = 0.0;
  for (const Edge& e : edge_)
    if (e.rest > 0.0) worst = std::max(worst, std::abs(glm::length(x_[e.a] - x_[e.b]) - e.rest) / e.rest);
  return worst;
}

}  // namespace cagewrap
