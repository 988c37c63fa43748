// Tests for core/document/topology_change.h: composing changes, carrying set edits, offsets and labels, the
// errors of apply_topology_change; and the key property: a bound, edited cage subdivided (linear,
// Loop, local) and rebound with its carried edits still reproduces the skin at rest, and the carried
// exclusions still take effect.
#include "core/document/topology_change.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <set>

#include "core/cage/cage_attachment.h"
#include "core/document/cage_edit.h"
#include "core/cage/keyposes.h"
#include "core/document/cage_subdivide.h"
#include "core/deform/deformer.h"
#include "core/deform/registration.h"
#include "tests/cage_checks.h"
#include "tests/expect_error.h"
#include "tests/fixtures.h"

namespace cagewrap {
namespace {

using V = std::vector<uint32_t>;

Document document_with(const Cage& cage) {
  Document doc;
  doc.cage = std::make_shared<const Cage>(cage);
  doc.revision = next_revision();
  return doc;
}

// An affine field of the rest positions: interpolating it with affine weights is exact.
glm::vec3 field(const glm::vec3& p) {
  return {0.5f * p.x - p.z + 0.1f, 2.0f * p.y, 0.3f - 0.25f * p.x};
}

TEST(TopologyChange, IdentityAndComposition) {
  const Cage oct = test::octahedron_cage();
  const CageTopologyChange id = identity_change(oct);
  EXPECT_TRUE(check_change(id, oct, oct).ok());
  auto one = subdivide_linear(oct);
  ASSERT_TRUE(one.ok());
  const CageTopologyChange same = compose(id, one->change);
  EXPECT_EQ(same.vertex_parents, one->change.vertex_parents);
  EXPECT_EQ(same.element_parents, one->change.element_parents);
  // two steps composed = two levels; a second-level vertex has up to 3 parents in the octahedron
  auto two = subdivide_linear(one->cage);
  auto both = subdivide_linear(oct, 2);
  ASSERT_TRUE(two.ok() && both.ok());
  const CageTopologyChange c = compose(one->change, two->change);
  EXPECT_EQ(c.vertex_offsets, both->change.vertex_offsets);
  EXPECT_EQ(c.vertex_parents, both->change.vertex_parents);
  EXPECT_EQ(c.element_parents, both->change.element_parents);
  EXPECT_EQ(c.face_parent, both->change.face_parent);
  EXPECT_TRUE(check_change(c, oct, both->cage).ok());
  size_t most = 0;
  for (size_t v = 0; v < c.num_vertices(); ++v) most = std::max(most, c.parents_of_vertex(v).size());
  EXPECT_EQ(most, 3u);  // the quarter points inside a face: (1/2, 1/4, 1/4)
}

TEST(TopologyChange, CheckChangeNamesTheMismatch) {
  const Cage oct = test::octahedron_cage();
  auto one = subdivide_linear(oct);
  ASSERT_TRUE(one.ok());
  EXPECT_TRUE(Fails(check_change(one->change, fixtures::box_cage(), one->cage), ErrorCode::kTopologyMismatch,
                    {"starts from a cage of vertex count 6", "has 26"}));
  EXPECT_TRUE(Fails(check_change(one->change, oct, oct), ErrorCode::kTopologyMismatch, {"ends at a cage"}));
  CageTopologyChange broken = one->change;
  broken.vertex_weights[0] = 0.5;
  EXPECT_TRUE(
      Fails(check_change(broken, oct, one->cage), ErrorCode::kInvalidArgument, {"new vertex 0", "sum"}));
}

TEST(TopologyChange, SetEditsPassToChildrenAndSurvivors) {
  const Cage oct = test::octahedron_cage();
  auto one = subdivide_linear(oct);
  ASSERT_TRUE(one.ok());
  std::vector<SetEdit> edits = {{7, {2}, {0}}, {3, {5, 2}, {}}};
  auto carried = carry_set_edits(one->change, edits);
  ASSERT_TRUE(carried.ok()) << carried.error().message;
  ASSERT_EQ(carried->size(), 2u);
  EXPECT_EQ((*carried)[0].point, 7u);
  EXPECT_EQ((*carried)[0].exclude, (V{8, 9, 10, 11}));
  EXPECT_EQ((*carried)[0].include, (V{0, 1, 2, 3}));
  EXPECT_EQ((*carried)[1].exclude, (V{8, 9, 10, 11, 20, 21, 22, 23}));

  // a merge: the elements of collapsed faces have no child; an edit left empty is removed
  auto merged = merge_vertices(oct, V{0, 2});
  ASSERT_TRUE(merged.ok());
  auto m = carry_set_edits(merged->change, std::vector<SetEdit>{{1, {0, 1}, {}}, {2, {4}, {}}});
  ASSERT_TRUE(m.ok());
  ASSERT_EQ(m->size(), 1u);
  EXPECT_EQ((*m)[0].exclude, (V{0}));  // old element 1 is new element 0; old 0 collapsed

  EXPECT_TRUE(Fails(carry_set_edits(one->change, std::vector<SetEdit>{{4, {99}, {}}}),
                    ErrorCode::kIndexOutOfRange, {"point 4", "element 99", "8 elements"}));
}

TEST(TopologyChange, VertexAttributesAndLabels) {
  const Cage oct = test::octahedron_cage();
  auto loop = subdivide_loop(oct);
  ASSERT_TRUE(loop.ok());
  std::vector<glm::vec3> values;
  for (const auto& p : oct.polygons.positions) values.push_back(field(p));
  auto carried = interpolate_vertex_attribute(loop->change, values);
  ASSERT_EQ(carried.size(), loop->cage.num_vertices());
  for (size_t v = 0; v < carried.size(); ++v)
    EXPECT_LT(glm::length(carried[v] - field(loop->cage.polygons.positions[v])), 1e-5f) << v;
  std::vector<double> scalars = {0, 1, 2, 3, 4, 5};
  auto s = interpolate_vertex_attribute(loop->change, std::span<const double>(scalars));
  EXPECT_NEAR(s[4],
              4 * (1 - 4 * (5.0 / 8 - std::pow(3.0 / 8 + 0.25 * std::cos(M_PI / 2), 2)) / 4) +
                  (5.0 / 8 - std::pow(3.0 / 8 + 0.25 * std::cos(M_PI / 2), 2)) / 4 * (0 + 2 + 1 + 3),
              1e-12);

  // labels: even vertices keep theirs; an edge vertex (3/8, 3/8, 1/8, 1/8) takes its lower end's
  std::vector<uint32_t> joints = {10, 11, 12, 13, 14, 15};
  auto labels = carry_vertex_labels(loop->change, joints);
  for (uint32_t v = 0; v < 6; ++v) EXPECT_EQ(labels[v], joints[v]);
  for (size_t v = 6; v < labels.size(); ++v) {
    auto parents = loop->change.parents_of_vertex(v);
    auto weights = loop->change.weights_of_vertex(v);
    uint32_t lowest_heaviest = UINT32_MAX;
    for (size_t i = 0; i < parents.size(); ++i)
      if (weights[i] == 0.375) lowest_heaviest = std::min(lowest_heaviest, parents[i]);
    EXPECT_EQ(labels[v], joints[lowest_heaviest]) << v;
    EXPECT_EQ(dominant_parent(loop->change, v), lowest_heaviest);
  }
}

TEST(ApplyTopologyChange, CarriesOffsetsAndEditsAndChecksTheCage) {
  const Cage oct = test::octahedron_cage();
  Document doc = document_with(oct);
  doc.set_edits = {{0, {1}, {}}};
  for (const auto& p : oct.polygons.positions) doc.cage_offsets.push_back(field(p));
  auto edit = subdivide_linear(oct);
  ASSERT_TRUE(edit.ok());
  auto out = apply_topology_change(doc, *edit);
  ASSERT_TRUE(out.ok()) << out.error().message;
  EXPECT_NE(out->revision, doc.revision);
  EXPECT_EQ(out->cage->num_elements(), 32u);
  ASSERT_EQ(out->cage_offsets.size(), 18u);
  for (size_t v = 0; v < 18; ++v)
    EXPECT_LT(glm::length(out->cage_offsets[v] - field(out->cage->polygons.positions[v])), 1e-6f);
  ASSERT_EQ(out->set_edits.size(), 1u);
  EXPECT_EQ(out->set_edits[0].exclude, (V{4, 5, 6, 7}));
  EXPECT_EQ(doc.cage->num_elements(), 8u);  // the input document is left alone

  Document no_offsets = document_with(oct);
  auto plain = apply_topology_change(no_offsets, *edit);
  ASSERT_TRUE(plain.ok());
  EXPECT_TRUE(plain->cage_offsets.empty());

  EXPECT_TRUE(Fails(apply_topology_change(Document{}, *edit), ErrorCode::kInvalidArgument, {"no cage"}));
  EXPECT_TRUE(Fails(apply_topology_change(document_with(fixtures::box_cage()), *edit),
                    ErrorCode::kTopologyMismatch, {"vertex count"}));
  Document bad_edit = doc;
  bad_edit.set_edits = {{0, {40}, {}}};
  EXPECT_TRUE(Fails(apply_topology_change(bad_edit, *edit), ErrorCode::kIndexOutOfRange, {"element 40"}));
}

// Attachment overrides pass to each new vertex from its dominant parent; keypose offsets are
// interpolated like the driver offsets.
TEST(ApplyTopologyChange, CarriesAttachmentOverridesAndKeyposeOffsets) {
  const Cage oct = test::octahedron_cage();
  Document doc = document_with(oct);
  doc.attachment.overrides = {{0, 7}, {1, 3}};  // vertex 0 follows node 7, vertex 1 node 3
  KeyposeSet set;
  set.name = "bulge";
  set.drivers.push_back(JointDriver{});
  std::vector<glm::vec3> dense(oct.num_vertices(), glm::vec3(0.f));
  for (size_t v = 0; v < dense.size(); ++v) dense[v] = field(oct.polygons.positions[v]);
  set.keys.push_back(make_key({90.0}, dense));
  doc.keyposes = {set};
  auto edit = subdivide_linear(oct);
  ASSERT_TRUE(edit.ok());
  auto out = apply_topology_change(doc, *edit);
  ASSERT_TRUE(out.ok()) << out.error().message;
  const size_t n = out->cage->num_vertices();
  const auto per_vertex = overrides_per_vertex(out->attachment, n);
  for (size_t v = 0; v < n; ++v) {
    const uint32_t parent = dominant_parent(edit->change, v);
    const int32_t expected = parent == 0 ? 7 : parent == 1 ? 3 : -1;
    EXPECT_EQ(per_vertex[v], expected) << "vertex " << v;
  }
  ASSERT_EQ(out->keyposes.size(), 1u);
  ASSERT_EQ(out->keyposes[0].keys.size(), 1u);
  EXPECT_EQ(out->keyposes[0].keys[0].values, (std::vector<double>{90.0}));
  const auto carried = dense_offsets(out->keyposes[0].keys[0], n);
  for (size_t v = 0; v < n; ++v)  // an affine field is carried exactly
    EXPECT_LT(glm::length(carried[v] - field(out->cage->polygons.positions[v])), 1e-6f) << "vertex " << v;
}

// Simulation weights: mass and stiffness interpolated (an affine field stays exact), the pin from
// the dominant parent; a document without weights keeps none.
TEST(ApplyTopologyChange, CarriesSimulationWeights) {
  const Cage oct = test::octahedron_cage();
  Document doc = document_with(oct);
  for (const auto& p : oct.polygons.positions)
    doc.sim.vertices.push_back({p.y > 0.5f, 1.0f + 0.25f * p.x, 0.5f + 0.2f * p.z});
  auto edit = subdivide_linear(oct);
  ASSERT_TRUE(edit.ok());
  auto out = apply_topology_change(doc, *edit);
  ASSERT_TRUE(out.ok()) << out.error().message;
  const size_t n = out->cage->num_vertices();
  ASSERT_EQ(out->sim.vertices.size(), n);
  for (size_t v = 0; v < n; ++v) {
    const glm::vec3 p = out->cage->polygons.positions[v];
    EXPECT_NEAR(out->sim.vertices[v].mass, 1.0f + 0.25f * p.x, 1e-6f) << "vertex " << v;
    EXPECT_NEAR(out->sim.vertices[v].stiffness, 0.5f + 0.2f * p.z, 1e-6f) << "vertex " << v;
    EXPECT_EQ(out->sim.vertices[v].pinned, doc.sim.vertices[dominant_parent(edit->change, v)].pinned) << "vertex " << v;
  }
  auto plain = apply_topology_change(document_with(oct), *edit);
  ASSERT_TRUE(plain.ok());
  EXPECT_TRUE(plain->sim.vertices.empty());
}

// ------------------------------------------------------------------------------------------ the key test

// The cylinder arm bound to its octagonal cage, with the points under face 17 (a quad in the middle of
// the tube, facing +z) excluding that face's two elements.
struct EditedArm {
  PolyMesh skin = fixtures::cylinder_skin();
  Cage cage = fixtures::cylinder_cage();
  BindParams params;
  V excluded;  // old elements of face 17
  std::vector<SetEdit> edits;
  EditedArm() {
    params.variant = Variant::kBasic;  // stencil ids are elements: exclusions can be read off the table
    for (uint32_t e = 0; e < cage.num_elements(); ++e)
      if (cage.element_face[e] == 17) excluded.push_back(e);
    for (uint32_t p = 0; p < skin.num_vertices(); ++p) {
      const glm::vec3& x = skin.positions[p];
      if (x.x > 1.7f && x.x < 2.3f && x.z > 0.45f) edits.push_back({p, excluded, {}});
    }
  }
};

Binding bind_or_die(const PolyMesh& skin, const Cage& cage, const BindParams& params,
                    std::span<const SetEdit> edits) {
  auto b = bind_skin(skin.positions, cage, cage.polygons.positions, params, edits);
  EXPECT_TRUE(b.ok()) << (b.ok() ? "" : b.error().message);
  return std::move(b).value();
}

std::set<uint32_t> ids_of_point(const Binding& b, uint32_t p) {
  return std::set<uint32_t>(b.ids.begin() + b.offsets[p], b.ids.begin() + b.offsets[p + 1]);
}

// How many of the edited points use one of `elements` in `b`.
size_t points_using(const Binding& b, std::span<const SetEdit> edits, std::span<const uint32_t> elements) {
  size_t n = 0;
  for (const SetEdit& e : edits) {
    auto ids = ids_of_point(b, e.point);
    n += std::any_of(elements.begin(), elements.end(), [&](uint32_t k) { return ids.count(k) > 0; });
  }
  return n;
}

double rest_error(const Binding& b, const PolyMesh& skin, std::span<const glm::vec3> rest) {
  auto d = Deformer::create(b, skin.positions);
  EXPECT_TRUE(d.ok());
  std::vector<glm::vec3> out(skin.num_vertices(), glm::vec3(NAN));
  EXPECT_TRUE(d->deform(rest, out).ok());
  return fixtures::max_distance(out, skin.positions);
}

TEST(EditedArm, TheEditMattersBeforeAnyChange) {
  EditedArm arm;
  ASSERT_EQ(arm.excluded.size(), 2u);
  ASSERT_GE(arm.edits.size(), 10u);
  Binding plain = bind_or_die(arm.skin, arm.cage, arm.params, {});
  Binding edited = bind_or_die(arm.skin, arm.cage, arm.params, arm.edits);
  EXPECT_EQ(points_using(plain, arm.edits, arm.excluded), arm.edits.size());
  EXPECT_EQ(points_using(edited, arm.edits, arm.excluded), 0u);
}

class CarriedEdits : public ::testing::TestWithParam<std::string> {};

TEST_P(CarriedEdits, RestIsReproducedAndExclusionsStillApply) {
  EditedArm arm;
  Document doc = document_with(arm.cage);
  doc.params = arm.params;
  doc.set_edits = arm.edits;
  for (const auto& p : arm.cage.polygons.positions) doc.cage_offsets.push_back(field(p));

  const std::string op = GetParam();
  Result<CageEdit> edit = op == "linear"  ? subdivide_linear(arm.cage)
                          : op == "loop"  ? subdivide_loop(arm.cage)
                          : op == "local" ? refine_faces(arm.cage, V{17, 3, 40})
                                          : subdivide_linear(arm.cage, 2);
  ASSERT_TRUE(edit.ok()) << edit.error().message;
  auto carried = apply_topology_change(doc, *edit);
  ASSERT_TRUE(carried.ok()) << carried.error().message;
  const Cage& cage = *carried->cage;
  ASSERT_GT(cage.num_elements(), arm.cage.num_elements());

  // the excluded elements' children, and the carried edits name exactly them
  const ElementChildren children = element_children(edit->change);
  V excluded;
  for (uint32_t k : arm.excluded)
    excluded.insert(excluded.end(), children.of(k).begin(), children.of(k).end());
  std::sort(excluded.begin(), excluded.end());
  excluded.erase(std::unique(excluded.begin(), excluded.end()), excluded.end());
  ASSERT_GE(excluded.size(), 2u);
  ASSERT_EQ(carried->set_edits.size(), arm.edits.size());
  for (size_t i = 0; i < arm.edits.size(); ++i) {
    EXPECT_EQ(carried->set_edits[i].point, arm.edits[i].point);
    EXPECT_EQ(carried->set_edits[i].exclude, excluded);
  }
  if (op != "loop") {
    // the shape is kept: the children are exactly the new elements lying on face 17
    const auto& x = cage.polygons.positions;
    for (uint32_t e = 0; e < cage.num_elements(); ++e) {
      const Tri& t = cage.elements[e];
      glm::dvec3 c = (glm::dvec3(x[t[0]]) + glm::dvec3(x[t[1]]) + glm::dvec3(x[t[2]])) / 3.0;
      const double angle = std::atan2(c.z, c.y) * 180.0 / M_PI;
      const bool on_face_17 = c.x > 1.54 && c.x < 2.46 && angle > 67.5 && angle < 112.5;
      EXPECT_EQ(on_face_17, std::binary_search(excluded.begin(), excluded.end(), e)) << "element " << e;
    }
  }

  // rebind with the carried edits: the skin is reproduced at rest, and no edited point uses a child
  Binding edited = bind_or_die(arm.skin, cage, carried->params, carried->set_edits);
  const double diag = bounding_box(arm.skin.positions).diagonal();
  EXPECT_LE(rest_error(edited, arm.skin, cage.polygons.positions), 1e-5 * diag);
  EXPECT_EQ(points_using(edited, arm.edits, excluded), 0u);
  for (const SetEdit& e : arm.edits)
    EXPECT_FALSE(ids_of_point(edited, e.point).empty()) << "point " << e.point;
  // without the edits the same points do use them: the carried edit makes the difference
  Binding plain = bind_or_die(arm.skin, cage, carried->params, {});
  EXPECT_GE(points_using(plain, arm.edits, excluded), arm.edits.size() * 9 / 10);
  EXPECT_LE(rest_error(plain, arm.skin, cage.polygons.positions), 1e-5 * diag);
  // and the default (extended) variant reproduces the rest too
  BindParams extended = carried->params;
  extended.variant = Variant::kExtended;
  EXPECT_LE(rest_error(bind_or_die(arm.skin, cage, extended, carried->set_edits), arm.skin,
                       cage.polygons.positions),
            1e-5 * diag);

  // the offsets follow: an affine field of the rest cage stays that field
  ASSERT_EQ(carried->cage_offsets.size(), cage.num_vertices());
  for (size_t v = 0; v < cage.num_vertices(); ++v)
    EXPECT_LT(glm::length(carried->cage_offsets[v] - field(cage.polygons.positions[v])), 1e-5f) << v;
}

INSTANTIATE_TEST_SUITE_P(Subdivisions, CarriedEdits, ::testing::Values("linear", "loop", "local", "linear2"));

}  // namespace
}  // namespace cagewrap
