// Registration with set edits and part labels: the hierarchy against the brute-force loop, automatic
// separation on the two-legs fixture, and Rebinder::update (set edits) and Rebinder::move_rest with
// ReachIndex (moved rest cage vertices) against a full bind, bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <numeric>
#include <random>

#include "core/deform/deformer.h"
#include "core/deform/registration.h"
#include "core/deform/rest_edit.h"
#include "core/deform/set_editing.h"
#include "tests/fixtures.h"
#include "tests/set_fixtures.h"

namespace cagewrap {
namespace {

using fixtures::TwoLegs;

Binding bind_or_die(const TwoLegs& t, const BindParams& p, std::span<const SetEdit> edits = {},
                    const PartLabels* labels = nullptr) {
  auto b = bind_skin(t.skin.positions, t.cage, t.cage.polygons.positions, p, edits, {}, labels);
  EXPECT_TRUE(b.ok()) << (b.ok() ? "" : b.error().message);
  return std::move(b).value();
}

// The tests run each case without part labels, then with the two legs' labels.
std::array<const PartLabels*, 2> without_and_with_labels(const TwoLegs& t) { return {nullptr, &t.labels}; }

// Every table of two bindings, bit for bit (floats compared as stored).
void expect_same_tables(const Binding& a, const Binding& b) {
  EXPECT_EQ(a.offsets, b.offsets);
  EXPECT_EQ(a.ids, b.ids);
  EXPECT_EQ(a.weights, b.weights);
  EXPECT_EQ(a.bary, b.bary);
  EXPECT_EQ(a.set_offsets, b.set_offsets);
  EXPECT_EQ(a.set_ids, b.set_ids);
  EXPECT_EQ(a.set_weights, b.set_weights);
  EXPECT_EQ(a.rigid_points, b.rigid_points);
  EXPECT_EQ(a.rigid_element, b.rigid_element);
  EXPECT_EQ(a.rigid_bary, b.rigid_bary);
  EXPECT_EQ(a.separated, b.separated);
  EXPECT_EQ(a.total_separated, b.total_separated);
  EXPECT_EQ(a.separated_points, b.separated_points);
  EXPECT_EQ(a.quality_inside, b.quality_inside);
  EXPECT_EQ(a.max_set_size, b.max_set_size);
  EXPECT_EQ(a.total_set_size, b.total_set_size);
  EXPECT_EQ(a.reach, b.reach);
}

// Some edits of every kind on the two legs: remove a face of the other leg, add one, make one face
// the only one, exclude everything (an empty set: a fallback point).
std::vector<SetEdit> assorted_edits(const TwoLegs& t) {
  const IndexSet left_face{3}, right_face{static_cast<uint32_t>(t.left_faces + 3)};
  std::vector<SetEdit> edits;
  auto apply = [&](SetEditMode mode, IndexSet points, const IndexSet& faces) {
    auto r = apply_set_edit(edits, mode, points, faces, t.cage, t.skin.num_vertices());
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    edits = std::move(r->edits);
  };
  apply(SetEditMode::kRemove, IndexSet{0, 1, 2, 3, 40, 41}, right_face);
  apply(SetEditMode::kAdd, IndexSet{100, 101, 102}, right_face);
  apply(SetEditMode::kOnly, IndexSet{200, 201, t.left_points + 5}, left_face);
  SetEdit none{300, {}, {}};
  for (uint32_t e = 0; e < t.cage.num_elements(); ++e) none.exclude.push_back(e);
  edits.push_back(none);
  return canonical_set_edits(edits);
}

class EveryVariantSets : public ::testing::TestWithParam<Variant> {};

// The hierarchy (with its per-point fallback to a direct query when edits or labels hide a point's
// nearest elements) gives the brute-force loop's tables exactly, separation counts included.
TEST_P(EveryVariantSets, HierarchyMatchesBruteForceWithEditsAndLabels) {
  TwoLegs t = fixtures::two_legs();
  BindParams p;
  p.variant = GetParam();
  const std::vector<SetEdit> edits = assorted_edits(t);
  for (const PartLabels* labels : without_and_with_labels(t)) {
    Binding fast = bind_or_die(t, p, edits, labels);
    auto slow = bind_skin_brute_force(t.skin.positions, t.cage, t.cage.polygons.positions, p, edits, labels);
    ASSERT_TRUE(slow.ok()) << slow.error().message;
    expect_same_tables(fast, *slow);
    EXPECT_EQ(fast.separation_applied, labels != nullptr);
  }
}

// Rebinder::update on some points equals a full bind with the same edits: the touched points'
// stencils bit for bit, the others unchanged; and a deformer told of the change deforms like a new one.
TEST_P(EveryVariantSets, UpdateEqualsAFullBind) {
  TwoLegs t = fixtures::two_legs();
  BindParams p;
  p.variant = GetParam();
  for (const PartLabels* labels : without_and_with_labels(t)) {
    auto rebinder = Rebinder::create(t.skin.positions, t.cage, t.cage.polygons.positions, p, labels);
    ASSERT_TRUE(rebinder.ok()) << rebinder.error().message;
    Binding before = std::move(rebinder->bind({})).value();
    expect_same_tables(before, bind_or_die(t, p, {}, labels));
    const std::vector<SetEdit> edits = assorted_edits(t);
    std::vector<uint32_t> touched;
    for (const SetEdit& e : edits) touched.push_back(e.point);
    touched.push_back(7);  // a point without an edit: re-registered to the same stencil
    std::sort(touched.begin(), touched.end());
    Binding live = before;
    auto deformer = Deformer::create(live, t.skin.positions);
    ASSERT_TRUE(deformer.ok());
    ASSERT_TRUE(rebinder->update(live, edits, touched).ok());
    ASSERT_TRUE(deformer->stencil_changed().ok());
    Binding full = bind_or_die(t, p, edits, labels);
    expect_same_tables(live, full);
    EXPECT_FALSE(live.rigid_points.empty()) << "the point that excludes everything follows an element";
    // untouched points: the very same entries as before the update
    auto sets_before = before.sets(), sets_after = live.sets();
    for (uint32_t i = 0; i < live.num_points; ++i) {
      if (std::binary_search(touched.begin(), touched.end(), i)) continue;
      ASSERT_TRUE(std::ranges::equal(sets_before.of(i), sets_after.of(i))) << "point " << i;
    }
    // a bent pose: the updated deformer and a fresh one agree exactly
    auto posed = fixtures::bent(t.cage.polygons.positions, 1.5, 30);
    std::vector<glm::vec3> a(t.skin.num_vertices()), b(t.skin.num_vertices());
    ASSERT_TRUE(deformer->deform(posed, a).ok());
    auto fresh = Deformer::create(full, t.skin.positions);
    ASSERT_TRUE(fresh.ok());
    ASSERT_TRUE(fresh->deform(posed, b).ok());
    EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.size() * sizeof(glm::vec3)));
    // resetting the edits with another update gives the unedited binding back
    ASSERT_TRUE(rebinder->update(live, {}, touched).ok());
    expect_same_tables(live, before);
  }
}

// Moving rest cage vertices: the points ReachIndex finds, re-registered on the moved cage, give a
// full bind on it bit for bit (edits and labels included), move after move; a local move touches a
// part of the skin only. One move collapses a vertex onto its neighbour (degenerate elements).
TEST_P(EveryVariantSets, RestMoveEqualsAFullBind) {
  TwoLegs t = fixtures::two_legs();
  BindParams p;
  p.variant = GetParam();
  const std::vector<SetEdit> edits = assorted_edits(t);
  for (const PartLabels* labels : without_and_with_labels(t)) {
    p.scale = bind_or_die(t, p, edits, labels).h;  // a fixed h: the moves below leave it alone
    Binding live = bind_or_die(t, p, edits, labels);
    auto index = ReachIndex::create(live, t.skin.positions);
    ASSERT_TRUE(index.ok()) << index.error().message;
    std::vector<glm::vec3> rest = t.cage.polygons.positions;
    const Tri first = t.cage.elements[0];
    const std::vector<std::vector<uint32_t>> moves = {{0}, {first[1], first[2]}, {first[0]}};
    for (size_t m = 0; m < moves.size(); ++m) {
      for (uint32_t v : moves[m]) rest[v] += glm::vec3(0.03f * float(m + 1), -0.05f, 0.02f);
      if (m == 2) rest[first[0]] = rest[first[1]];  // element 0 (and its neighbours) collapse
      auto points = index->affected_points(live, t.cage, rest, moves[m], edits);
      ASSERT_TRUE(points.ok()) << points.error().message;
      EXPECT_FALSE(points->empty());
      EXPECT_LT(points->size(), t.skin.num_vertices() / 2) << "move " << m << " is local";
      auto rebinder = Rebinder::create(t.skin.positions, t.cage, rest, p, labels);
      ASSERT_TRUE(rebinder.ok()) << rebinder.error().message;
      ASSERT_TRUE(rebinder->move_rest(live, edits, *points).ok());
      index->refresh(live, *points);
      auto full = bind_skin(t.skin.positions, t.cage, rest, p, edits, {}, labels);
      ASSERT_TRUE(full.ok()) << full.error().message;
      SCOPED_TRACE("move " + std::to_string(m));
      expect_same_tables(live, *full);
      EXPECT_EQ(live.rest_cage, full->rest_cage);
      EXPECT_EQ(live.element_status, full->element_status);
      EXPECT_EQ(live.invalid_elements, full->invalid_elements);
    }
    EXPECT_FALSE(live.invalid_elements.empty()) << "the collapse made degenerate elements";
  }
}

INSTANTIATE_TEST_SUITE_P(Sets, EveryVariantSets,
                         ::testing::Values(Variant::kBasic, Variant::kClamped, Variant::kExtended),
                         [](const auto& info) { return std::string(variant_name(info.param)); });

// A random walk of edits applied stroke by stroke keeps the live binding equal to a full bind.
TEST(Rebinder, StrokeAfterStrokeStaysEqualToAFullBind) {
  TwoLegs t = fixtures::two_legs();
  BindParams p;
  auto rebinder = Rebinder::create(t.skin.positions, t.cage, t.cage.polygons.positions, p, &t.labels);
  ASSERT_TRUE(rebinder.ok());
  Binding live = std::move(rebinder->bind({})).value();
  std::vector<SetEdit> edits;
  std::mt19937 rng(7);
  const SetEditMode modes[] = {SetEditMode::kRemove, SetEditMode::kAdd, SetEditMode::kOnly,
                               SetEditMode::kReset};
  for (int stroke = 0; stroke < 12; ++stroke) {
    std::vector<uint32_t> points;
    const uint32_t first = rng() % t.skin.num_vertices();
    for (uint32_t k = 0; k < 40; ++k)
      points.push_back((first + k) % static_cast<uint32_t>(t.skin.num_vertices()));
    IndexSet faces{static_cast<uint32_t>(rng() % t.cage.polygons.num_faces()),
                   static_cast<uint32_t>(rng() % t.cage.polygons.num_faces())};
    auto r = apply_set_edit(edits, modes[rng() % 4], IndexSet(points), faces, t.cage, t.skin.num_vertices());
    ASSERT_TRUE(r.ok()) << r.error().message;
    edits = r->edits;
    ASSERT_TRUE(rebinder->update(live, edits, r->changed_points).ok());
  }
  expect_same_tables(live, bind_or_die(t, p, edits, &t.labels));
}

TEST(Rebinder, RefusesABindingOfAnotherSkinCageOrParameters) {
  TwoLegs t = fixtures::two_legs();
  BindParams p;
  auto rebinder = Rebinder::create(t.skin.positions, t.cage, t.cage.polygons.positions, p);
  ASSERT_TRUE(rebinder.ok());
  Binding b = std::move(rebinder->bind({})).value();
  BindParams other = p;
  other.local = 2;
  Binding wrong_params = bind_or_die(t, other);
  auto s = rebinder->update(wrong_params, {}, std::vector<uint32_t>{1});
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, ErrorCode::kInvalidArgument);
  Binding wrong_cage = b;
  wrong_cage.rest_cage[0].x += 1;
  s = rebinder->update(wrong_cage, {}, std::vector<uint32_t>{1});
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, ErrorCode::kTopologyMismatch);
  s = rebinder->update(b, {}, std::vector<uint32_t>{99999});
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("99999"), std::string::npos);
  std::vector<SetEdit> bad = {{5, {}, {99999}}};
  s = rebinder->update(b, bad, std::vector<uint32_t>{1});
  ASSERT_FALSE(s.ok()) << "every edit is checked, not only the touched points'";
  EXPECT_NE(s.error().message.find("99999"), std::string::npos);
  // the one-off form
  auto copy = rebind_points(b, t.skin.positions, t.cage, t.cage.polygons.positions, p, {},
                            std::vector<uint32_t>{1, 2});
  ASSERT_TRUE(copy.ok());
  expect_same_tables(*copy, b);
}

// What a rest edit cannot do locally, or is given wrong, is refused with what to do.
TEST(RestEdit, RefusesAnotherHBadVerticesAndAFileBinding) {
  TwoLegs t = fixtures::two_legs();
  BindParams p;  // scale 0: h is the mean cage edge length, which a move changes
  Binding b = bind_or_die(t, p);
  auto index = ReachIndex::create(b, t.skin.positions);
  ASSERT_TRUE(index.ok());
  std::vector<glm::vec3> rest = t.cage.polygons.positions;
  rest[3].y += 0.2f;
  auto rebinder = Rebinder::create(t.skin.positions, t.cage, rest, p);
  ASSERT_TRUE(rebinder.ok());
  auto points = index->affected_points(b, t.cage, rest, std::vector<uint32_t>{3}, {});
  ASSERT_TRUE(points.ok());
  auto s = rebinder->move_rest(b, {}, *points);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("scale h"), std::string::npos) << s.error().message;
  auto bad = index->affected_points(b, t.cage, rest, std::vector<uint32_t>{4242}, {});
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("4242"), std::string::npos);
  std::vector<glm::vec3> short_rest(rest.begin(), rest.end() - 1);
  EXPECT_FALSE(index->affected_points(b, t.cage, short_rest, std::vector<uint32_t>{3}, {}).ok());
  Binding from_file = b;
  from_file.reach.clear();
  auto none = ReachIndex::create(from_file, t.skin.positions);
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.error().message.find("bind again"), std::string::npos);
}

// Separation on the two legs: without it the inside of each leg takes elements of the other leg's
// cage; with it none does, the report counts what it kept out, and the rest pose is still exact.
TEST(Separation, KeepsTheLegsApart) {
  TwoLegs t = fixtures::two_legs();
  const uint32_t left_elements = [&] {
    uint32_t n = 0;
    for (uint32_t f : t.cage.element_face) n += f < t.left_faces;
    return n;
  }();
  auto crossing = [&](const Binding& b) {
    size_t n = 0;
    auto sets = b.sets();
    for (uint32_t i = 0; i < b.num_points; ++i)
      for (uint32_t e : sets.of(i))
        if ((i < t.left_points) != (e < left_elements)) {
          ++n;
          break;
        }
    return n;
  };
  BindParams p;
  p.separate = false;
  Binding off = bind_or_die(t, p, {}, &t.labels);
  p.separate = true;
  Binding on = bind_or_die(t, p, {}, &t.labels);
  Binding unlabelled = bind_or_die(t, p);
  EXPECT_GT(crossing(off), 20u);
  EXPECT_EQ(crossing(on), 0u);
  EXPECT_FALSE(off.separation_applied);
  EXPECT_TRUE(off.separated.empty());
  EXPECT_FALSE(unlabelled.separation_applied) << "no labels: nothing to separate by";
  EXPECT_EQ(crossing(unlabelled), crossing(off));
  EXPECT_TRUE(on.separation_applied);
  ASSERT_EQ(on.separated.size(), on.num_points);
  EXPECT_GE(on.separated_points, crossing(off));
  EXPECT_EQ(on.total_separated, std::accumulate(on.separated.begin(), on.separated.end(), uint64_t{0}));
  // 2 steps join the legs through the hips: nothing separated
  p.separation_steps = 2;
  Binding two = bind_or_die(t, p, {}, &t.labels);
  EXPECT_EQ(crossing(two), crossing(off));
  EXPECT_EQ(two.separated_points, 0u);
  // rest reproduction
  auto d = Deformer::create(on, t.skin.positions);
  ASSERT_TRUE(d.ok());
  std::vector<glm::vec3> out(t.skin.num_vertices());
  ASSERT_TRUE(d->deform(t.cage.polygons.positions, out).ok());
  EXPECT_LE(fixtures::max_distance(out, t.skin.positions), 1e-5);
}

TEST(Separation, BadLabelsAreNamed) {
  TwoLegs t = fixtures::two_legs();
  BindParams p;
  auto fails_with = [&](const PartLabels& l, const std::string& text) {
    auto b = bind_skin(t.skin.positions, t.cage, t.cage.polygons.positions, p, {}, {}, &l);
    ASSERT_FALSE(b.ok());
    EXPECT_EQ(b.error().code, ErrorCode::kInvalidArgument);
    EXPECT_NE(b.error().message.find(text), std::string::npos) << b.error().message;
  };
  PartLabels l = t.labels;
  l.point.pop_back();
  fails_with(l, "skin points");
  l = t.labels;
  l.cage_vertex.push_back(1);
  fails_with(l, "cage vertices");
  l = t.labels;
  l.point[17] = 9;
  fails_with(l, "skin point 17");
  l = t.labels;
  l.parent = {1, 0, 0};
  fails_with(l, "cycle");
  l = t.labels;
  l.parent = {-1, 5, 0};
  fails_with(l, "parent 5");
  p.separation_steps = 65;
  auto b = bind_skin(t.skin.positions, t.cage, t.cage.polygons.positions, p, {}, {}, &t.labels);
  ASSERT_FALSE(b.ok());
  EXPECT_NE(b.error().message.find("separation steps"), std::string::npos);
}

// An unlabelled point or cage vertex is connected to everything.
TEST(Separation, UnlabelledConnectsToEverything) {
  TwoLegs t = fixtures::two_legs();
  BindParams p;
  PartLabels l = t.labels;
  std::fill(l.point.begin(), l.point.end(), PartLabels::kUnlabelled);
  Binding none = bind_or_die(t, p, {}, &l);
  EXPECT_EQ(none.separated_points, 0u);
  p.separate = false;
  Binding off = bind_or_die(t, p);
  EXPECT_EQ(none.ids, off.ids);
  EXPECT_EQ(none.weights, off.weights);
  l = t.labels;
  std::fill(l.cage_vertex.begin(), l.cage_vertex.end(), PartLabels::kUnlabelled);
  p.separate = true;
  Binding open_cage = bind_or_die(t, p, {}, &l);
  EXPECT_EQ(open_cage.ids, off.ids);
}

}  // namespace
}  // namespace cagewrap
