// The parametric driver as a deformer of the posed skin (issue 21, core/rig/driver_layer.h): its
// sculpt is added to the cage's skin and follows the skeleton. On the demo character with a driver
// fitted in front of the chest and one control point pushed out: at rest the rig's skin moves by the
// sculpt around the chest only; with the whole character turned a quarter turn (an override of the
// root), the sculpt turns with it; a driver with no sculpt adds nothing; a rig made without the
// driver does not fit a document with it.
#include <algorithm>
#include <numeric>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include "core/rig/rig.h"
#include "tests/driver_fixtures.h"
#include "tests/rig_fixtures.h"

namespace cagewrap {
namespace {

std::vector<glm::vec3> posed_skin(const Document& doc, Rig& rig, std::span<const glm::quat> overrides) {
  std::vector<glm::vec3> skin(rig.num_skin_points());
  PosedCage cage;
  EXPECT_TRUE(rig.pose_clip(doc, -1, 0.0, overrides, cage, skin).ok());
  return skin;
}

TEST(DriverLayer, TheSculptIsAddedToTheCageSkinAndFollowsTheSkeleton) {
  const Document plain = test::demo_document();
  const Document driven = with_patch_driver(plain, test::chest_driver(0.06));
  auto without = Rig::create(plain);
  auto with = Rig::create(driven);
  ASSERT_TRUE(without.ok()) << without.error().message;
  ASSERT_TRUE(with.ok()) << with.error().message;
  EXPECT_FALSE(without->fits(driven)) << "a rig made without the driver does not pose it";

  // at rest: the sculpt, around the chest only
  const std::vector<glm::vec3> a = posed_skin(plain, *without, {}), b = posed_skin(driven, *with, {});
  size_t most = 0;
  double largest = 0.0, far = 0.0;
  for (size_t i = 0; i < a.size(); ++i) {
    const double d = glm::distance(a[i], b[i]);
    if (d > largest) largest = d, most = i;
    if (a[i].y < 0.6f) far = std::max(far, d);  // the legs
  }
  EXPECT_GT(largest, 0.01) << "the sculpt moves the chest";
  EXPECT_LT(largest, 0.06);
  EXPECT_LT(far, 1e-4) << "and not the legs";
  const glm::vec3 sculpt_rest = b[most] - a[most];

  // the whole character a quarter turn about y (the root's override): the sculpt turns with it
  const Skeleton& sk = plain.character->skeleton;
  std::vector<glm::quat> turn(sk.size(), glm::quat(1, 0, 0, 0));
  uint32_t root = 0;
  for (uint32_t n = 0; n < sk.size(); ++n)
    if (sk.node(n).name == "hips") root = n;
  turn[root] = sk.node(root).rest.rotation * glm::angleAxis(glm::radians(90.0f), glm::vec3(0, 1, 0));
  const std::vector<glm::vec3> ta = posed_skin(plain, *without, turn), tb = posed_skin(driven, *with, turn);
  const glm::vec3 sculpt_turned = tb[most] - ta[most];
  // the root's world rotation changed by q r q^-1 (q its rest rotation, r the quarter turn)
  const glm::quat q = sk.node(root).rest.rotation;
  const glm::vec3 expected = (q * glm::angleAxis(glm::radians(90.0f), glm::vec3(0, 1, 0)) * glm::inverse(q)) * sculpt_rest;
  EXPECT_LT(glm::length(sculpt_turned - expected), 0.15 * glm::length(sculpt_rest))
      << "the sculpt at rest (" << sculpt_rest.x << ", " << sculpt_rest.y << ", " << sculpt_rest.z << ") turned ("
      << sculpt_turned.x << ", " << sculpt_turned.y << ", " << sculpt_turned.z << ")";
  EXPECT_GT(glm::length(sculpt_turned - sculpt_rest), 0.5 * glm::length(sculpt_rest)) << "not left where it was at rest";

  // a driver with no sculpt adds nothing
  const Document idle = with_patch_driver(plain, test::chest_driver(0.0));
  auto idle_rig = Rig::create(idle);
  ASSERT_TRUE(idle_rig.ok());
  EXPECT_EQ(posed_skin(idle, *idle_rig, turn), ta);
}

}  // namespace
}  // namespace cagewrap
