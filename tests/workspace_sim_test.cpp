// The Simulation window's edits driven in-process on the demo character (app/workspace/workspace_sim.cpp,
// issue 20): on and off, parameters, weights of the selected cage vertices blended by the soft
// selection, colliders; each one undo step, and every refusal named with the document kept.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tests/workspace_fixtures.h"

namespace cagewrap::app {
namespace {

using WorkspaceSimTest = DemoWorkspaceTest;

TEST_F(WorkspaceSimTest, OnOffAndParametersAreUndoSteps) {
  const bool was = doc().sim.enabled;
  const size_t steps = undo_steps();
  ASSERT_TRUE(ws.run(was ? "sim off" : "sim on"));
  EXPECT_EQ(doc().sim.enabled, !was);
  EXPECT_EQ(undo_steps(), steps + 1);
  ASSERT_TRUE(ws.run("sim_param gravity -3.5"));
  EXPECT_DOUBLE_EQ(doc().sim.params.gravity.y, -3.5);
  ASSERT_TRUE(ws.run("sim_param substeps 7"));
  EXPECT_EQ(doc().sim.params.substeps, 7);
  EXPECT_EQ(undo_steps(), steps + 3);
  ws.run("undo");
  ws.run("undo");
  ws.run("undo");
  EXPECT_EQ(doc().sim.enabled, was);
  EXPECT_NE(doc().sim.params.gravity.y, -3.5);
  EXPECT_TRUE(errors.empty()) << errors.front();
}

TEST_F(WorkspaceSimTest, WeightsFollowTheSelectionAndItsSoftShares) {
  ws.run("mode cage_vertices");
  ws.run("sim_weights free 2 0.1");  // nothing selected
  EXPECT_TRUE(logged("select cage vertices first (F5)"));
  ws.run("select_cage_vertex 40");
  ASSERT_TRUE(ws.run("sim_weights free 2 0.1"));
  const size_t nv = doc().cage->num_vertices();
  ASSERT_EQ(doc().sim.vertices.size(), nv);
  EXPECT_FALSE(doc().sim.vertices[40].pinned);
  EXPECT_FLOAT_EQ(doc().sim.vertices[40].mass, 2.0f);
  EXPECT_FLOAT_EQ(doc().sim.vertices[40].stiffness, 0.1f);
  size_t freed = 0;
  for (const SimVertex& v : doc().sim.vertices) freed += !v.pinned;
  EXPECT_EQ(freed, 1u) << "only the selected vertex without soft selection";

  // with soft selection the neighbours get a share: a free vertex's weights move toward the new ones by
  // its share (all free at mass 1 first; a pinned vertex freed starts from the new weights)
  ws.run("select all");
  ASSERT_TRUE(ws.run("sim_weights free 1 0.5"));
  ws.run("select_cage_vertex 40");
  ws.view.soft.enabled = true;
  ws.view.soft.radius = 0.15;
  ASSERT_TRUE(ws.run("sim_weights free 4 0.0"));
  EXPECT_FLOAT_EQ(doc().sim.vertices[40].mass, 4.0f);
  size_t between = 0, untouched = 0;
  for (size_t v = 0; v < nv; ++v) {
    const float m = doc().sim.vertices[v].mass;
    EXPECT_GE(m, 1.0f);
    EXPECT_LE(m, 4.0f);
    between += v != 40 && m > 1.0f && m < 4.0f;
    untouched += m == 1.0f;
  }
  EXPECT_GT(between, 0u) << "the soft selection's neighbours move part-way";
  EXPECT_GT(untouched, nv / 2) << "vertices beyond the radius keep their weights";

  ws.view.soft.enabled = false;
  ASSERT_TRUE(ws.run("sim_weights pin"));
  EXPECT_TRUE(doc().sim.vertices[40].pinned);
  ws.run("undo");
  EXPECT_FALSE(doc().sim.vertices[40].pinned);
}

TEST_F(WorkspaceSimTest, CollidersAndRefusalsAreNamed) {
  const size_t had = doc().sim.colliders.size();
  ASSERT_TRUE(ws.run("sim_collider sphere 0 1 0.4 0 0 0 0.15"));
  ASSERT_EQ(doc().sim.colliders.size(), had + 1);
  EXPECT_EQ(doc().sim.colliders.back().kind, ColliderKind::kSphere);
  EXPECT_DOUBLE_EQ(doc().sim.colliders.back().radius, 0.15);

  const uint64_t revision = doc().revision;
  ws.run("sim_collider cone 0 0 0 0 1 0 1");
  EXPECT_TRUE(logged("unknown collider kind 'cone'"));
  ws.run("sim_remove_collider 99");
  EXPECT_TRUE(logged("there is no collider 99"));
  ws.run("sim_param wind 3");
  EXPECT_TRUE(logged("unknown simulation parameter 'wind'"));
  ws.run("sim maybe");
  EXPECT_TRUE(logged("sim on|off"));
  EXPECT_TRUE(errors.empty());
  ws.run("sim_param substeps 0");  // checked before it enters the document
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_NE(errors[0].find("substeps 0 must be 1..100"), std::string::npos) << errors[0];
  EXPECT_EQ(doc().revision, revision);

  ASSERT_TRUE(ws.run("sim_remove_collider " + std::to_string(had)));
  EXPECT_EQ(doc().sim.colliders.size(), had);
}

}  // namespace
}  // namespace cagewrap::app
