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

#include "core/rig/auto_cage.h"
#include "core/cage/cage_attachment.h"
#include "core/io/cage_import.h"
#include "core/character/character.h"
#include "core/character/demo_character.h"
#include "core/document/document.h"
#include "core/cage/keyposes.h"

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

// The demo character (core/character/demo_character.h) with its cage (assets/demo_cage.obj), default settings.
inline Document demo_document() {
  Document doc;
  doc.character = std::make_shared<const Character>(make_demo_character());
  doc.character_hash = "demo";
  auto mesh = load_cage_mesh(std::string(CAGEWRAP_SOURCE_DIR) + "/assets/demo_cage.obj");
  EXPECT_TRUE(mesh.ok()) << mesh.error().message;
  auto cage = make_cage(std::move(mesh).value(), "demo_cage.obj");
  EXPECT_TRUE(cage.ok());
  doc.cage = std::make_shared<const Cage>(std::move(cage).value());
  doc.revision = next_revision();
  return doc;
}

// The demo with the cage the default path builds (`cagewrap cage`, the editor's automatic cage).
// The default path on any character: the automatic cage at its default settings.
inline Document with_automatic_cage(Document doc) {
  auto built = build_auto_cage(*doc.character);
  EXPECT_TRUE(built.ok()) << built.error().message;
  auto cage = make_cage(built->cage, "automatic cage");
  EXPECT_TRUE(cage.ok());
  return with_cage(doc, std::make_shared<const Cage>(std::move(cage).value()));
}

inline Document demo_with_automatic_cage() { return with_automatic_cage(demo_document()); }

// A biceps bulge on the demo character (core/character/demo_character.h) and its cage (assets/demo_cage.obj):
// the cage vertices of the left upper arm's front, mid-bone, pushed 2 cm outwards (bind space),
// keyed at 120 degrees of forearm.L's rotation about its local X (the elbow's bending axis), linear.
struct BicepsKeypose {
  std::vector<uint32_t> vertices;  // the keyed cage vertices
  std::vector<glm::vec3> bulge;    // #Vc offsets, zero elsewhere
  KeyposeSet set;                  // "biceps.L"
};

inline BicepsKeypose demo_biceps_keypose(const Character& demo, std::span<const glm::vec3> cage_rest,
                                         const CageAttachment& att) {
  BicepsKeypose b;
  const Skeleton& sk = demo.skeleton;
  const auto rest = sk.global_transforms(sk.rest_pose());
  const uint32_t upper = sk.find("upper_arm.L"), forearm = sk.find("forearm.L");
  const glm::dvec3 a(rest[upper][3]), e(rest[forearm][3]);  // shoulder and elbow
  b.bulge.assign(cage_rest.size(), glm::vec3(0.0f));
  for (uint32_t v = 0; v < cage_rest.size(); ++v) {
    if (demo.skins[att.skin].joints[att.joint[v]] != upper) continue;
    glm::dvec3 p(cage_rest[v]);
    double t = glm::dot(p - a, e - a) / glm::dot(e - a, e - a);
    glm::dvec3 radial = p - (a + t * (e - a));
    if (t < 0.25 || t > 0.85 || radial.z < 0.3 * glm::length(radial)) continue;  // mid-bone, front
    b.vertices.push_back(v);
    b.bulge[v] = glm::vec3(0.02 * glm::normalize(radial));
  }
  b.set.name = "biceps.L";
  b.set.drivers = {JointDriver{forearm, DriverKind::kRotation, {1, 0, 0}}};
  set_key(b.set, make_key({120}, b.bulge));
  return b;
}

}  // namespace cagewrap::test
