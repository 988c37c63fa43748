// rebind_new_topology (core/deform/rest_edit.h): after a topology edit of the cage (refine, merge,
// flip, triangulate), the points out of reach of every removed and added element keep their rows, the
// others are registered again, and the result is a fresh bind on the new cage, bit for bit.
#include <gtest/gtest.h>

#include <functional>

#include "core/deform/registration.h"
#include "core/deform/rest_edit.h"
#include "core/deform/set_editing.h"
#include "core/document/cage_edit.h"
#include "core/document/cage_subdivide.h"
#include "core/document/topology_change.h"
#include "tests/fixtures.h"
#include "tests/set_fixtures.h"

namespace cagewrap {
namespace {

constexpr Variant kVariants[] = {Variant::kBasic, Variant::kClamped, Variant::kExtended};

struct Op {
  const char* name;
  std::function<Result<CageEdit>(const Cage&)> apply;
  bool local;  // a local edit: most points keep their rows
};

std::vector<Op> cylinder_ops() {
  return {
      {"refine a face", [](const Cage& c) { return refine_faces(c, std::vector<uint32_t>{17}); }, true},
      {"merge two vertices", [](const Cage& c) { return merge_vertices(c, std::vector<uint32_t>{17, 18}); }, true},
      {"flip a face", [](const Cage& c) { return flip_faces(c, std::vector<uint32_t>{3}); }, true},
      {"triangulate", [](const Cage& c) { return triangulate_cage(c); }, false},
      {"subdivide", [](const Cage& c) { return subdivide_linear(c, 1); }, false},
  };
}

TEST(TopologyRebind, EqualsAFreshBindAndKeepsTheRowsOutOfReach) {
  const PolyMesh skin = fixtures::cylinder_skin();
  const Cage cage = fixtures::cylinder_cage();
  const auto& rest = cage.polygons.positions;
  for (Variant v : kVariants) {
    BindParams p;
    p.variant = v;
    p.scale = 0.7;  // fixed: the mean edge length changes with the topology
    auto bound = bind_skin(skin.positions, cage, rest, p);
    ASSERT_TRUE(bound.ok());
    for (const Op& op : cylinder_ops()) {
      auto edit = op.apply(cage);
      ASSERT_TRUE(edit.ok()) << op.name << ": " << edit.error().message;
      const auto& new_rest = edit->cage.polygons.positions;
      Binding b = *bound;
      auto r = rebind_new_topology(b, skin.positions, edit->cage, new_rest, {}, {}, nullptr, nullptr);
      ASSERT_TRUE(r.ok()) << op.name << ": " << r.error().message;
      auto fresh = bind_skin(skin.positions, edit->cage, new_rest, p);
      ASSERT_TRUE(fresh.ok());
      EXPECT_EQ(registration_difference(b, *fresh), "") << op.name << ", " << variant_name(v);
      std::printf("  %s (%s): %zu kept, %zu removed, %zu added elements; %zu of %zu points again\n", op.name,
                  variant_name(v), r->kept_elements, r->removed_elements, r->added_elements, r->points,
                  skin.positions.size());
      if (op.local) {
        EXPECT_GT(r->kept_elements, 0u) << op.name;
        EXPECT_GT(r->points, 0u) << op.name;
        EXPECT_LT(r->points, skin.positions.size() / 2) << op.name << ": most rows should be kept";
      }
    }
  }
}

// With part labels (carried to the new vertices as the document carries them) and set edits
// (carried to the new elements): the edited points are registered again, the result is a fresh bind's.
TEST(TopologyRebind, CarriesLabelsAndSetEdits) {
  const fixtures::TwoLegs t = fixtures::two_legs();
  const auto& rest = t.cage.polygons.positions;
  const uint32_t right = static_cast<uint32_t>(t.left_faces);
  std::vector<SetEdit> edits = {{5, {0, 1}, {}, false}, {t.left_points + 9, {}, {right + 3}, false}};
  edits = canonical_set_edits(edits);
  BindParams p;
  p.scale = 0.5;
  auto bound = bind_skin(t.skin.positions, t.cage, rest, p, edits, {}, &t.labels);
  ASSERT_TRUE(bound.ok());
  auto edit = refine_faces(t.cage, std::vector<uint32_t>{17, right + 20});
  ASSERT_TRUE(edit.ok()) << edit.error().message;
  PartLabels labels = t.labels;
  labels.cage_vertex = carry_vertex_labels(edit->change, t.labels.cage_vertex);
  auto carried = carry_set_edits(edit->change, edits);
  ASSERT_TRUE(carried.ok());
  const auto& new_rest = edit->cage.polygons.positions;
  Binding b = *bound;
  auto r = rebind_new_topology(b, t.skin.positions, edit->cage, new_rest, *carried, edits, &labels, &t.labels);
  ASSERT_TRUE(r.ok()) << r.error().message;
  auto fresh = bind_skin(t.skin.positions, edit->cage, new_rest, p, *carried, {}, &labels);
  ASSERT_TRUE(fresh.ok());
  EXPECT_EQ(registration_difference(b, *fresh), "");
  EXPECT_TRUE(b.separation_applied);
  EXPECT_LT(r->points, t.skin.positions.size() / 2);
}

TEST(TopologyRebind, RefusesWhatItCannotKeep) {
  const PolyMesh skin = fixtures::cylinder_skin();
  const Cage cage = fixtures::cylinder_cage();
  const auto& rest = cage.polygons.positions;
  auto edit = refine_faces(cage, std::vector<uint32_t>{0});
  ASSERT_TRUE(edit.ok());
  const auto& new_rest = edit->cage.polygons.positions;
  // a scale of 0: h is the mean edge length, which the refinement changes
  auto bound = bind_skin(skin.positions, cage, rest, BindParams{});
  ASSERT_TRUE(bound.ok());
  Binding b = *bound;
  auto r = rebind_new_topology(b, skin.positions, edit->cage, new_rest, {}, {}, nullptr, nullptr);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("distance scale h"), std::string::npos) << r.error().message;
  // a binding without reach (read from a file)
  BindParams p;
  p.scale = 0.7;
  bound = bind_skin(skin.positions, cage, rest, p);
  ASSERT_TRUE(bound.ok());
  b = *bound;
  b.reach.clear();
  r = rebind_new_topology(b, skin.positions, edit->cage, new_rest, {}, {}, nullptr, nullptr);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("bind again"), std::string::npos) << r.error().message;
  // elements in another order: the same cage with its faces reversed
  PolyMesh reversed;
  reversed.positions = cage.polygons.positions;
  for (size_t f = cage.polygons.num_faces(); f-- > 0;) reversed.add_face(cage.polygons.face(f));
  auto shuffled = make_cage(reversed, "reversed");
  ASSERT_TRUE(shuffled.ok());
  b = *bound;
  r = rebind_new_topology(b, skin.positions, *shuffled, reversed.positions, {}, {}, nullptr, nullptr);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("reordered"), std::string::npos) << r.error().message;
  EXPECT_EQ(registration_difference(b, *bound), "") << "a refused rebind leaves the binding as it was";
}

}  // namespace
}  // namespace cagewrap
