// Secondary motion on the cage (paper section 6, Figure 6): the low-resolution driver cage is moved
// by a physical simulation and carries cheap secondary motion (a belly jiggle, a cape) to the dense
// skin through the usual deformation.
//
// This work is based on:
//   Mueller, Heidelberger, Hennix, Ratcliff, "Position Based Dynamics" (VRIPHYS 2006);
//   Macklin, Mueller, Chentanez, "XPBD: Position-Based Simulation of Compliant Constrained
//   Dynamics" (MIG 2016); Macklin, Storey, Lu, Terdiman, Chentanez, Jeschke, Mueller, "Small Steps
//   in Physics Simulation" (SCA 2019): many substeps, one constraint sweep each.
//
// The target of each cage vertex is its attached (skinned) position, what the cage would be without
// simulation. Per substep of length dt (fixed: 1 / (frame_rate * substeps)):
//   pinned vertex:  x = target, exactly (it follows the skeleton);
//   free vertex:    v *= exp(-damping dt); v += gravity dt; p = x + v dt
//                   goal spring (XPBD, compliance 1 / k): p += (target - p) * k dt^2 / (m + k dt^2)
//                     with k / m = (2 pi goal_frequency)^2 * s / (1 - s) / m, s the painted stiffness:
//                     s = 0.5 and mass 1 springs back at goal_frequency Hz, s = 0 no goal (cloth);
//                     s = 1 is a hard goal: the vertex is handled as pinned (exactly its target,
//                     immovable for the edges), so a cage all at stiffness 1 is the skinned cage
//                   `iterations` Gauss-Seidel sweeps over the cage's edges in a fixed order (XPBD
//                     distance constraints, compliance edge_compliance, rest lengths from the rest
//                     cage), weighted by inverse mass (a pinned end does not move)
//                   collisions: pushed out of every collider (plane, sphere, capsule) to its surface
//                     plus collision_margin, in collider order
//                   v = (p - x) / dt, x = p.
// Targets and collider shapes move linearly from the previous frame's to this frame's over the
// substeps. Everything runs on one thread in a fixed order, so a run is bit-for-bit repeatable.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "core/cage/cage_attachment.h"
#include "core/character/character.h"
#include "core/geometry/mesh.h"
#include "core/base/result.h"

namespace cagewrap {

struct SimParams {
  double frame_rate = 30.0;       // simulated (cached) frames per second of clip time
  int substeps = 8;               // per frame: dt = 1 / (frame_rate * substeps) = 1/240 s by default
  int iterations = 1;             // edge-constraint sweeps per substep
  glm::dvec3 gravity{0.0, -9.81, 0.0};  // m/s^2
  double damping = 2.0;           // 1/s: velocity decays as exp(-damping t)
  double goal_frequency = 3.0;    // Hz of the goal spring at stiffness 0.5, mass 1
  bool edges = true;              // keep the cage's edge lengths (cloth)
  double edge_compliance = 0.0;   // XPBD compliance of an edge (m/N, mass 1 = 1 kg); 0 = inextensible
  double collision_margin = 0.005;  // m kept between a vertex and a collider's surface
  bool skeleton_colliders = false;  // collide with capsules around the character's bones
  double skeleton_radius_scale = 1.0;  // scales the capsules' estimated radii
  double preroll = 0.0;           // seconds the clip's first pose is held before it plays (settling)
  bool operator==(const SimParams&) const = default;
};

// A cage vertex's simulation weights, painted by the artist.
struct SimVertex {
  bool pinned = true;      // follows the skeleton exactly
  float mass = 1.0f;       // relative (> 0): heavier vertices swing slower and yield less to edges
  float stiffness = 0.5f;  // 0..1: pull back to the skinned position (1 = rigid, 0 = none)
  bool operator==(const SimVertex&) const = default;
};

enum class ColliderKind { kPlane, kSphere, kCapsule };
const char* collider_kind_name(ColliderKind k);
bool parse_collider_kind(const std::string& name, ColliderKind& out);

// A collision shape. Plane: through `a` with normal `b` (the free side); sphere: centre `a`;
// capsule: segment a..b. `node` >= 0: the shape is given in the rest pose and moves with that
// skeleton node (node global * inverse rest global); -1: fixed in the world.
struct Collider {
  std::string name;
  ColliderKind kind = ColliderKind::kSphere;
  glm::dvec3 a{0.0}, b{0.0, 1.0, 0.0};
  double radius = 0.1;
  int32_t node = -1;
  bool operator==(const Collider&) const = default;
};

// What a document stores (Document::sim, saved in the project).
struct SimSettings {
  bool enabled = false;
  SimParams params;
  std::vector<SimVertex> vertices;  // #Vc, or empty: every vertex pinned (the simulation does nothing)
  std::vector<Collider> colliders;
  bool operator==(const SimSettings&) const = default;
};

// Checks the settings against a cage of `num_vertices` vertices and a skeleton of `num_nodes`
// nodes: the message names the parameter, the vertex or the collider (by index and name).
Status validate_sim_settings(const SimSettings& settings, size_t num_vertices, size_t num_nodes);

// A collider in world space at one instant.
struct ColliderShape {
  ColliderKind kind = ColliderKind::kSphere;
  glm::dvec3 a{0.0}, b{0.0};
  double radius = 0.0;
};

// Capsules around the bones of a skin, in its bind pose: one per limb (core/cage/cage_attachment.h
// skin_limbs), with the radius estimated from the skin: the 20th percentile of the distances to the
// limb's segment of the skin points whose heaviest joint is the limb's (a low percentile, so that
// the capsule stays inside the body where it is flattened), times `radius_scale`. Limbs no point
// follows get none.
struct BoneCapsule {
  uint32_t joint = 0;  // skin joint index
  glm::dvec3 a{0.0}, b{0.0};
  double radius = 0.0;
};
std::vector<BoneCapsule> skeleton_capsules(const Character& character, uint32_t skin, double radius_scale);

// The world shapes of the settings' colliders and the bone capsules at a pose: `globals` (#N) the
// nodes' world transforms, `rest_globals` (#N) at rest, `joint_skinning` (#J of the skin, from
// joint_matrices) for the capsules.
void pose_colliders(std::span<const Collider> colliders, std::span<const BoneCapsule> capsules,
                    std::span<const glm::mat4> globals, std::span<const glm::mat4> rest_globals,
                    std::span<const glm::mat4> joint_skinning, std::vector<ColliderShape>& out);

// The solver. Made once for a cage and settings (validated), then reset and stepped frame by frame;
// it allocates nothing per step.
class CageSim {
 public:
  // `topology` gives the edges, `rest` (#Vc) their rest lengths. Fails with validate_sim_settings'
  // message, or when rest is not #Vc finite positions.
  static Result<CageSim> create(const PolyMesh& topology, std::span<const glm::vec3> rest,
                                const SimSettings& settings);

  // Starts at rest on the targets (#Vc), with the colliders' shapes: x = targets, v = 0.
  void reset(std::span<const glm::vec3> targets, std::span<const ColliderShape> colliders);
  // Advances one frame (substeps of dt) to the targets (#Vc) and collider shapes given (the same
  // number of colliders as at reset: checked), moving both linearly from the previous frame's.
  void step_frame(std::span<const glm::vec3> targets, std::span<const ColliderShape> colliders);

  std::span<const glm::dvec3> positions() const { return x_; }
  std::span<const glm::dvec3> velocities() const { return v_; }
  size_t num_vertices() const { return x_.size(); }
  size_t num_free() const { return free_.size(); }
  size_t num_edges() const { return edge_.size(); }
  // Pinned or at stiffness 1: exactly on its target.
  bool pinned(size_t v) const { return inv_mass_[v] == 0.0; }
  double dt() const { return dt_; }
  // Kinetic energy sum 1/2 m |v|^2 plus the goal springs' energy sum 1/2 k |x - target|^2 of the free
  // vertices (targets of the last frame).
  double energy() const;
  // The largest relative change of an edge's length from its rest length, |l - l0| / l0, over the
  // edges the solver keeps (0 without edges): how far the cloth stretches.
  double max_edge_strain() const;

 private:
  CageSim() = default;
  void substep(double s);  // s: the substep's end as a share of the frame (0..1]

  SimParams params_;
  double dt_ = 0.0;
  std::vector<glm::dvec3> x_, v_, p_;             // #Vc positions, velocities, predicted
  std::vector<glm::dvec3> target_prev_, target_;  // #Vc the previous frame's and this frame's targets
  std::vector<double> inv_mass_, goal_;           // #Vc 1/m (0: pinned or stiffness 1); k / m of the goal spring
  std::vector<uint32_t> free_;                    // indices of the free vertices, ascending
  struct Edge {
    uint32_t a, b;
    double rest;
  };
  std::vector<Edge> edge_;  // edges with at least one free end, in mesh_edges order
  std::vector<ColliderShape> shape_prev_, shape_, shape_now_;
};

}  // namespace cagewrap
