// Tests for app/workspace/history.h: undo/redo order and labels, one drag = one step, the dirty flag across
// undo, redo, save and branching, and the memory cap (shared data counted once; oldest steps go).
#include <gtest/gtest.h>

#include <memory>

#include "app/workspace/history.h"
#include "tests/fixtures.h"
#include "tests/patch_fixtures.h"

namespace cagewrap {
namespace {

// A document without files: a small character and the 26-vertex box cage.
Document make_doc(int cage_subdivisions = 2) {
  auto character = std::make_shared<Character>();
  character->primitives.emplace_back();
  character->primitives[0].positions.assign(1000, glm::vec3(0.5f));
  Document d;
  d.character = character;
  d.character_path = "hero.glb";
  d.character_hash = "fnv1a64:0123456789abcdef";
  d.cage = std::make_shared<const Cage>(fixtures::box_cage(1.0, cage_subdivisions));
  d.revision = next_revision();
  return d;
}

Document moved(const Document& d, float dx) {
  std::vector<glm::vec3> p(d.cage_positions().begin(), d.cage_positions().end());
  for (auto& x : p) x.x += dx;
  return with_cage_positions(d, p);
}

Document with_epsilon(const Document& d, double epsilon) {
  BindParams p = d.params;
  p.epsilon = epsilon;
  return with_params(d, p);
}

TEST(History, UndoRedoWalkTheSteps) {
  Document d0 = make_doc();
  History h(d0);
  EXPECT_FALSE(h.can_undo());
  EXPECT_FALSE(h.can_redo());
  EXPECT_EQ(h.undo_label(), "Undo");
  EXPECT_EQ(h.redo_label(), "Redo");
  Document d1 = moved(d0, 1.0f);
  Document d2 = with_epsilon(d1, 0.3);
  EXPECT_TRUE(h.push("Move vertices", d1));
  EXPECT_TRUE(h.push("Change epsilon", d2));
  EXPECT_EQ(h.undo_steps(), 2u);
  EXPECT_EQ(h.undo_label(), "Undo Change epsilon");

  EXPECT_EQ(h.undo().revision, d1.revision);
  EXPECT_EQ(h.undo_label(), "Undo Move vertices");
  EXPECT_EQ(h.redo_label(), "Redo Change epsilon");
  EXPECT_EQ(h.undo().revision, d0.revision);
  EXPECT_FALSE(h.can_undo());
  EXPECT_EQ(h.undo().revision, d0.revision);  // no-op at the start
  EXPECT_EQ(h.redo_steps(), 2u);
  EXPECT_EQ(h.redo_label(), "Redo Move vertices");
  EXPECT_EQ(h.redo().revision, d1.revision);
  EXPECT_EQ(h.redo().revision, d2.revision);
  EXPECT_FALSE(h.can_redo());
  EXPECT_EQ(h.redo().revision, d2.revision);  // no-op at the end
  // the snapshots hold the content they were pushed with
  EXPECT_EQ(h.current().params.epsilon, 0.3);
  EXPECT_TRUE(same_content(h.undo(), d1));
  EXPECT_EQ(h.current().cage_positions()[0].x, d1.cage_positions()[0].x);
}

TEST(History, PushAfterUndoDropsRedo) {
  Document d0 = make_doc();
  History h(d0);
  Document d1 = moved(d0, 1.0f);
  h.push("Move vertices", d1);
  h.push("Move vertices", moved(d1, 1.0f));
  h.undo();
  h.undo();
  Document other = with_epsilon(d0, 0.5);
  h.push("Change epsilon", other);
  EXPECT_FALSE(h.can_redo());
  EXPECT_EQ(h.undo_steps(), 1u);
  EXPECT_EQ(h.undo().revision, d0.revision);
  EXPECT_EQ(h.redo().revision, other.revision);
}

TEST(History, PushingTheCurrentRevisionRecordsNothing) {
  Document d0 = make_doc();
  History h(d0);
  EXPECT_FALSE(h.push("Nothing", d0));
  EXPECT_FALSE(h.can_undo());
}

TEST(History, OneDragIsOneStep) {
  Document doc = make_doc();
  const Document before = doc;
  History h(doc);
  h.begin(doc);  // IsItemActivated
  EXPECT_TRUE(h.dragging());
  for (int frame = 0; frame < 30; ++frame) doc = moved(doc, 0.01f);  // the live document
  EXPECT_EQ(h.undo_steps(), 0u);  // nothing recorded while dragging
  EXPECT_TRUE(h.dirty(doc));
  EXPECT_FALSE(h.dirty());
  EXPECT_TRUE(h.commit("Move vertices", doc));  // IsItemDeactivatedAfterEdit
  EXPECT_FALSE(h.dragging());
  EXPECT_EQ(h.undo_steps(), 1u);
  EXPECT_EQ(h.undo_label(), "Undo Move vertices");
  EXPECT_EQ(h.current().revision, doc.revision);
  EXPECT_EQ(h.undo().revision, before.revision);
}

TEST(History, DragWithoutChangeOrWithoutBeginRecordsNothing) {
  Document doc = make_doc();
  History h(doc);
  h.begin(doc);
  EXPECT_FALSE(h.commit("Move vertices", doc));
  EXPECT_FALSE(h.commit("Move vertices", moved(doc, 1.0f)));  // no begin()
  EXPECT_EQ(h.undo_steps(), 0u);
}

TEST(History, CancelRestoresTheStateBeforeTheDrag) {
  Document doc = make_doc();
  const uint64_t before = doc.revision;
  History h(doc);
  h.begin(doc);
  doc = moved(doc, 2.0f);
  doc = h.cancel();
  EXPECT_EQ(doc.revision, before);
  EXPECT_FALSE(h.dragging());
  EXPECT_FALSE(h.commit("Move vertices", moved(doc, 1.0f)));  // the drag is closed
  EXPECT_EQ(h.undo_steps(), 0u);
  EXPECT_EQ(h.cancel().revision, before);  // without a drag: the current state
}

TEST(History, UndoDuringADragClosesIt) {
  Document d0 = make_doc();
  History h(d0);
  h.push("Move vertices", moved(d0, 1.0f));
  h.begin(h.current());
  h.undo();
  EXPECT_FALSE(h.dragging());
}

TEST(History, DirtyFollowsTheSavePointAcrossUndoAndRedo) {
  Document d0 = make_doc();
  History h(d0);
  EXPECT_FALSE(h.dirty());
  h.push("Move vertices", moved(d0, 1.0f));
  EXPECT_TRUE(h.dirty());
  h.undo();
  EXPECT_FALSE(h.dirty());  // back to the saved state
  h.redo();
  EXPECT_TRUE(h.dirty());
  h.push("Change epsilon", with_epsilon(h.current(), 0.4));
  h.mark_saved("/projects/hero.cagewrap");
  EXPECT_FALSE(h.dirty());
  h.undo();
  EXPECT_TRUE(h.dirty());
  h.undo();
  EXPECT_TRUE(h.dirty());
  h.redo();
  h.redo();
  EXPECT_FALSE(h.dirty());

  // a new branch from before the save point: the saved state is gone for good
  h.undo();
  h.push("Change epsilon", with_epsilon(h.current(), 0.6));
  EXPECT_TRUE(h.dirty());
  while (h.can_undo()) {
    h.undo();
    EXPECT_TRUE(h.dirty());
  }
  while (h.can_redo()) {
    h.redo();
    EXPECT_TRUE(h.dirty());
  }
}

TEST(History, MarkSavedGivesEverySnapshotTheProjectPath) {
  Document d0 = make_doc();
  History h(d0);
  h.push("Move vertices", moved(d0, 1.0f));
  const uint64_t revision = h.current().revision;
  h.mark_saved("/p/hero.cagewrap");
  EXPECT_EQ(h.current().project_path, "/p/hero.cagewrap");
  EXPECT_EQ(h.current().revision, revision);  // a save is not an edit
  EXPECT_EQ(h.undo().project_path, "/p/hero.cagewrap");
  EXPECT_TRUE(h.dirty());
}

TEST(History, SharedDataIsCountedOnce) {
  Document d0 = make_doc();
  History h(d0);
  const size_t base = h.memory_bytes();
  EXPECT_GE(base, estimated_bytes(*d0.character) + estimated_bytes(*d0.cage));
  EXPECT_LT(base, estimated_bytes(*d0.character) + estimated_bytes(*d0.cage) + estimated_own_bytes(d0) + 1);
  // 100 parameter edits share the character and the cage: each costs only its own bytes
  Document d = d0;
  for (int i = 0; i < 100; ++i) {
    d = with_epsilon(d, 0.01 * (i + 1));
    h.push("Change epsilon", d);
  }
  EXPECT_EQ(h.memory_bytes(), base + 100 * estimated_own_bytes(d0));
  // a cage edit adds one cage
  h.push("Move vertices", moved(d, 1.0f));
  EXPECT_EQ(h.memory_bytes(), base + 101 * estimated_own_bytes(d0) + estimated_bytes(*d0.cage));
  // undoing and pushing a new branch releases what the dropped redo step held
  h.undo();
  h.push("Change epsilon", with_epsilon(h.current(), 0.9));
  EXPECT_EQ(h.memory_bytes(), base + 101 * estimated_own_bytes(d0));
}

TEST(History, MemoryCapEvictsTheOldestSteps) {
  Document d0 = make_doc(8);  // 6 * 64 quads: a cage of several kilobytes
  const size_t cage_bytes = estimated_bytes(*d0.cage);
  const size_t own = estimated_own_bytes(d0);
  const size_t base = estimated_bytes(*d0.character) + cage_bytes + own;
  const size_t cap = base + 3 * (cage_bytes + own);  // room for the first state and three more cages
  History h(d0, cap);
  std::weak_ptr<const Cage> first_cage = d0.cage;
  std::vector<uint64_t> revisions = {d0.revision};
  Document d = d0;
  d0 = Document{};  // the history holds the only reference to the first cage now
  for (int i = 0; i < 10; ++i) {
    d = moved(d, 1.0f);
    revisions.push_back(d.revision);
    h.push("Move vertices", d);
    EXPECT_LE(h.memory_bytes(), cap);
  }
  EXPECT_EQ(h.undo_steps(), 3u);
  EXPECT_TRUE(first_cage.expired());  // evicted snapshots release their cage
  EXPECT_EQ(h.current().revision, revisions.back());
  while (h.can_undo()) h.undo();
  EXPECT_EQ(h.current().revision, revisions[revisions.size() - 4]);  // the oldest kept state
  EXPECT_TRUE(h.dirty());  // the save point (the first state) was evicted: never clean again
  while (h.can_redo()) h.redo();

  // the current state always stays, even under a cap it does not fit
  h.set_memory_cap(0);
  EXPECT_EQ(h.undo_steps(), 0u);
  EXPECT_EQ(h.current().revision, revisions.back());
  EXPECT_EQ(h.memory_bytes(), estimated_bytes(*d.character) + cage_bytes + own);
}

// The parametric driver is document content: replacing it is a step that undo and redo restore,
// a drag of a control point is one step, and an equal driver is the same content.
TEST(History, ParametricDriverStepsUndoAndRedo) {
  Document d0 = make_doc();
  History h(d0);
  PatchDriver fitted;
  fitted.rest = test::wavy_surface(5, 6);
  fitted.posed = fitted.rest;
  Document d1 = with_patch_driver(d0, std::make_shared<const PatchDriver>(fitted));
  EXPECT_NE(d1.revision, d0.revision);
  EXPECT_EQ(d0.patch_driver, nullptr);  // copy on write: the old document keeps none
  EXPECT_FALSE(same_content(d0, d1));
  EXPECT_GT(estimated_own_bytes(d1), estimated_own_bytes(d0) + 2 * 30 * sizeof(glm::dvec3) - 1);
  ASSERT_TRUE(h.push("Fit parametric driver", d1));

  // a drag of control point 8: many live states, one step
  h.begin(h.current());
  Document live = h.current();
  for (int i = 1; i <= 5; ++i) {
    PatchDriver d = *live.patch_driver;
    std::vector<glm::dvec3> p = d.posed.control_points();
    p[8] += glm::dvec3(0.0, 0.1, 0.0);
    d.posed.set_control_points(p);
    live = with_patch_driver(live, std::make_shared<const PatchDriver>(d));
  }
  ASSERT_TRUE(h.commit("Move control point 8", live));
  PatchDriver dense = *live.patch_driver;
  dense.density = 6;
  ASSERT_TRUE(h.push("Driver density 6", with_patch_driver(live, std::make_shared<const PatchDriver>(dense))));
  EXPECT_EQ(h.undo_steps(), 3u);

  EXPECT_EQ(h.undo().patch_driver->density, 2u);
  const glm::dvec3 moved = h.current().patch_driver->posed.control_points()[8];
  EXPECT_NEAR(moved.y - fitted.posed.control_points()[8].y, 0.5, 1e-12);
  EXPECT_EQ(h.undo_label(), "Undo Move control point 8");
  EXPECT_EQ(*h.undo().patch_driver, fitted);  // before the drag
  EXPECT_EQ(h.undo().patch_driver, nullptr);  // before the fit
  EXPECT_TRUE(same_content(h.current(), d0));
  EXPECT_EQ(*h.redo().patch_driver, fitted);
  EXPECT_EQ(h.redo().patch_driver->posed.control_points()[8], moved);
  EXPECT_EQ(h.redo().patch_driver->density, 6u);
  // an equal driver built anew is the same content (compared by value, not by address)
  Document again = with_patch_driver(h.current(), std::make_shared<const PatchDriver>(*h.current().patch_driver));
  EXPECT_TRUE(same_content(again, h.current()));
}

}  // namespace
}  // namespace cagewrap
