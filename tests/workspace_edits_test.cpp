// The Cage menu's edits and the Sets window's edits driven in-process on the demo character
// (app/workspace/workspace_cage.cpp, workspace_sets.cpp; issue 20): topology edits are one undo step
// and carry sculpted offsets, an imported cage replaces the old one's vertex data, set edits on a
// selection, a limb's faces and a brush stroke re-register the points at once, and every refusal is
// named with the document kept. The windows only draw these.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "tests/workspace_fixtures.h"
#include "core/geometry/mesh.h"

namespace cagewrap::app {
namespace {

class WorkspaceEditsTest : public DemoWorkspaceTest {
 protected:
  void SetUp() override {
    DemoWorkspaceTest::SetUp();
    ws.run("clip rest");
    forearm_l = node("forearm.L");
    ASSERT_GE(forearm_l, 0);
  }
  // Waits for the background bind (an extended binding: with contributing sets).
  void finish_bind() {
    DemoWorkspaceTest::finish_bind();
    ASSERT_TRUE(ws.scene()->binding->has_sets());
  }
  std::vector<uint32_t> set_of(uint32_t point) const {
    const auto members = ws.scene()->binding->sets().of(point);
    return {members.begin(), members.end()};
  }
  int forearm_l = -1;
};

// A local topology edit (refine one face) on a bound cage keeps the bound h and registers again only
// the points within reach of the changed faces (issue 24); the binding equals a fresh bind of the
// refined cage. A whole-cage subdivision lets h follow and binds everything.
TEST_F(WorkspaceEditsTest, ALocalTopologyEditRegistersOnlyThePointsItReaches) {
  finish_bind();
  Scene& s = *ws.scene();
  const double h = s.binding->h;
  ASSERT_LE(doc().params.scale, 0.0) << "the demo binds with h from the mean edge length";
  ws.run("mode cage_faces");
  ws.run("select_cage_face 5");
  ASSERT_TRUE(ws.run("cage_op refine"));
  EXPECT_DOUBLE_EQ(doc().params.scale, h) << "h is kept so that the edit stays local";
  EXPECT_TRUE(logged("scale h fixed to the bound"));
  std::vector<std::string> messages;
  while (s.job) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    if (auto m = s.poll_bind()) messages.push_back(*m);
  }
  ASSERT_EQ(messages.size(), 1u);
  EXPECT_NE(messages[0].find("cage topology edit"), std::string::npos) << messages[0];
  const std::string of = " of " + std::to_string(s.skin_rest.size()) + " skin points registered again";
  ASSERT_NE(messages[0].find(of), std::string::npos) << messages[0];
  const size_t again = std::stoul(messages[0].substr(messages[0].rfind(';') + 2));
  EXPECT_GT(again, 0u);
  EXPECT_LT(again, s.skin_rest.size() / 4) << "a refined face reaches a small part of the skin";
  auto fresh = bind_document(doc(), s.skin_rest, s.attachment ? &*s.attachment : nullptr);
  ASSERT_TRUE(fresh.ok());
  EXPECT_EQ(registration_difference(*s.binding, *fresh), "");
  ASSERT_TRUE(ws.run("cage_op linear"));  // whole-cage: h follows the new mean edge length
  EXPECT_DOUBLE_EQ(doc().params.scale, h) << "already fixed by the refinement, it stays";
}

// Cage > Refine selected faces and Subdivide (linear), each one undo step; a sculpted offset follows
// subdivision (the vertex keeps it, the midpoints of its edges get half).
TEST_F(WorkspaceEditsTest, TopologyEditsAreOneUndoStepAndCarryOffsets) {
  const PolyMesh cage = doc().cage->polygons;
  ASSERT_TRUE(cage.all_triangles());
  const size_t f = cage.num_faces(), steps = undo_steps();
  ws.run("mode cage_faces");
  ws.run("select_cage_face 5");
  ASSERT_TRUE(ws.run("cage_op refine"));
  EXPECT_EQ(doc().cage->polygons.num_faces(), f + 3 + 3);  // red-green: the face becomes 4, each of its 3 neighbours 2
  EXPECT_EQ(undo_steps(), steps + 1);
  EXPECT_TRUE(logged("Refine faces: " + std::to_string(f) + " -> " + std::to_string(f + 6) + " faces"));
  ws.run("undo");
  EXPECT_EQ(doc().cage->polygons.num_faces(), f);

  ws.run("mode cage_vertices");
  ws.run("select_cage_vertex 500");
  ws.run("move 0 0.1 0");
  ASSERT_TRUE(ws.run("cage_op linear"));
  EXPECT_EQ(doc().cage->polygons.num_faces(), 4 * f);
  size_t full = 0, half = 0, other = 0;
  for (const glm::vec3& o : doc().cage_offsets) {
    if (std::abs(glm::length(o) - 0.1f) < 1e-5f) ++full;
    else if (std::abs(glm::length(o) - 0.05f) < 1e-5f) ++half;
    else if (glm::length(o) != 0.0f) ++other;
  }
  size_t degree = 0;  // edges at vertex 500
  for (auto [a, b] : unique_edges(cage))
    if (a == 500 || b == 500) ++degree;
  EXPECT_EQ(full, 1u);
  EXPECT_EQ(half, degree);
  EXPECT_EQ(other, 0u);
  // the selection's ids are still the cage's (vertex ids below the old count stay in subdivision)
  EXPECT_TRUE(ws.view.selection.cage_vertices.contains(500));
  ws.run("undo");
  EXPECT_EQ(doc().cage->polygons.num_faces(), f);
  EXPECT_TRUE(errors.empty()) << errors.front();
}

TEST_F(WorkspaceEditsTest, MergeAndFlipActOnTheSelectionAndUndoClipsIt) {
  const size_t v = doc().cage->num_vertices();
  ws.run("mode cage_vertices");
  ws.run("select_cage_vertex 10");
  ws.run("select_cage_vertex 11 add");
  ws.run("select_cage_vertex " + std::to_string(v - 1) + " add");
  ASSERT_TRUE(ws.run("cage_op merge"));
  ASSERT_TRUE(errors.empty()) << errors.front();
  // merged into one vertex at the lowest id; ids close up, so the last id is past the cage now
  EXPECT_EQ(doc().cage->num_vertices(), v - 2);
  for (uint32_t i : ws.view.selection.cage_vertices) EXPECT_LT(i, v - 2);
  ws.run("undo");
  EXPECT_EQ(doc().cage->num_vertices(), v);

  // flip turns the selected face's normal around and is one undo step; flip again restores it
  const auto corners = [this](uint32_t face) {
    const auto c = doc().cage->polygons.face(face);
    return std::vector<uint32_t>(c.begin(), c.end());
  };
  const std::vector<uint32_t> before = corners(7);
  ws.run("mode cage_faces");
  ws.run("select_cage_face 7");
  ASSERT_TRUE(ws.run("cage_op flip"));
  const std::vector<uint32_t> flipped = corners(7);
  EXPECT_EQ(flipped.front(), before.front());
  EXPECT_TRUE(std::equal(flipped.begin() + 1, flipped.end(), before.rbegin()));
  ws.run("undo");
  EXPECT_EQ(corners(7), before);
}

TEST_F(WorkspaceEditsTest, RefusedCageEditsAreNamedAndKeepTheDocument) {
  const uint64_t revision = doc().revision;
  const size_t steps = undo_steps();
  ws.run("cage_op shear");
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_NE(errors[0].find("unknown cage operation 'shear'"), std::string::npos) << errors[0];
  EXPECT_NE(errors[0].find("triangulate"), std::string::npos) << "the message lists the operations: " << errors[0];
  ws.run("mode cage_faces");
  ws.run("select none");
  ws.run("cage_op refine");  // nothing selected
  ASSERT_EQ(errors.size(), 2u);
  EXPECT_NE(errors[1].find("Refine faces"), std::string::npos) << errors[1];
  ws.run("cage_op weld 0");
  ASSERT_EQ(errors.size(), 3u);
  EXPECT_NE(errors[2].find("Weld vertices"), std::string::npos) << errors[2];
  const std::string missing = (std::filesystem::temp_directory_path() / "no_such_cage_here.obj").string();
  ws.run("import_cage " + missing);
  ASSERT_EQ(errors.size(), 4u);
  EXPECT_NE(errors[3].find("no_such_cage_here.obj"), std::string::npos) << errors[3];
  EXPECT_EQ(doc().revision, revision);
  EXPECT_EQ(undo_steps(), steps);
}

// An imported cage replaces the old one: its sculpted offsets and set edits named the old vertices
// and elements, so they go, in one undo step that undo takes back whole.
TEST_F(WorkspaceEditsTest, AnImportedCageDropsTheOldCagesVertexData) {
  ws.run("select_cage_vertex 12");
  ws.run("move 0 0.05 0");
  ASSERT_FALSE(doc().cage_offsets.empty());
  const auto old_cage = doc().cage;
  const size_t steps = undo_steps();
  const std::string box = std::string(CAGEWRAP_SOURCE_DIR) + "/assets/demo_cage.obj";
  ASSERT_TRUE(ws.run("import_cage " + box));
  ASSERT_TRUE(errors.empty()) << errors.front();
  EXPECT_NE(doc().cage, old_cage);
  EXPECT_EQ(undo_steps(), steps + 1);
  EXPECT_TRUE(std::all_of(doc().cage_offsets.begin(), doc().cage_offsets.end(), [](const glm::vec3& o) { return o == glm::vec3(0.f); }));
  EXPECT_TRUE(ws.view.selection.cage_vertices.empty());
  EXPECT_TRUE(logged("imported cage " + box));
  ws.run("undo");
  EXPECT_EQ(doc().cage, old_cage);
  EXPECT_GT(glm::length(doc().cage_offsets.at(12)), 0.04f);
}

// Cage > Automatic cage builds in the background; when it ends the cage is the document's, one undo
// step, with its report kept and logged. A second build while one runs is refused; Cancel leaves the
// document as it was.
TEST_F(WorkspaceEditsTest, AnAutomaticCageIsBuiltInTheBackgroundAsOneUndoStep) {
  const auto demo_cage = doc().cage;
  ASSERT_TRUE(ws.run("auto_cage 600"));
  ASSERT_TRUE(ws.building_cage());
  ws.run("auto_cage 800");
  EXPECT_TRUE(logged("an automatic cage is being built already"));
  ws.run("auto_cage_cancel");
  poll_while([this] { return ws.building_cage(); });
  EXPECT_TRUE(logged("automatic cage cancelled"));
  EXPECT_EQ(doc().cage, demo_cage);
  EXPECT_FALSE(ws.auto_cage_state().report.has_value());

  const size_t steps = undo_steps();
  ASSERT_TRUE(ws.run("auto_cage 600"));
  poll_while([this] { return ws.building_cage(); });
  ASSERT_TRUE(errors.empty()) << errors.front();
  EXPECT_EQ(undo_steps(), steps + 1);
  ASSERT_NE(doc().cage, demo_cage);
  EXPECT_EQ(doc().cage, ws.auto_cage_state().cage);
  const size_t faces = doc().cage->polygons.num_faces();
  EXPECT_GT(faces, 300u);
  EXPECT_LE(faces, 600u);
  ASSERT_TRUE(ws.auto_cage_state().report.has_value());
  EXPECT_EQ(ws.auto_cage_state().report->faces, faces);
  EXPECT_EQ(ws.auto_cage_state().builds, 1u);
  EXPECT_TRUE(logged("automatic cage: " + std::to_string(faces) + " faces"));
  EXPECT_TRUE(logged("cage quality"));
  ws.run("undo");
  EXPECT_EQ(doc().cage, demo_cage);
}

// "Select limb" picks the forearm's faces; "only these faces" on one point makes them the only
// elements that drive it, at once (re-registered in place), and undo takes the edit back.
TEST_F(WorkspaceEditsTest, OnlyTheLimbsFacesDriveThePointAtOnce) {
  finish_bind();
  ws.run("mode joints");
  ws.run("select_joint " + std::to_string(forearm_l));
  ASSERT_TRUE(ws.run("select_limb_faces"));
  const IndexSet limb = ws.view.selection.cage_faces;
  ASSERT_GT(limb.size(), 5u);
  ws.run("mode skin_vertices");
  ws.run("select_skin_vertex 20000");
  const size_t steps = undo_steps();
  ASSERT_TRUE(ws.run("set_edit only"));
  ASSERT_TRUE(errors.empty()) << errors.front();
  EXPECT_EQ(undo_steps(), steps + 1);
  ASSERT_EQ(doc().set_edits.size(), 1u);
  const SetEdit& e = doc().set_edits[0];
  EXPECT_EQ(e.point, 20000u);
  EXPECT_TRUE(e.only);
  EXPECT_GT(e.include.size(), 10u) << "the forearm's faces hold many elements";
  EXPECT_FALSE(ws.scene()->job) << "a set edit re-registers the point in place, no rebind";
  const std::vector<uint32_t> now = set_of(20000);
  ASSERT_FALSE(now.empty());
  for (uint32_t el : now) {
    EXPECT_TRUE(limb.contains(doc().cage->element_face[el])) << "element " << el << " is not on the forearm";
  }
  ws.run("undo");
  EXPECT_TRUE(doc().set_edits.empty());
}

// #17: removing the faces that drive a point from its contributing set removes their elements from
// the binding at once.
TEST_F(WorkspaceEditsTest, RemovingAPointsOwnFacesRemovesThemFromItsSet) {
  finish_bind();
  ws.run("mode skin_vertices");
  ws.run("select_skin_vertex 13849");
  const std::vector<uint32_t> before = set_of(13849);
  ASSERT_GE(before.size(), 2u);
  ASSERT_TRUE(ws.run("select_set_faces"));
  ASSERT_FALSE(ws.view.selection.cage_faces.empty());
  ASSERT_TRUE(ws.run("set_edit remove"));
  ASSERT_TRUE(errors.empty()) << errors.front();
  if (ws.scene()->job) finish_bind();
  for (uint32_t e : set_of(13849))
    EXPECT_EQ(std::find(before.begin(), before.end(), e), before.end()) << "element " << e << " was removed but still drives the point";
  ASSERT_EQ(doc().set_edits.size(), 1u);
  EXPECT_GE(doc().set_edits[0].exclude.size(), before.size());
}

// A brush stroke removes the selected faces from the sets of the points within its radius along the
// skin: one undo step for the stroke; with mirroring the mirror points get the mirror faces' edit.
TEST_F(WorkspaceEditsTest, ABrushStrokeIsOneUndoStepAndMirrors) {
  finish_bind();
  ws.run("mode cage_faces");
  ws.run("select_cage_face 600");
  ws.run("select grow");
  ws.run("mode skin_vertices");
  const size_t steps = undo_steps();
  ASSERT_TRUE(ws.run("paint_at_skin_vertex 20000 0.15"));
  ASSERT_TRUE(errors.empty()) << errors.front();
  EXPECT_EQ(undo_steps(), steps + 1);
  EXPECT_FALSE(ws.set_stroking());
  const size_t painted = doc().set_edits.size();
  EXPECT_GT(painted, 50u) << "the brush covers many points";
  for (const auto& e : doc().set_edits) {
    EXPECT_FALSE(e.exclude.empty());
    EXPECT_TRUE(e.include.empty());
  }
  ws.run("undo");
  EXPECT_TRUE(doc().set_edits.empty()) << "one undo takes the stroke back";

  ws.view.sets.mirror = true;
  ASSERT_TRUE(ws.run("paint_at_skin_vertex 20000 0.15"));
  // the mirror images of the points are edited too (the demo is symmetric across x = 0)
  EXPECT_GE(doc().set_edits.size(), 2 * painted - painted / 10) << "mirrored stroke: about twice the points";
  const auto& rest = ws.scene()->skin_rest;
  size_t left = 0, right = 0;
  for (const auto& e : doc().set_edits) (rest[e.point].x > 0 ? right : left) += 1;
  EXPECT_GT(std::min(left, right), painted / 2) << left << " on one side, " << right << " on the other";
}

TEST_F(WorkspaceEditsTest, RefusedSetEditsAreNamedAndKeepTheDocument) {
  finish_bind();
  const uint64_t revision = doc().revision;
  ws.run("mode skin_vertices");
  ws.run("select_skin_vertex 100");
  ws.run("set_edit remove");  // no faces selected
  EXPECT_TRUE(logged("select the cage faces to remove first (F6)"));
  ws.run("select_skin_vertex 100");
  ws.run("set_edit sideways");
  EXPECT_TRUE(logged("unknown set edit mode 'sideways'"));
  ws.run("paint_at_skin_vertex 99999999");
  EXPECT_TRUE(logged("no skin vertex 99999999"));
  ws.run("select none");
  ws.run("set_edit reset");
  EXPECT_TRUE(logged("select the skin vertices to edit first (F7)"));
  EXPECT_EQ(doc().revision, revision);
  EXPECT_TRUE(doc().set_edits.empty());
}

}  // namespace
}  // namespace cagewrap::app
