// Contributing-set editing and display: canonical edit lists, the four edit modes with X-mirroring,
// what a bind makes of each mode, the display queries and the surface brush.
#include "core/deform/set_editing.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/deform/registration.h"
#include "core/document/set_queries.h"
#include "core/document/skin_brush.h"
#include "tests/expect_error.h"
#include "tests/fixtures.h"
#include "tests/set_fixtures.h"

namespace cagewrap {
namespace {

using fixtures::TwoLegs;

std::vector<uint32_t> v(std::initializer_list<uint32_t> x) {
  return x;
}

TEST(CanonicalSetEdits, OnePerPointSortedWithoutContradictionsOrEmptyRules) {
  std::vector<SetEdit> raw = {
      {9, {5, 3, 3}, {4}},
      {2, {7}, {}},
      {9, {8, 1, 8, 2}, {2, 6, 6}},  // the later edit of point 9 wins; 2 both excluded and included
      {4, {}, {}},                   // no rule
      {6, {1, 2}, {3, 1}, true},     // only: the exclusions go
      {5, {3}, {3}},                 // everything included: no exclusion left
  };
  std::vector<SetEdit> c = canonical_set_edits(raw);
  ASSERT_EQ(c.size(), 4u);
  EXPECT_EQ(c[0], (SetEdit{2, {7}, {}}));
  EXPECT_EQ(c[1], (SetEdit{5, {}, {3}}));
  EXPECT_EQ(c[2], (SetEdit{6, {}, {1, 3}, true}));
  EXPECT_EQ(c[3], (SetEdit{9, {1, 8}, {2, 6}}));
  EXPECT_EQ(canonical_set_edits(c), c) << "idempotent";
  // what excludes() says, on canonical edits
  EXPECT_TRUE(c[3].excludes(8));
  EXPECT_FALSE(c[3].excludes(2));
  EXPECT_TRUE(c[2].excludes(2));
  EXPECT_FALSE(c[2].excludes(3));
}

// The raw and the canonical list give the same binding.
TEST(CanonicalSetEdits, BindReadsARawListAsItsCanonicalForm) {
  TwoLegs t = fixtures::two_legs();
  std::vector<SetEdit> raw = {{12, {4, 4, 0}, {9, 0}}, {12, {3}, {}}, {30, {2, 1}, {1}}, {31, {}, {}}};
  BindParams p;
  auto a = bind_skin(t.skin.positions, t.cage, t.cage.polygons.positions, p, raw);
  auto b = bind_skin(t.skin.positions, t.cage, t.cage.polygons.positions, p, canonical_set_edits(raw));
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ(a->set_ids, b->set_ids);
  EXPECT_EQ(a->set_weights, b->set_weights);
}

class EditModes : public ::testing::Test {
 protected:
  TwoLegs t = fixtures::two_legs();
  // the left leg's point nearest to the right leg, half way up
  uint32_t inner_point() const {
    uint32_t best = 0;
    for (uint32_t i = 0; i < t.left_points; ++i)
      if (std::abs(t.skin.positions[i].y - 1.5f) < 0.06f && t.skin.positions[i].x > t.skin.positions[best].x)
        best = i;
    return best;
  }
  Binding bind(std::span<const SetEdit> edits) const {
    auto b = bind_skin(t.skin.positions, t.cage, t.cage.polygons.positions, params, edits);
    EXPECT_TRUE(b.ok()) << (b.ok() ? "" : b.error().message);
    return std::move(b).value();
  }
  std::vector<uint32_t> set_of(const Binding& b, uint32_t point) const {
    auto s = b.sets().of(point);
    std::vector<uint32_t> out(s.begin(), s.end());
    std::sort(out.begin(), out.end());
    return out;
  }
  SetEditResult apply(std::span<const SetEdit> edits, SetEditMode mode, const IndexSet& points,
                      const IndexSet& faces) const {
    auto r = apply_set_edit(edits, mode, points, faces, t.cage, t.skin.num_vertices());
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    return std::move(r).value();
  }
  // the right leg's faces that drive `point` in `b`
  IndexSet right_faces_in_set(const Binding& b, uint32_t point) const {
    std::vector<uint32_t> f;
    for (uint32_t e : b.sets().of(point))
      if (t.cage.element_face[e] >= t.left_faces) f.push_back(t.cage.element_face[e]);
    return IndexSet(std::move(f));
  }
  BindParams params = [] {
    BindParams p;
    p.separate = false;
    return p;
  }();
};

// Figure 5: removing the right leg's faces from the sets of the left leg's points.
TEST_F(EditModes, RemoveTakesTheFacesOutOfTheSets) {
  const uint32_t p = inner_point();
  Binding plain = bind({});
  const IndexSet right = right_faces_in_set(plain, p);
  ASSERT_FALSE(right.empty()) << "the fixture must show the problem";
  SetEditResult r = apply({}, SetEditMode::kRemove, IndexSet{p}, right);
  EXPECT_EQ(r.changed_points, v({p}));
  ASSERT_EQ(r.edits.size(), 1u);
  EXPECT_EQ(r.edits[0].exclude, face_elements(t.cage, right));
  Binding edited = bind(r.edits);
  EXPECT_TRUE(right_faces_in_set(edited, p).empty());
  EXPECT_FALSE(set_of(edited, p).empty());
  // again: nothing changes
  SetEditResult again = apply(r.edits, SetEditMode::kRemove, IndexSet{p}, right);
  EXPECT_TRUE(again.changed_points.empty());
  EXPECT_EQ(again.edits, r.edits);
  // adding them back undoes the exclusion and includes them
  SetEditResult add = apply(r.edits, SetEditMode::kAdd, IndexSet{p}, right);
  EXPECT_TRUE(add.edits[0].exclude.empty());
  EXPECT_EQ(add.edits[0].include, face_elements(t.cage, right));
  // reset drops the rules: the automatic set again
  SetEditResult reset = apply(add.edits, SetEditMode::kReset, IndexSet{p}, {});
  EXPECT_TRUE(reset.edits.empty());
  EXPECT_EQ(reset.changed_points, v({p}));
  EXPECT_EQ(set_of(bind(reset.edits), p), set_of(plain, p));
}

TEST_F(EditModes, AddJoinsFarFacesAndOnlyKeepsJustThem) {
  const uint32_t p = inner_point();
  const IndexSet far{static_cast<uint32_t>(t.left_faces - 1)};  // the left leg's top cap, far from mid-leg
  const std::vector<uint32_t> far_elements = face_elements(t.cage, far);
  Binding plain = bind({});
  for (uint32_t e : far_elements) ASSERT_FALSE(std::ranges::count(set_of(plain, p), e));
  Binding added = bind(apply({}, SetEditMode::kAdd, IndexSet{p}, far).edits);
  for (uint32_t e : far_elements) EXPECT_TRUE(std::ranges::count(set_of(added, p), e));
  EXPECT_GT(set_of(added, p).size(), far_elements.size());
  // only: the set holds nothing else, whatever is nearer
  SetEditResult only = apply({}, SetEditMode::kOnly, IndexSet{p}, far);
  ASSERT_EQ(only.edits.size(), 1u);
  EXPECT_TRUE(only.edits[0].only);
  Binding just = bind(only.edits);
  for (uint32_t e : set_of(just, p)) EXPECT_TRUE(std::ranges::count(far_elements, e)) << e;
  EXPECT_FALSE(set_of(just, p).empty());
  // removing one of them from an `only` set leaves the other
  const IndexSet two{far.indices()[0], static_cast<uint32_t>(t.left_faces / 2)};
  SetEditResult only2 = apply({}, SetEditMode::kOnly, IndexSet{p}, two);
  SetEditResult less = apply(only2.edits, SetEditMode::kRemove, IndexSet{p}, far);
  EXPECT_TRUE(less.edits[0].only);
  EXPECT_EQ(less.edits[0].include, face_elements(t.cage, IndexSet{static_cast<uint32_t>(t.left_faces / 2)}));
  // removing everything from an `only` set leaves an empty set: the point follows an element rigidly
  SetEditResult none =
      apply(less.edits, SetEditMode::kRemove, IndexSet{p}, IndexSet{static_cast<uint32_t>(t.left_faces / 2)});
  ASSERT_EQ(none.edits.size(), 1u);
  Binding empty = bind(none.edits);
  EXPECT_TRUE(set_of(empty, p).empty());
  EXPECT_TRUE(std::ranges::count(empty.rigid_points, p));
}

TEST_F(EditModes, ErrorsNameThePointOrFace) {
  auto r =
      apply_set_edit({}, SetEditMode::kRemove, IndexSet{999999}, IndexSet{0}, t.cage, t.skin.num_vertices());
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("999999"), std::string::npos);
  r = apply_set_edit({}, SetEditMode::kRemove, IndexSet{1}, IndexSet{777}, t.cage, t.skin.num_vertices());
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("face 777"), std::string::npos);
  r = apply_set_edit({}, SetEditMode::kOnly, IndexSet{1}, IndexSet{}, t.cage, t.skin.num_vertices());
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ErrorCode::kInvalidArgument);
  SetEditMode m;
  EXPECT_TRUE(parse_set_edit_mode("only", m));
  EXPECT_EQ(m, SetEditMode::kOnly);
  EXPECT_FALSE(parse_set_edit_mode("erase", m));
}

// The two legs are mirror images: removing the right leg's faces from a left point also removes the
// left leg's mirrored faces from its mirrored point; points and faces without a counterpart are named.
TEST_F(EditModes, MirrorAppliesTheEditToTheOtherSide) {
  const uint32_t p = inner_point();
  const std::vector<glm::vec3> centroids = face_centroids(t.cage.polygons);
  MirrorMap points(t.skin.positions, 1e-4), faces(centroids, 1e-4);
  const IndexSet right{static_cast<uint32_t>(t.left_faces + 2), static_cast<uint32_t>(t.left_faces + 3)};
  auto r = apply_set_edit({}, SetEditMode::kRemove, IndexSet{p}, right, t.cage, t.skin.num_vertices(),
                          {&points, &faces});
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_TRUE(r->unmatched_points.empty());
  EXPECT_TRUE(r->unmatched_faces.empty());
  ASSERT_EQ(r->edits.size(), 2u);
  const uint32_t q = r->edits[1].point;  // the mirrored point, on the right leg
  EXPECT_GE(q, t.left_points);
  EXPECT_NEAR(t.skin.positions[q].x, -t.skin.positions[p].x, 1e-5);
  EXPECT_NEAR(t.skin.positions[q].y, t.skin.positions[p].y, 1e-5);
  EXPECT_NEAR(t.skin.positions[q].z, t.skin.positions[p].z, 1e-5);
  for (uint32_t e : r->edits[1].exclude)
    EXPECT_LT(t.cage.element_face[e], t.left_faces) << "the left leg's faces";
  EXPECT_EQ(r->edits[1].exclude.size(), r->edits[0].exclude.size());
  EXPECT_EQ(r->changed_points, v({p, q}));
  // a slightly asymmetric skin: within the tolerance it still matches, beyond it the point is named
  std::vector<glm::vec3> moved = t.skin.positions;
  moved[q].x += 0.01f;
  MirrorMap loose(moved, 0.02), tight(moved, 0.001);
  r = apply_set_edit({}, SetEditMode::kRemove, IndexSet{p}, right, t.cage, t.skin.num_vertices(),
                     {&loose, &faces});
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(r->unmatched_points.empty());
  r = apply_set_edit({}, SetEditMode::kRemove, IndexSet{p}, right, t.cage, t.skin.num_vertices(),
                     {&tight, &faces});
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->unmatched_points, v({p}));
}

// A point on the plane x = 0 is its own counterpart: it takes both the faces and their mirrors (for
// `only` too, where applying them one after the other would keep only the second).
TEST(MirrorSetEdit, APointOnThePlaneTakesBothSides) {
  PolyMesh skin = fixtures::sphere_skin();
  Cage cage = fixtures::box_cage();
  MirrorMap points(skin.positions, 1e-4);
  const std::vector<glm::vec3> centroids = face_centroids(cage.polygons);
  MirrorMap faces(centroids, 1e-4);
  // a face with centroid x > 0 and its mirror
  uint32_t f = 0;
  while (!(centroids[f].x > 0.5f)) ++f;
  ASSERT_EQ(faces.counterparts(f).size(), 1u);
  const uint32_t g = faces.counterparts(f)[0];
  auto r = apply_set_edit({}, SetEditMode::kOnly, IndexSet{0}, IndexSet{f}, cage, skin.num_vertices(),
                          {&points, &faces});
  ASSERT_TRUE(r.ok());
  ASSERT_EQ(r->edits.size(), 1u) << "the north pole is its own mirror";
  std::vector<uint32_t> both = face_elements(cage, IndexSet{f, g});
  EXPECT_EQ(r->edits[0].include, both);
}

TEST(MirrorMap, MapsARegionOntoARegionWithoutHoles) {
  // left side sampled at 1, 2, 3, 4; right side at -1.5, -2.5, -3.5 (coarser and shifted)
  std::vector<glm::vec3> pts = {{1, 0, 0},     {2, 0, 0},     {3, 0, 0},    {4, 0, 0},
                                {-1.5f, 0, 0}, {-2.5f, 0, 0}, {-3.5f, 0, 0}};
  MirrorMap m(pts, 0.6);
  MirrorResult r = m.mirror(IndexSet{4, 5, 6});
  EXPECT_EQ(r.mirrored, (IndexSet{0, 1, 2, 3})) << "every left point whose mirror lands near a selected one";
  EXPECT_TRUE(r.unmatched.empty());
  MirrorResult back = m.mirror(IndexSet{0, 1, 2, 3});
  EXPECT_EQ(back.mirrored, (IndexSet{4, 5, 6}));
  EXPECT_EQ(MirrorMap(pts, 0.1).mirror(IndexSet{0}).unmatched, v({0}));
  EXPECT_TRUE(MirrorMap().counterparts(3).empty());
}

// ---------------------------------------------------------------------------------------- queries

TEST_F(EditModes, PointSetsAndFaceHeatMaps) {
  const std::vector<SetEdit> edits = apply({}, SetEditMode::kRemove, IndexSet{5}, IndexSet{0, 1}).edits;
  for (Variant variant : {Variant::kBasic, Variant::kClamped, Variant::kExtended}) {
    params.variant = variant;
    Binding b = bind(edits);
    for (uint32_t i : {0u, 5u, inner_point(), t.left_points + 9}) {
      auto s = point_set(b, t.cage, i, edits);
      ASSERT_TRUE(s.ok()) << s.error().message;
      float sum = 0;
      for (size_t k = 0; k < s->members.size(); ++k) {
        sum += s->members[k].weight;
        EXPECT_EQ(s->members[k].face, t.cage.element_face[s->members[k].element]);
        if (k) {
          EXPECT_GE(s->members[k - 1].weight, s->members[k].weight) << "strongest first";
        }
      }
      EXPECT_NEAR(sum, 1.f, 1e-5f);
      EXPECT_EQ(s->edited, i == 5);
    }
    // all faces drive every point fully; no face drives nothing; a face's share is what its members weigh
    auto all = face_influence(b, t.cage, select_all(static_cast<uint32_t>(t.cage.polygons.num_faces())));
    ASSERT_TRUE(all.ok());
    for (float x : *all) EXPECT_NEAR(x, 1.f, 1e-5f);
    auto none = face_influence(b, t.cage, IndexSet{});
    for (float x : *none) EXPECT_EQ(x, 0.f);
    const IndexSet right = right_faces_in_set(b, inner_point());
    auto heat = face_influence(b, t.cage, right);
    auto s = point_set(b, t.cage, inner_point());
    float expect = 0;
    for (const SetMember& m : s->members) expect += right.contains(m.face) ? m.weight : 0.f;
    EXPECT_NEAR((*heat)[inner_point()], expect, 1e-6f);
    EXPECT_GT(expect, 0.f);
    EXPECT_EQ((*heat)[5], 0.f) << "point 5's set no longer holds faces 0 and 1... nor any right face";
  }
  Binding b = bind({});
  EXPECT_FALSE(point_set(b, t.cage, 999999).ok());
  Cage other = fixtures::box_cage();
  auto wrong = point_set(b, other, 0);
  ASSERT_FALSE(wrong.ok());
  EXPECT_EQ(wrong.error().code, ErrorCode::kTopologyMismatch);
  // an extended binding without its set table (from a version 1 file) says to bind again
  params.variant = Variant::kExtended;
  Binding old = bind({});
  old.set_offsets.clear();
  auto no_sets = face_influence(old, t.cage, IndexSet{0});
  ASSERT_FALSE(no_sets.ok());
  EXPECT_NE(no_sets.error().message.find("bind again"), std::string::npos);
}

TEST_F(EditModes, OverviewFlagsEmptyEditedAndBadlyBoundPoints) {
  SetEdit none{3, {}, {}, true};  // an empty set
  // point 8 (at the bottom) may use only the top cap's elements: far away, so badly bound
  SetEdit far{8, {}, face_elements(t.cage, IndexSet{static_cast<uint32_t>(t.left_faces - 1)}), true};
  std::vector<SetEdit> edits = {none, far};
  for (Variant variant : {Variant::kBasic, Variant::kExtended}) {
    params.variant = variant;
    Binding b = bind(edits);
    auto o = set_overview(b, t.skin.positions, edits);
    ASSERT_TRUE(o.ok()) << o.error().message;
    EXPECT_EQ(o->outside, b.num_points - b.quality_inside) << "the cage-quality test, point by point";
    EXPECT_EQ(o->empty, b.rigid_points.size());
    EXPECT_TRUE(o->flags[3] & kSetEmpty);
    EXPECT_TRUE(o->flags[3] & kSetEdited);
    EXPECT_TRUE(o->flags[8] & kSetEdited);
    EXPECT_EQ(o->edited, 2u);
    EXPECT_EQ(o->size[3], 0);
    EXPECT_EQ(o->max_size, b.max_set_size);
    EXPECT_NEAR(o->mean_size * b.num_points, double(b.total_set_size), 1e-6);
    EXPECT_TRUE(o->flags[8] & kSetOutside);
    EXPECT_FALSE(o->flags[100] & kSetOutside);
  }
  EXPECT_EQ(edited_points(edits), (IndexSet{3, 8}));
  EXPECT_FALSE(set_overview(bind({}), std::vector<glm::vec3>(3), {}).ok());
}

// ---------------------------------------------------------------------------------------- brush

TEST(SkinBrush, MeasuresAlongTheSurfaceAndDoesNotJumpTheGap) {
  TwoLegs t = fixtures::two_legs();
  Triangulation tri = triangulate(t.skin);
  SkinBrush brush(t.skin.positions, tri.triangles);
  // a triangle on the left leg's inner side, half way up
  uint32_t hit_tri = 0;
  double best = -1e9;
  for (uint32_t k = 0; k < tri.triangles.size(); ++k) {
    glm::dvec3 c(0.0);
    for (uint32_t v : tri.triangles[k]) c += glm::dvec3(t.skin.positions[v]) / 3.0;
    if (tri.triangles[k][0] < t.left_points && std::abs(c.y - 1.5) < 0.1 && c.x > best)
      best = c.x, hit_tri = k;
  }
  glm::dvec3 hit(0.0);
  for (uint32_t v : tri.triangles[hit_tri]) hit += glm::dvec3(t.skin.positions[v]) / 3.0;
  // 0.5 in space reaches the right leg (0.3 away); along the surface it does not
  auto r = brush.points_within(hit_tri, hit, 0.5);
  ASSERT_TRUE(r.ok()) << r.error().message;
  ASSERT_FALSE(r->points.empty());
  EXPECT_TRUE(std::is_sorted(r->points.begin(), r->points.end()));
  size_t in_space = 0;
  for (uint32_t i = 0; i < t.skin.num_vertices(); ++i)
    in_space += glm::length(glm::dvec3(t.skin.positions[i]) - hit) <= 0.5;
  for (size_t k = 0; k < r->points.size(); ++k) {
    const uint32_t i = r->points[k];
    EXPECT_LT(i, t.left_points) << "the brush crossed the gap";
    EXPECT_LE(r->distance[k], 0.5f);
    // graph distance is never shorter than the straight line
    EXPECT_GE(r->distance[k] + 1e-5, glm::length(glm::dvec3(t.skin.positions[i]) - hit));
  }
  EXPECT_LT(r->points.size(), in_space);
  // straight up the leg the graph distance is exact (rings 0.1 apart)
  const uint32_t corner = tri.triangles[hit_tri][0];
  auto z = brush.points_within(hit_tri, glm::dvec3(t.skin.positions[corner]), 0.35);
  ASSERT_TRUE(z.ok());
  const uint32_t up3 = corner + 3 * 24;  // three rings up the same column
  auto it = std::lower_bound(z->points.begin(), z->points.end(), up3);
  ASSERT_TRUE(it != z->points.end() && *it == up3);
  EXPECT_NEAR(z->distance[static_cast<size_t>(it - z->points.begin())], 0.3, 1e-5);
  // radius 0: the corners at the hit point only; a repeat gives the same answer (scratch reset)
  auto zero = brush.points_within(hit_tri, glm::dvec3(t.skin.positions[corner]), 0.0);
  EXPECT_EQ(zero->points, v({corner}));
  auto again = brush.points_within(hit_tri, hit, 0.5);
  EXPECT_EQ(again->points, r->points);
  EXPECT_FALSE(brush.points_within(static_cast<uint32_t>(tri.triangles.size()), hit, 0.1).ok());
  EXPECT_FALSE(brush.points_within(hit_tri, hit, -1).ok());
  EXPECT_FALSE(brush.points_within(hit_tri, glm::dvec3(NAN), 1).ok());
}

}  // namespace
}  // namespace cagewrap

namespace cagewrap {
namespace {

// Set edits by element id (a parametric driver's samples, issue 21): the same rules as by cage faces, with the
// elements given directly (duplicates and order ignored); errors name the point or element out of range.
TEST(ElementSetEdit, AppliesTheModesToTheGivenElements) {
  const std::vector<SetEdit> none;
  auto only = apply_element_set_edit(none, SetEditMode::kOnly, IndexSet{4, 9}, std::vector<uint32_t>{7, 2, 7}, 10, 8);
  ASSERT_TRUE(only.ok()) << only.error().message;
  ASSERT_EQ(only->edits.size(), 2u);
  EXPECT_TRUE(only->edits[0] == (SetEdit{4, {}, {2, 7}, true}));
  EXPECT_EQ(only->changed_points, (std::vector<uint32_t>{4, 9}));
  auto removed = apply_element_set_edit(only->edits, SetEditMode::kRemove, IndexSet{4}, std::vector<uint32_t>{7}, 10, 8);
  ASSERT_TRUE(removed.ok());
  EXPECT_TRUE(removed->edits[0] == (SetEdit{4, {}, {2}, true})) << "removing from an `only` set drops it from the included";
  auto added = apply_element_set_edit(none, SetEditMode::kAdd, IndexSet{1}, std::vector<uint32_t>{3}, 10, 8);
  ASSERT_TRUE(added.ok());
  EXPECT_TRUE(added->edits[0] == (SetEdit{1, {}, {3}, false}));
  auto reset = apply_element_set_edit(only->edits, SetEditMode::kReset, IndexSet{9}, {}, 10, 8);
  ASSERT_TRUE(reset.ok());
  EXPECT_EQ(reset->edits.size(), 1u);
  EXPECT_EQ(reset->changed_points, (std::vector<uint32_t>{9}));
  auto same = apply_element_set_edit(only->edits, SetEditMode::kOnly, IndexSet{4}, std::vector<uint32_t>{2, 7}, 10, 8);
  ASSERT_TRUE(same.ok());
  EXPECT_TRUE(same->changed_points.empty()) << "the same rule again changes nothing";

  EXPECT_TRUE(Fails(apply_element_set_edit(none, SetEditMode::kAdd, IndexSet{10}, std::vector<uint32_t>{1}, 10, 8),
                    ErrorCode::kIndexOutOfRange, {"skin point 10"}));
  EXPECT_TRUE(Fails(apply_element_set_edit(none, SetEditMode::kAdd, IndexSet{1}, std::vector<uint32_t>{8}, 10, 8),
                    ErrorCode::kIndexOutOfRange, {"element 8", "there are 8"}));
  EXPECT_TRUE(Fails(apply_element_set_edit(none, SetEditMode::kAdd, IndexSet{1}, {}, 10, 8), ErrorCode::kInvalidArgument,
                    {"no elements given to add"}));
}

}  // namespace
}  // namespace cagewrap
