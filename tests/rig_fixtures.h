// Small hand-built skinned skeletons (no mesh) for the attachment, keypose and rig tests: a
// straight chain along +Y, and a rig symmetric about x = 0 whose left and right frames mirror like
// the demo character's (local Y along the bone, local X = Y x world Z).
#pragma once

#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <gtest/gtest.h>

#include "core/cage_attachment.h"
#include "core/character.h"
#include "core/document.h"
#include "core/keyposes.h"

namespace cagewrap::test {

struct RigJoint {
  std::string name;
  int parent;
  glm::dvec3 head;   // world, rest
  glm::dmat3 frame;  // world rest rotation (columns: local X, Y, Z)
  bool skinned = true;
};

// Local X = Y x world Z, with Y the bone direction (the demo character's arm frames).
inline glm::dmat3 bone_frame(glm::dvec3 along) {
  glm::dvec3 y = glm::normalize(along);
  glm::dvec3 x = glm::normalize(glm::cross(y, glm::dvec3(0, 0, 1)));
  return glm::dmat3(x, y, glm::cross(x, y));
}

inline Character rig_character(const std::vector<RigJoint>& joints) {
  std::vector<SkeletonNode> nodes(joints.size());
  for (size_t i = 0; i < joints.size(); ++i) {
    const RigJoint& j = joints[i];
    glm::dmat3 parent_r = j.parent >= 0 ? joints[j.parent].frame : glm::dmat3(1.0);
    glm::dvec3 parent_p = j.parent >= 0 ? joints[j.parent].head : glm::dvec3(0.0);
    nodes[i].name = j.name;
    nodes[i].parent = j.parent;
    nodes[i].rest.rotation = glm::quat(glm::normalize(glm::quat_cast(glm::transpose(parent_r) * j.frame)));
    nodes[i].rest.translation = glm::vec3(glm::transpose(parent_r) * (j.head - parent_p));
  }
  Character c;
  c.source = "test rig";
  auto sk = Skeleton::create(std::move(nodes), "test rig");
  EXPECT_TRUE(sk.ok());
  c.skeleton = std::move(sk).value();
  Skin skin;
  skin.name = "rig";
  auto globals = c.skeleton.global_transforms(c.skeleton.rest_pose());
  for (size_t i = 0; i < joints.size(); ++i)
    if (joints[i].skinned) {
      skin.joints.push_back(static_cast<uint32_t>(i));
      skin.inverse_bind.push_back(glm::inverse(globals[i]));
    }
  c.skins.push_back(std::move(skin));
  return c;
}

// upper (0,0,0) -> lower (0,1,0) -> hand (0,2,0), frames = world axes; plus an unskinned node "mesh".
inline Character chain_character() {
  return rig_character({{"upper", -1, {0, 0, 0}, glm::dmat3(1.0)},
                        {"lower", 0, {0, 1, 0}, glm::dmat3(1.0)},
                        {"hand", 1, {0, 2, 0}, glm::dmat3(1.0)},
                        {"mesh", -1, {0, 0, 0}, glm::dmat3(1.0), false}});
}

// spine at the origin; arm.L (0.5,0,0) -> hand.L (1.5,0,0); arm.R, hand.R mirrored; with
// `unpaired`, also tail.L, which has no right counterpart.
inline Character symmetric_character(bool unpaired = false) {
  std::vector<RigJoint> j = {{"spine", -1, {0, 0, 0}, glm::dmat3(1.0)},
                             {"arm.L", 0, {0.5, 0, 0}, bone_frame({1, 0, 0})},
                             {"hand.L", 1, {1.5, 0, 0}, bone_frame({1, 0, 0})},
                             {"arm.R", 0, {-0.5, 0, 0}, bone_frame({-1, 0, 0})},
                             {"hand.R", 3, {-1.5, 0, 0}, bone_frame({-1, 0, 0})}};
  if (unpaired) j.push_back({"tail.L", 0, {0.1, -1, 0}, bone_frame({0, -1, 0})});
  return rig_character(j);
}

// The node's local rotation set to rest * q.
inline void rotate(const Skeleton& skeleton, Pose& pose, const std::string& node, const glm::quat& q) {
  int32_t n = skeleton.find(node);
  ASSERT_GE(n, 0) << node;
  pose.local[n].rotation = glm::normalize(skeleton.node(n).rest.rotation * q);
}

inline glm::quat about_deg(double degrees, glm::dvec3 axis) {
  return glm::quat(glm::angleAxis(glm::radians(degrees), glm::normalize(axis)));
}

// The demo character's biceps bulge (rig_test.cpp's acceptance case): the cage vertices that follow
// the left upper arm, on its front and mid-bone, pushed 2 cm outwards (bind space), keyed at 120
// degrees of elbow flexion (forearm.L's rotation about its local X; linear). `attachment` is the
// demo cage's attachment to the demo character (`doc`).
struct BicepsKey {
  std::vector<uint32_t> vertices;  // the bulging cage vertices
  std::vector<glm::vec3> bulge;    // #Vc offsets (zero elsewhere)
  KeyposeSet set;
};
inline BicepsKey biceps_keypose(const Document& doc, const CageAttachment& attachment) {
  BicepsKey k;
  const Skeleton& sk = doc.character->skeleton;
  const auto rest = sk.global_transforms(sk.rest_pose());
  const uint32_t upper = sk.find("upper_arm.L"), forearm = sk.find("forearm.L");
  const glm::dvec3 a(rest[upper][3]), b(rest[forearm][3]);  // shoulder and elbow
  const auto positions = doc.cage_positions();
  k.bulge.assign(positions.size(), glm::vec3(0.0f));
  for (uint32_t v = 0; v < positions.size(); ++v) {
    if (doc.character->skins[attachment.skin].joints[attachment.joint[v]] != upper) continue;
    glm::dvec3 p(positions[v]);
    double t = glm::dot(p - a, b - a) / glm::dot(b - a, b - a);
    glm::dvec3 radial = p - (a + t * (b - a));
    if (t < 0.25 || t > 0.85 || radial.z < 0.3 * glm::length(radial)) continue;  // mid-bone, front
    k.vertices.push_back(v);
    k.bulge[v] = glm::vec3(0.02 * glm::normalize(radial));
  }
  k.set.name = "biceps.L";
  k.set.drivers = {JointDriver{forearm, DriverKind::kRotation, {1, 0, 0}}};
  set_key(k.set, make_key({120}, k.bulge));
  return k;
}

}  // namespace cagewrap::test
