// Keyposes (paper section 5, step 3): cage vertex offsets keyed against joint angles, set-driven-key
// style, and across several joint angles in pose space.
//
// This work is based on: Singh, Kokkevis, "Skinning Characters using Surface-Oriented Free-Form
// Deformations" (GI 2000), section 5; Lewis, Cordner, Fong, "Pose Space Deformation" (SIGGRAPH 2000)
// for the multi-driver interpolation; Fritsch, Carlson (1980) for the monotone cubic.
//
// Data model (part of the Document, saved, undoable):
// - A **driver** reads one joint angle of a skeleton node, in degrees, relative to the node's rest
//   rotation q = inverse(rest) * pose (core/character/joint_angles.h, rotation_from_rest), about a unit axis in
//   the node's own rest frame:
//     kRotation: the component of q's rotation vector (axis * angle, the exponential map) along the
//                axis; for a hinge (an elbow about its local X) it is the hinge angle, and three of
//                them about X, Y, Z are the coordinates of the joint's rotation (a shoulder);
//     kTwist:    the twist angle of q's swing/twist decomposition about the axis (signed);
//     kSwing:    the swing angle: how far q turns the axis itself (unsigned, 0..180).
//   Every kind reads 0 at rest.
// - A **keypose set** has one or more drivers and keys; several sets may act on the same vertices
//   (their offsets add). A **key** is a point in the set's driver space (one value per driver,
//   degrees) with sparse per-cage-vertex offsets.
// - Offsets live in the bind space of the vertex, the space of Document::cage_offsets: they are
//   added to the rest cage before the vertex's skinning matrix M_v is applied, so a keyed bulge
//   moves by M_v's linear part and travels with the limb the vertex follows (its own joint, not the
//   driver's). Being in the rest (bind) space of the character, they mirror by negating x.
//
// Interpolation of a set at a pose (its drivers read x):
// - one driver: the keys sorted by value, piecewise linear or monotone cubic (kSmooth,
//   core/geometry/interpolation.h), clamped outside the keyed range;
// - several drivers: radial basis functions in driver space (Gaussian, thin plate or linear),
//   weights solved so that every key is reproduced exactly.
// - The rest pose (all drivers 0) is an implicit key with zero offsets unless `rest_key` is false;
//   an explicit key at the rest point replaces it.
// Mute/solo per set: when any set is soloed only the soloed ones act; a muted set never does.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "core/geometry/interpolation.h"
#include "core/base/result.h"
#include "core/character/skeleton.h"

namespace cagewrap {

enum class DriverKind { kRotation, kTwist, kSwing };
const char* driver_kind_name(DriverKind k);
bool parse_driver_kind(const std::string& name, DriverKind& out);

struct JointDriver {
  uint32_t node = 0;            // skeleton node
  DriverKind kind = DriverKind::kRotation;
  glm::vec3 axis{1.0f, 0.0f, 0.0f};  // in the node's rest frame; normalized on use (must not be 0)
  bool operator==(const JointDriver&) const = default;
};

struct KeyposeKey {
  std::vector<double> values;      // #D driver values, degrees (D = the set's drivers)
  std::vector<uint32_t> vertices;  // sorted, unique cage vertices
  std::vector<glm::vec3> offsets;  // #vertices offsets in bind space (see above)
  bool operator==(const KeyposeKey&) const = default;
};

enum class KeyInterpolation { kLinear, kSmooth };
const char* key_interpolation_name(KeyInterpolation i);
bool parse_key_interpolation(const std::string& name, KeyInterpolation& out);

struct KeyposeSet {
  std::string name;
  std::vector<JointDriver> drivers;  // >= 1
  std::vector<KeyposeKey> keys;      // distinct values; kept sorted by values (set_key)
  KeyInterpolation interpolation = KeyInterpolation::kLinear;  // one driver
  RbfKernel kernel = RbfKernel::kGaussian;                     // several drivers
  double rbf_width = 0.0;  // Gaussian width in degrees; <= 0: automatic (RbfInterpolator::create)
  bool rest_key = true;    // the rest pose is an implicit key with zero offsets
  bool mute = false;
  bool solo = false;
  bool operator==(const KeyposeSet&) const = default;
};

// ---------------------------------------------------------------- evaluation

// The driver's reading at a pose, degrees.
double driver_value(const JointDriver& driver, const Skeleton& skeleton, const Pose& pose);
// Every driver of a set (#D).
std::vector<double> driver_values(const KeyposeSet& set, const Skeleton& skeleton, const Pose& pose);

// A pose at which the set's drivers read `values` (#D, degrees): `base` with each driver node's
// local rotation set to rest * exp(r), r the sum over its drivers of value * axis (kRotation,
// kTwist) or value * a unit vector perpendicular to the axis (kSwing). Exact (driver_values gives
// `values` back, up to +-180 degrees) when each node has one driver, or only kRotation drivers
// about orthogonal axes; otherwise a pose near it. Drivers that fail validation are skipped.
Pose pose_at_driver_values(const KeyposeSet& set, std::span<const double> values, const Skeleton& skeleton,
                           Pose base);

// Whether set i acts (mute/solo).
bool keypose_set_active(std::span<const KeyposeSet> sets, size_t i);

// One set's offsets at the driver reading x (#D) added into out (#Vc; vertices beyond it are
// ignored).
void add_keypose_set_offsets(const KeyposeSet& set, std::span<const double> x, std::span<glm::vec3> out);

// The keyposes' offsets at a pose: out (#Vc) is overwritten with the sum over the active sets.
// Add them to Document::cage_offsets (both in bind space) before posing the cage: the driver cage
// is then D = M_v * (rest_v + cage_offset_v + keypose_offset_v) (core/rig/rig.h does this).
// Sets that fail validation (a driver naming no node, keys of the wrong size) are skipped.
void evaluate_keyposes(std::span<const KeyposeSet> sets, const Skeleton& skeleton, const Pose& pose,
                       std::span<glm::vec3> out);

// Checks a set against a skeleton and a cage: drivers (node in range, finite non-zero axis), keys
// (one finite value per driver, distinct points, vertices sorted, unique and in range, one finite
// offset per vertex). The message names the set, the key and the field.
Status validate_keypose_set(const KeyposeSet& set, size_t num_nodes, size_t num_vertices);

// ---------------------------------------------------------------- editing (values; wrap in with_keyposes)

// A key from dense offsets (#Vc): only non-zero offsets are kept.
KeyposeKey make_key(std::vector<double> values, std::span<const glm::vec3> dense_offsets);
// #Vc offsets of a key, zero where it has none (entries beyond num_vertices are dropped). With
// make_key, the per-vertex form for code that carries per-vertex data through topology changes.
std::vector<glm::vec3> dense_offsets(const KeyposeKey& key, size_t num_vertices);
// Adds the key, replacing one at the same values; keeps keys sorted (lexicographically by values).
void set_key(KeyposeSet& set, KeyposeKey key);
// Keys a sculpt: a copy of `set` with a key at `values` (#D: driver_values at the pose being edited,
// perhaps rounded) whose offsets are what the set gives at `values` now plus `delta` (#Vc, bind
// space: what was sculpted at this pose, which the caller then takes out of
// Document::cage_offsets). Keys are reproduced exactly, so the shape at this pose does not change.
KeyposeSet key_sculpt(const KeyposeSet& set, std::vector<double> values, std::span<const glm::vec3> delta);
// Removes the key at `values`; false when there is none.
bool remove_key(KeyposeSet& set, std::span<const double> values);
// Replaces the set with the same name and drivers, or appends it; returns its index.
size_t upsert_keypose_set(std::vector<KeyposeSet>& sets, KeyposeSet set);
// Drops every key's vertices and offsets (the cage's vertices changed); drivers and values stay.
void clear_vertex_data(std::vector<KeyposeSet>& sets);

// ---------------------------------------------------------------- mirroring

struct MirroredKeyposeSet {
  KeyposeSet set;
  std::vector<uint32_t>
      unmatched;  // keyed vertices no vertex took its offset from (none near their mirror image)
};
// The set for the other side of a character symmetric about x = 0 in its rest pose:
// - each driver's node becomes its mirror by name (core/character/mirror_names.h; a node with no side stays);
// - its axis becomes a' = R_m^-1 X R_n a (R_n, R_m: rest world rotations of the node and its mirror,
//   X: the reflection x -> -x). A reflection turns a rotation by t about n into one by -t about Xn,
//   so kRotation and kTwist read -t about a' (kSwing reads the same). **decision:** the axis is
//   stored as -a' with the values kept when -a' is closer to the original axis (the usual case:
//   the demo character's elbows bend about +X on both sides, and a bulge keyed at 120 degrees
//   mirrors to 120 degrees), otherwise as a' with the values negated;
// - vertices: each cage vertex takes the offset of the vertex nearest its mirror image (core/
//   selection.h mirror_x_counterparts, on the rest cage, within `tolerance`) with x negated (bind
//   space). On a symmetric cage that is the pairwise map; on a cage that is only nearly symmetric
//   (a decimated one), a tolerance of about an edge length transfers the keys without holes;
// - the name is mirror_name(name); a name with no side of its own has its driver joint's name mirrored
//   in it ("forearm.L_X" -> "forearm.R_X"), else (when a driver moved to another joint) " (mirrored)" is
//   added. Mute and solo are copied.
// Fails when a driver's node has no mirror by name (naming it).
Result<MirroredKeyposeSet> mirror_keypose_set(const KeyposeSet& set, const Skeleton& skeleton,
                                              std::span<const glm::vec3> cage_rest, double tolerance);

}  // namespace cagewrap
