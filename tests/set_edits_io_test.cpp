// Set edits as inputs that last: the set edits file (docs/edits-format.md) with its rules and errors,
// the project file keeping `only` edits and the separation parameters, edits surviving a rebind with
// other parameters, and edits made with each mode carried across cage subdivision.
#include "core/io/set_edits_io.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "core/document/cage_subdivide.h"
#include "core/document/project_io.h"
#include "core/deform/registration.h"
#include "core/document/topology_change.h"
#include "tests/document_fixtures.h"
#include "tests/expect_error.h"
#include "tests/set_fixtures.h"

namespace cagewrap {
namespace {

using fixtures::TwoLegs;
using test::read_text;
using test::write_text;

class SetEditsFileTest : public test::TempDirTest {
 protected:
  TwoLegs t = fixtures::two_legs();
  Result<ResolvedSetEdits> resolve(const std::string& text) {
    write_text(path("e.json"), text);
    auto f = load_set_edits(path("e.json"));
    if (!f) return f.error();
    return resolve_set_edits(*f, path("e.json"), t.skin.positions, t.cage);
  }
};

TEST_F(SetEditsFileTest, SavedEditsLoadBackCanonical) {
  std::vector<SetEdit> edits = {{40, {9, 3}, {}}, {7, {}, {5, 1}, true}, {12, {2}, {2, 4}}};
  ASSERT_TRUE(save_set_edits(path("e.json"), edits, t.skin.num_vertices(), t.cage.num_elements()).ok());
  const std::string text = read_text(path("e.json"));
  EXPECT_NE(text.find("\"format\": \"cagewrap-set-edits\""), std::string::npos) << text;
  EXPECT_NE(text.find("{\"point\": 7, \"exclude\": [], \"include\": [1, 5], \"only\": true}"),
            std::string::npos)
      << text;
  auto f = load_set_edits(path("e.json"));
  ASSERT_TRUE(f.ok()) << f.error().message;
  EXPECT_EQ(f->num_points, int64_t(t.skin.num_vertices()));
  EXPECT_EQ(f->num_elements, int64_t(t.cage.num_elements()));
  EXPECT_TRUE(f->rules.empty());
  EXPECT_EQ(f->edits, canonical_set_edits(edits));
  auto r = resolve_set_edits(*f, path("e.json"), t.skin.positions, t.cage);
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r->edits, canonical_set_edits(edits));
  ASSERT_TRUE(save_set_edits(path("none.json"), {}, 3, 4).ok());
  auto none = load_set_edits(path("none.json"));
  ASSERT_TRUE(none.ok());
  EXPECT_TRUE(none->edits.empty());
}

// Rules by point and face lists give what apply_set_edit gives, mirrored when asked.
TEST_F(SetEditsFileTest, RulesResolveInOrder) {
  const uint32_t rf = static_cast<uint32_t>(t.left_faces + 2);
  auto r = resolve(R"({"format": "cagewrap-set-edits", "version": 1,
    "edits": [{"point": 3, "exclude": [0]}],
    "rules": [
      {"mode": "remove", "points": [10, 11, 12], "faces": [)" +
                   std::to_string(rf) + R"(], "mirror": 0.0001},
      {"mode": "only", "points": [20], "faces": [1, 2]},
      {"mode": "add", "points": [3], "faces": [0]},
      {"mode": "reset", "points": [12]}
    ]})");
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_TRUE(r->warnings.empty());
  std::vector<SetEdit> expect = {{3, {}, {0}}};
  const std::vector<glm::vec3> centroids = face_centroids(t.cage.polygons);
  MirrorMap pm(t.skin.positions, 0.0001), fm(centroids, 0.0001);
  expect = apply_set_edit(expect, SetEditMode::kRemove, IndexSet{10, 11, 12}, IndexSet{rf}, t.cage,
                          t.skin.num_vertices(), {&pm, &fm})
               ->edits;
  expect =
      apply_set_edit(expect, SetEditMode::kOnly, IndexSet{20}, IndexSet{1, 2}, t.cage, t.skin.num_vertices())
          ->edits;
  expect = apply_set_edit(expect, SetEditMode::kAdd, IndexSet{3}, IndexSet{0}, t.cage, t.skin.num_vertices())
               ->edits;
  expect =
      apply_set_edit(expect, SetEditMode::kReset, IndexSet{12}, IndexSet{}, t.cage, t.skin.num_vertices())
          ->edits;
  EXPECT_EQ(r->edits, expect);
  EXPECT_EQ(r->edits.size(), 7u)
      << "points 3, 10, 11, 20 and the mirrors of 10, 11, 12 (12 itself was reset)";
  // a mirror with no counterpart is a warning naming the rule
  t.skin.positions[10].x += 0.01f;
  auto w = resolve(R"({"format": "cagewrap-set-edits", "version": 1,
    "rules": [{"mode": "remove", "points": [10], "faces": [0], "mirror": 1e-9}]})");
  ASSERT_TRUE(w.ok());
  ASSERT_EQ(w->warnings.size(), 1u);
  EXPECT_NE(w->warnings[0].find("rules[0]"), std::string::npos) << w->warnings[0];
}

TEST_F(SetEditsFileTest, ErrorsNameTheFileAndTheJsonPath) {
  const std::string f = path("e.json");
  const std::string head = R"({"format": "cagewrap-set-edits", "version": 1, )";
  EXPECT_TRUE(Fails(load_set_edits(path("missing.json")), ErrorCode::kFileNotFound, {"missing.json"}));
  EXPECT_TRUE(Fails(resolve("{\n  \"format\": 1,,\n}"), ErrorCode::kParse, {f, "line 2"}));
  EXPECT_TRUE(Fails(resolve(R"({"format": "cagewrap-project", "version": 1})"), ErrorCode::kUnsupportedFormat,
                    {f, "not a set edits file"}));
  EXPECT_TRUE(Fails(resolve(R"({"format": "cagewrap-set-edits", "version": 7, "edits": []})"),
                    ErrorCode::kVersion, {f, "version 7", "up to 1"}));
  EXPECT_TRUE(Fails(resolve(head + R"("other": []})"), ErrorCode::kParse, {f, "neither"}));
  EXPECT_TRUE(Fails(resolve(head + R"("edits": [{"exclude": [1]}]})"), ErrorCode::kParse,
                    {f, "edits[0].point is missing"}));
  EXPECT_TRUE(Fails(resolve(head + R"("edits": [{"point": 1, "include": [1, -2]}]})"), ErrorCode::kParse,
                    {f, "edits[0].include[1] should be an index"}));
  EXPECT_TRUE(Fails(resolve(head + R"("edits": [{"point": 1, "only": "yes"}]})"), ErrorCode::kParse,
                    {f, "edits[0].only should be true or false"}));
  EXPECT_TRUE(Fails(resolve(head + R"("edits": [{"point": 1, "exclude": [0, 99999]}]})"),
                    ErrorCode::kIndexOutOfRange,
                    {f, "edits[0].exclude[1] is element 99999, but the cage has"}));
  EXPECT_TRUE(Fails(resolve(head + R"("edits": [{"point": 99999}]})"), ErrorCode::kIndexOutOfRange,
                    {f, "edits[0].point is skin point 99999"}));
  EXPECT_TRUE(Fails(resolve(head + R"("rules": [{"mode": "erase", "points": [1], "faces": [1]}]})"),
                    ErrorCode::kParse, {f, "rules[0].mode is \"erase\""}));
  EXPECT_TRUE(Fails(resolve(head + R"("rules": [{"mode": "add", "points": [1]}]})"), ErrorCode::kParse,
                    {f, "rules[0].faces is missing"}));
  EXPECT_TRUE(Fails(resolve(head + R"("rules": [{"mode": "add", "points": [1], "faces": [5000]}]})"),
                    ErrorCode::kIndexOutOfRange, {f, "rules[0].faces[0] is face 5000, but the cage has"}));
  EXPECT_TRUE(
      Fails(resolve(head + R"("rules": [{"mode": "add", "points": [1], "faces": [0], "mirror": 0}]})"),
            ErrorCode::kParse, {f, "rules[0].mirror"}));
  EXPECT_TRUE(Fails(resolve(head + R"("points": 5, "edits": []})"), ErrorCode::kTopologyMismatch,
                    {f, "made for a skin of 5 points"}));
  EXPECT_TRUE(Fails(resolve(head + R"("elements": 5, "edits": []})"), ErrorCode::kTopologyMismatch,
                    {f, "made for a cage of 5 elements"}));
}

// ---------------------------------------------------------------------------------------- lasting

class ProjectSetEdits : public test::TempDirTest {};

// `only` edits and the separation parameters are saved with the document; a project written before
// separation existed loads with it off (its deformation does not change).
TEST_F(ProjectSetEdits, OnlyEditsAndSeparationRoundTrip) {
  test::write_tiny_character(path("hero.gltf"));
  test::write_box_cage(path("cage.obj"));
  auto doc = document_from_files(path("hero.gltf"), path("cage.obj"));
  ASSERT_TRUE(doc.ok());
  BindParams p;
  p.separate = true;
  p.separation_steps = 3;
  Document d = with_set_edits(with_params(*doc, p), {SetEdit{1, {}, {4, 5}, true}, SetEdit{2, {0}, {}}});
  ASSERT_TRUE(save_project(path("p.cagewrap"), d).ok());
  auto back = load_project(path("p.cagewrap"));
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_TRUE(back->warnings.empty());
  EXPECT_TRUE(same_content(d, back->document));
  EXPECT_TRUE(back->document.set_edits[0].only);
  EXPECT_EQ(back->document.params.separation_steps, 3u);
  // an older file: no separation fields
  std::string text = read_text(path("p.cagewrap"));
  for (const std::string field : {", \"separate\": true", ", \"separation_steps\": 3"}) {
    auto at = text.find(field);
    ASSERT_NE(at, std::string::npos) << field << " in " << text;
    text.erase(at, field.size());
  }
  write_text(path("old.cagewrap"), text);
  auto old = load_project(path("old.cagewrap"));
  ASSERT_TRUE(old.ok()) << old.error().message;
  EXPECT_FALSE(old->document.params.separate);
  EXPECT_EQ(old->document.params.separation_steps, 1u);
}

std::set<uint32_t> set_of(const Binding& b, uint32_t p) {
  auto s = b.sets().of(p);
  return std::set<uint32_t>(s.begin(), s.end());
}

// The same edits under other parameters (variant, falloff, K, threshold): removed elements stay out,
// `only` sets stay inside their faces.
TEST(SetEditsLast, ThroughARebindWithOtherParameters) {
  TwoLegs t = fixtures::two_legs();
  const IndexSet right{static_cast<uint32_t>(t.left_faces + 3), static_cast<uint32_t>(t.left_faces + 4)};
  const IndexSet left{2, 3};
  std::vector<uint32_t> points;
  for (uint32_t i = 0; i < t.left_points; i += 7) points.push_back(i);
  auto removed =
      apply_set_edit({}, SetEditMode::kRemove, IndexSet(points), right, t.cage, t.skin.num_vertices());
  auto only = apply_set_edit(removed->edits, SetEditMode::kOnly, IndexSet{t.left_points + 1}, right, t.cage,
                             t.skin.num_vertices());
  const std::vector<uint32_t> right_elements = face_elements(t.cage, right);
  for (Variant variant : {Variant::kBasic, Variant::kClamped, Variant::kExtended})
    for (double local : {2.0, 6.0})
      for (uint32_t k : {3u, 16u}) {
        BindParams p;
        p.variant = variant;
        p.local = local;
        p.max_elements = k;
        p.epsilon = k == 3 ? 0.3 : 0.02;
        auto b = bind_skin(t.skin.positions, t.cage, t.cage.polygons.positions, p, only->edits);
        ASSERT_TRUE(b.ok());
        for (uint32_t i : points)
          for (uint32_t e : right_elements) EXPECT_FALSE(set_of(*b, i).count(e)) << "point " << i;
        for (uint32_t e : set_of(*b, t.left_points + 1)) EXPECT_TRUE(std::ranges::count(right_elements, e));
      }
}

// Edits made with each mode, carried across subdivision (carry_set_edits): the removed faces' children
// stay out of the edited sets, an `only` set keeps to its faces' children, an added far face's children
// join; without the edits they behave otherwise.
TEST(SetEditsLast, AcrossCageSubdivision) {
  TwoLegs t = fixtures::two_legs();
  const uint32_t n = static_cast<uint32_t>(t.skin.num_vertices());
  // left points on the inner side, half way up
  std::vector<uint32_t> inner;
  for (uint32_t i = 0; i < t.left_points; ++i)
    if (t.skin.positions[i].x > -0.3f && std::abs(t.skin.positions[i].y - 1.5f) < 0.3f) inner.push_back(i);
  ASSERT_GT(inner.size(), 5u);
  BindParams p;
  p.separate = false;
  auto plain = bind_skin(t.skin.positions, t.cage, t.cage.polygons.positions, p);
  ASSERT_TRUE(plain.ok());
  p.scale = plain->h;   // the finer cages' mean edge is shorter: keep the same reach
  p.max_elements = 48;  // and their more numerous elements within it

  std::set<uint32_t> right_faces_used;
  for (uint32_t i : inner)
    for (uint32_t e : set_of(*plain, i))
      if (t.cage.element_face[e] >= t.left_faces) right_faces_used.insert(t.cage.element_face[e]);
  ASSERT_FALSE(right_faces_used.empty());
  const IndexSet right(std::vector<uint32_t>(right_faces_used.begin(), right_faces_used.end()));
  const IndexSet top{static_cast<uint32_t>(t.left_faces - 1)};  // the left leg's top cap
  const uint32_t only_point = t.left_points + 40, add_point = 60;
  std::vector<SetEdit> edits =
      apply_set_edit({}, SetEditMode::kRemove, IndexSet(inner), right, t.cage, n)->edits;
  edits = apply_set_edit(edits, SetEditMode::kOnly, IndexSet{only_point}, IndexSet{0, 1}, t.cage, n)->edits;
  edits = apply_set_edit(edits, SetEditMode::kAdd, IndexSet{add_point}, top, t.cage, n)->edits;

  for (const char* op : {"linear", "loop", "refine"}) {
    SCOPED_TRACE(op);
    std::vector<uint32_t> all_right(right.begin(), right.end());
    Result<CageEdit> change = std::string(op) == "linear" ? subdivide_linear(t.cage)
                              : std::string(op) == "loop" ? subdivide_loop(t.cage)
                                                          : refine_faces(t.cage, all_right);
    ASSERT_TRUE(change.ok()) << change.error().message;
    auto carried = carry_set_edits(change->change, edits);
    ASSERT_TRUE(carried.ok());
    EXPECT_EQ(carried->size(), edits.size());
    const Cage& fine = change->cage;
    const ElementChildren children = element_children(change->change);
    auto children_of = [&](std::span<const uint32_t> old_elements) {
      std::set<uint32_t> out;
      for (uint32_t e : old_elements)
        for (uint32_t c : children.of(e)) out.insert(c);
      return out;
    };
    const std::set<uint32_t> removed = children_of(face_elements(t.cage, right));
    const std::set<uint32_t> only_faces = children_of(face_elements(t.cage, IndexSet{0, 1}));
    const std::set<uint32_t> added = children_of(face_elements(t.cage, top));
    auto with = bind_skin(t.skin.positions, fine, fine.polygons.positions, p, *carried);
    auto without = bind_skin(t.skin.positions, fine, fine.polygons.positions, p);
    ASSERT_TRUE(with.ok() && without.ok());
    size_t used_with = 0, used_without = 0;
    for (uint32_t i : inner) {
      for (uint32_t e : set_of(*with, i)) used_with += removed.count(e);
      for (uint32_t e : set_of(*without, i)) used_without += removed.count(e);
    }
    EXPECT_EQ(used_with, 0u);
    EXPECT_GT(used_without, 0u);
    EXPECT_FALSE(set_of(*with, only_point).empty());
    for (uint32_t e : set_of(*with, only_point)) EXPECT_TRUE(only_faces.count(e)) << e;
    size_t joined = 0;
    for (uint32_t e : set_of(*with, add_point)) joined += added.count(e);
    EXPECT_GT(joined, 0u);
    for (uint32_t e : set_of(*without, add_point)) EXPECT_FALSE(added.count(e));
  }
}

}  // namespace
}  // namespace cagewrap
