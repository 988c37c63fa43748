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

#include "core/cage/keyposes.h"
#include "core/rig/driver_layer.h"
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

uint32_t node_named(const Skeleton& sk, const std::string& name) {
  for (uint32_t n = 0; n < sk.size(); ++n)
    if (sk.node(n).name == name) return n;
  ADD_FAILURE() << "no node " << name;
  return 0;
}

double largest_distance(std::span<const glm::vec3> a, std::span<const glm::vec3> b) {
  double d = 0.0;
  for (size_t i = 0; i < a.size(); ++i) d = std::max(d, double(glm::distance(a[i], b[i])));
  return d;
}

// The driver as a deformer of the stack (Document::driver_place): its mask scales its displacement per
// point, its place decides whether a later layer takes over its region (in order), and its keyposes add a
// sculpt at a joint angle that is not there at rest.
TEST(DriverLayer, ItsMaskPlaceAndKeyposesMakeItADeformerOfTheStack) {
  const Document plain = test::demo_document();
  const Document driven = with_patch_driver(plain, test::chest_driver(0.06));
  auto base_rig = Rig::create(plain);
  auto driven_rig = Rig::create(driven);
  ASSERT_TRUE(base_rig.ok() && driven_rig.ok());
  const std::vector<glm::vec3> a = posed_skin(plain, *base_rig, {}), b = posed_skin(driven, *driven_rig, {});
  ASSERT_GT(largest_distance(a, b), 0.01) << "the sculpt moves the chest";

  // the mask: its right half (x >= 0) only; the rig made for the driver poses it (the mask is no bind input)
  {
    DriverPlacement place;
    auto mask = std::make_shared<std::vector<float>>(a.size());
    const std::span<const glm::vec3> rest = driven_rig->skin_rest();
    for (size_t i = 0; i < mask->size(); ++i) (*mask)[i] = rest[i].x >= 0.0f ? 1.0f : 0.0f;
    place.mask = mask;
    const Document masked = with_driver_place(driven, place);
    ASSERT_TRUE(driven_rig->fits(masked));
    const std::vector<glm::vec3> m = posed_skin(masked, *driven_rig, {});
    double left = 0.0, right = 0.0, right_moved = 0.0;
    for (size_t i = 0; i < m.size(); ++i) {
      if (rest[i].x < 0.0f) left = std::max(left, double(glm::distance(m[i], a[i])));
      else right = std::max(right, double(glm::distance(m[i], b[i]))), right_moved = std::max(right_moved, double(glm::distance(a[i], b[i])));
    }
    EXPECT_EQ(left, 0.0) << "masked out: the cage's skin alone";
    EXPECT_LT(right, 1e-6) << "mask 1: the whole sculpt";
    EXPECT_GT(right_moved, 0.005) << "the half kept is one the sculpt moves";
  }

  // the place: a layer (the same cage, every point) after the driver takes over in order; before it, not
  {
    std::vector<DeformerLayer> layers(1);
    layers[0].name = "over";
    layers[0].cage = plain.cage;
    layers[0].params = plain.params;
    layers[0].attachment = plain.attachment;
    DriverPlacement first;
    first.after = 0;
    const Document under = with_driver_place(with_layers(driven, layers), first);
    const Document over = with_layers(driven, layers);  // after = -1: after every layer
    auto stack_rig = Rig::create(under);
    ASSERT_TRUE(stack_rig.ok()) << stack_rig.error().message;
    ASSERT_TRUE(stack_rig->fits(over));
    const std::vector<glm::vec3> s_under = posed_skin(under, *stack_rig, {}), s_over = posed_skin(over, *stack_rig, {});
    EXPECT_LT(largest_distance(s_under, a), 1e-5) << "the layer after the driver gives its own skin: the sculpt is gone";
    EXPECT_LT(largest_distance(s_over, b), 1e-5) << "the driver after the layer: the sculpt on it";
    // sum and blend have no order: the driver is added to the combined skin wherever it sits
    DeformerStack sum;
    sum.mode = StackMode::kSum;
    sum.base_muted = true;  // f_0 = p, so the sum is the layer's skin
    const std::vector<glm::vec3> s_sum = posed_skin(with_stack(under, sum), *stack_rig, {});
    EXPECT_LT(largest_distance(s_sum, b), 1e-5);
  }

  // its own binding parameters: another bind (the rig made with the cage's does not fit), another skin
  {
    DriverPlacement own;
    own.params = plain.params;
    own.params->local = 8.0;
    const Document wide = with_driver_place(driven, own);
    EXPECT_FALSE(driven_rig->fits(wide));
    auto wide_rig = Rig::create(wide);
    ASSERT_TRUE(wide_rig.ok());
    EXPECT_GT(largest_distance(posed_skin(wide, *wide_rig, {}), b), 1e-4);
    DriverPlacement same;
    same.params = plain.params;  // the cage's, given as its own: the same binding
    EXPECT_TRUE(driven_rig->fits(with_driver_place(driven, same)));
  }

  // keyposes: the sculpt keyed at 40 degrees of the spine about its X; none at rest, all of it at 40
  {
    const Skeleton& sk = plain.character->skeleton;
    const Document idle_doc = with_patch_driver(plain, test::chest_driver(0.0));
    KeyposeSet set;
    set.name = "spine_X";
    JointDriver jd;
    jd.node = node_named(sk, "spine");
    set.drivers.push_back(jd);
    const std::vector<glm::dvec3> sculpted = test::chest_driver(0.06)->posed.control_points(),
                                  rest = test::chest_driver(0.0)->rest.control_points();
    std::vector<glm::vec3> delta(rest.size());
    for (size_t c = 0; c < rest.size(); ++c) delta[c] = glm::vec3(sculpted[c] - rest[c]);
    DriverPlacement place;
    place.keyposes.push_back(key_sculpt(set, {40.0}, delta));
    const Document keyed = with_driver_place(idle_doc, place);
    auto keyed_rig = Rig::create(keyed);
    ASSERT_TRUE(keyed_rig.ok());
    const Pose at_rest = compose_pose(*plain.character, -1, 0.0, false);
    const Pose bent = pose_at_driver_values(set, std::vector<double>{40.0}, sk, at_rest);
    const Pose half = pose_at_driver_values(set, std::vector<double>{20.0}, sk, at_rest);
    auto pose = [](Rig& rig, const Document& doc, const Pose& p) {
      std::vector<glm::vec3> skin(rig.num_skin_points());
      PosedCage cage;
      EXPECT_TRUE(rig.pose(doc, p, cage, skin).ok());
      return skin;
    };
    EXPECT_EQ(largest_distance(pose(*keyed_rig, keyed, at_rest), pose(*base_rig, plain, at_rest)), 0.0) << "no sculpt at rest";
    const std::vector<glm::vec3> k40 = pose(*keyed_rig, keyed, bent), s40 = pose(*driven_rig, driven, bent);
    EXPECT_LT(largest_distance(k40, s40), 1e-6) << "at the key: the sculpt, carried by the bent spine";
    const double full = largest_distance(s40, pose(*base_rig, plain, bent));
    EXPECT_GT(full, 0.01);
    const double at_half = largest_distance(pose(*keyed_rig, keyed, half), pose(*base_rig, plain, half));
    EXPECT_GT(at_half, 0.3 * full) << "between the keys: part of it (linear)";
    EXPECT_LT(at_half, 0.7 * full);
  }
}

// Several drivers (Document::more_drivers): each binds on its own, their displacements add (each
// with its own mask), their order among themselves does not matter, and a rig made for one driver does
// not pose two.
TEST(DriverLayer, SeveralDriversAddTheirDisplacements) {
  const Document plain = test::demo_document();
  const Document front = with_patch_driver(plain, test::chest_driver(0.06));
  auto pushed_at = [](size_t k, glm::dvec3 by) {
    auto d = test::chest_driver(0.0);
    auto points = d->posed.control_points();
    points[k] += by;
    d->posed.set_control_points(points);
    return std::shared_ptr<const PatchDriver>(d);
  };
  const auto second = pushed_at(20, glm::dvec3(0.0, -0.04, 0.03));
  const Document other = with_patch_driver(plain, second);
  DriverPlacement named;
  named.name = "second";
  const Document both = with_more_drivers(front, {DriverDeformer{second, named}});
  ASSERT_EQ(driver_count(both), 2u);
  EXPECT_EQ(driver_name(both, 1), "second");
  const Skeleton& sk = plain.character->skeleton;
  std::vector<glm::quat> pose(sk.size(), glm::quat(1, 0, 0, 0));
  for (uint32_t n = 0; n < sk.size(); ++n) pose[n] = sk.node(n).rest.rotation;
  pose[node_named(sk, "spine")] = sk.node(node_named(sk, "spine")).rest.rotation * glm::angleAxis(0.5f, glm::vec3(1, 0, 0));
  std::vector<std::vector<glm::vec3>> skins;
  for (const Document* d : {&plain, &front, &other, &both}) {
    auto rig = Rig::create(*d);
    ASSERT_TRUE(rig.ok()) << rig.error().message;
    skins.push_back(posed_skin(*d, *rig, pose));
    if (d == &front) EXPECT_FALSE(rig->fits(both)) << "a rig made for one driver does not pose two";
  }
  const auto &p = skins[0], &a = skins[1], &b = skins[2], &ab = skins[3];
  double worst = 0.0;
  for (size_t i = 0; i < p.size(); ++i) worst = std::max(worst, double(glm::length(ab[i] - (a[i] + b[i] - p[i]))));
  EXPECT_LT(worst, 1e-5) << "the two drivers' displacements add";
  EXPECT_GT(largest_distance(a, p), 0.01);
  EXPECT_GT(largest_distance(b, p), 0.01);
  // the other order: the same skin
  const Document swapped = with_first_driver(both, 1);
  EXPECT_EQ(driver_name(swapped, 0), "second");
  auto rig = Rig::create(swapped);
  ASSERT_TRUE(rig.ok());
  EXPECT_LT(largest_distance(posed_skin(swapped, *rig, pose), ab), 1e-6);
  // the second one masked off everywhere: the first's alone
  Document masked = both;
  masked.more_drivers[0].place.mask = std::make_shared<const std::vector<float>>(p.size(), 0.0f);
  masked.revision = next_revision();
  auto masked_rig = Rig::create(masked);
  ASSERT_TRUE(masked_rig.ok());
  EXPECT_LT(largest_distance(posed_skin(masked, *masked_rig, pose), a), 1e-6);
  // the second soloed: the cages leave the rest skin, and its displacement alone is added to it
  const Document soloed = with_driver_solo(both, 1);
  ASSERT_EQ(soloed_driver(soloed), std::optional<size_t>(1));
  EXPECT_EQ(soloed.stack.solo_driver, "second");
  EXPECT_TRUE(deformer_muted(soloed, 0));
  EXPECT_FALSE(driver_moves_skin(soloed, 0));
  auto solo_rig = Rig::create(soloed);
  ASSERT_TRUE(solo_rig.ok()) << solo_rig.error().message;
  const std::vector<glm::vec3> alone = posed_skin(soloed, *solo_rig, pose);
  std::vector<glm::vec3> skin_rest;
  for (const Primitive& prim : plain.character->primitives) skin_rest.insert(skin_rest.end(), prim.positions.begin(), prim.positions.end());
  double solo_gap = 0.0;
  for (size_t i = 0; i < p.size(); ++i) solo_gap = std::max(solo_gap, double(glm::length(alone[i] - (skin_rest[i] + b[i] - p[i]))));
  EXPECT_LT(solo_gap, 1e-5) << "the rest skin plus the soloed driver's displacement";
  EXPECT_FALSE(soloed_driver(with_driver_solo(soloed, std::nullopt)));
  // removing the first makes the second the first
  const Document rest = without_first_driver(both);
  ASSERT_EQ(driver_count(rest), 1u);
  EXPECT_EQ(rest.patch_driver, second);
}

// The driver's attachment (DriverPlacement::attachment): its control points follow the joints it names, like
// a cage's vertices. Every control point assigned to the hips: with the spine bent the sculpt's displacement
// is the one at rest (the hips do not move), where attached to their closest limbs (the chest) it turns with
// the spine; the rig with the attachment poses the same; fitted is refused, and so is a control point past
// the driver's.
TEST(DriverLayer, ItsControlPointsFollowTheJointsItsAttachmentNames) {
  const Document plain = test::demo_document();
  const Character& ch = *plain.character;
  const Skeleton& sk = ch.skeleton;
  const auto driver = test::chest_driver(0.06);
  std::vector<glm::vec3> rest;
  for (const Primitive& p : ch.primitives) rest.insert(rest.end(), p.positions.begin(), p.positions.end());
  auto layer = DriverLayer::create(ch, rest, *driver, plain.params);
  ASSERT_TRUE(layer.ok()) << layer.error().message;
  std::vector<glm::quat> rot(sk.size());
  for (uint32_t n = 0; n < sk.size(); ++n) rot[n] = sk.node(n).rest.rotation;
  Pose at_rest = compose_pose(ch, -1, 0.0, false, {});
  std::vector<glm::quat> bend = rot;
  const uint32_t spine = node_named(sk, "spine");
  bend[spine] = rot[spine] * glm::angleAxis(0.6f, glm::vec3(1, 0, 0));
  Pose bent = compose_pose(ch, -1, 0.0, false, bend);
  const auto delta = [&](const Pose& pose) {
    std::vector<glm::vec3> d(rest.size());
    EXPECT_TRUE(layer->displacement(*driver, {}, sk, pose, sk.global_transforms(pose), d).ok());
    return d;
  };
  const std::vector<glm::vec3> closest_rest = delta(at_rest), closest_bent = delta(bent);
  EXPECT_GT(largest_distance(closest_rest, closest_bent), 0.01) << "attached to the chest, the sculpt turns with the spine";

  AttachmentSettings hips{AttachmentMode::kRigid};
  std::vector<uint32_t> all(layer->num_control_points());
  std::iota(all.begin(), all.end(), 0u);
  hips = assign_vertices(hips, all, node_named(sk, "hips"));
  ASSERT_TRUE(layer->attach(ch, &hips).ok());
  EXPECT_TRUE(layer->attached_by(&hips));
  EXPECT_FALSE(layer->attached_by(nullptr));
  const std::vector<glm::vec3> hips_rest = delta(at_rest), hips_bent = delta(bent);
  EXPECT_LT(largest_distance(hips_rest, closest_rest), 1e-6) << "at rest the attachment changes nothing";
  EXPECT_LT(largest_distance(hips_rest, hips_bent), 1e-6) << "attached to the hips, the spine's bend does not carry it";

  // the rig: the attachment is part of what it was made for
  Document doc = with_patch_driver(plain, driver);
  DriverPlacement place;
  place.attachment = hips;
  const Document attached = with_driver_place(doc, std::move(place));
  auto rig = Rig::create(attached);
  ASSERT_TRUE(rig.ok()) << rig.error().message;
  EXPECT_FALSE(rig->fits(doc)) << "a rig attached to the hips does not pose the driver attached to its closest limbs";
  auto plain_rig = Rig::create(plain);
  ASSERT_TRUE(plain_rig.ok());
  const std::vector<glm::vec3> f0 = posed_skin(plain, *plain_rig, bend), f = posed_skin(attached, *rig, bend);
  double worst = 0.0;
  for (size_t i = 0; i < f.size(); ++i) worst = std::max(worst, double(glm::length((f[i] - f0[i]) - hips_bent[i])));
  EXPECT_LT(worst, 1e-5) << "the rig adds the hips-attached displacement to the cage's skin";

  // refused: fitted, a control point past the driver's
  AttachmentSettings fitted{AttachmentMode::kFitted};
  EXPECT_FALSE(layer->attach(ch, &fitted).ok());
  AttachmentSettings past{AttachmentMode::kRigid};
  const uint32_t far = static_cast<uint32_t>(layer->num_control_points());
  past = assign_vertices(past, std::span<const uint32_t>(&far, 1), node_named(sk, "hips"));
  auto e = layer->attach(ch, &past);
  ASSERT_FALSE(e.ok());
  EXPECT_NE(e.error().message.find("control point " + std::to_string(far)), std::string::npos) << e.error().message;
  EXPECT_TRUE(layer->attached_by(&hips)) << "a refused attachment leaves the last one";
}

// The driver's contributing-set edits (DriverPlacement::set_edits, sample ids): the rig binds with them
// (the edited points follow the samples named), a rig made without them does not fit, and the other points
// keep their displacement exactly.
TEST(DriverLayer, ItsSetEditsAreBoundWithAndPartOfTheRig) {
  const Document plain = test::demo_document();
  const Document driven = with_patch_driver(plain, test::chest_driver(0.06));
  auto rig = Rig::create(driven);
  ASSERT_TRUE(rig.ok());
  const std::vector<glm::vec3> a = posed_skin(driven, *rig, {});
  // the chest point the sculpt moves most, made to follow the sheet's first sample alone
  const std::vector<glm::vec3> base = [&] {
    auto r = Rig::create(plain);
    EXPECT_TRUE(r.ok());
    return posed_skin(plain, *r, {});
  }();
  uint32_t most = 0;
  for (uint32_t i = 0; i < a.size(); ++i)
    if (glm::distance(a[i], base[i]) > glm::distance(a[most], base[most])) most = i;
  SetEdit e;
  e.point = most;
  e.include = {0};
  e.only = true;
  DriverPlacement place;
  place.set_edits = {e};
  const Document edited = with_driver_place(driven, place);
  EXPECT_FALSE(rig->fits(edited)) << "a rig bound without the edits does not pose them";
  auto edited_rig = Rig::create(edited);
  ASSERT_TRUE(edited_rig.ok()) << edited_rig.error().message;
  const std::vector<glm::vec3> b = posed_skin(edited, *edited_rig, {});
  EXPECT_GT(glm::distance(a[most], b[most]), 0.005) << "the edited point no longer takes the sculpt";
  double others = 0.0;
  for (size_t i = 0; i < a.size(); ++i)
    if (i != most) others = std::max(others, double(glm::distance(a[i], b[i])));
  EXPECT_LT(others, 1e-6) << "the other points keep their displacement";
}

}  // namespace
}  // namespace cagewrap
