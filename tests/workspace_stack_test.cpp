// The deformer stack in the editor (issue 21, app/workspace/workspace_stack.cpp): a layer added from
// a cage file, made active and sculpted (its offsets change, the document's cage keeps its own), the
// other deformers bound in the background, and the skin the editor shows equal to the whole stack's rig
// (what `cagewrap pose` and the exports make) within 1e-5 of the diagonal; mute, solo, hide, move,
// rename and remove are one undo step each; a saved project reopens with its stack; bad requests are named.
#include <algorithm>
#include <cmath>
#include <filesystem>

#include <glm/geometric.hpp>

#include "core/document/binding_cache.h"
#include "core/document/project_io.h"
#include "core/rig/rig.h"
#include "tests/workspace_fixtures.h"

namespace cagewrap::app {
namespace {

namespace fs = std::filesystem;

class WorkspaceStackTest : public DemoWorkspaceTest {
 protected:
  std::string cage_path() const { return std::string(CAGEWRAP_SOURCE_DIR) + "/assets/demo_cage.obj"; }
  // Every bind (the active deformer's and the others'), polled as the frame loop polls them.
  void finish_binds() {
    for (int i = 0; i < 60000 && ws.binding_any(); ++i) {
      ws.scene()->poll_bind();
      ws.poll_jobs();
      if (ws.binding_any()) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    ASSERT_FALSE(ws.binding_any()) << "the binds did not finish";
  }
  // The skin the editor shows at the walk's t = 0.4.
  std::vector<glm::vec3> shown() {
    ws.run("clip walk");
    ws.run("time 0.4");
    ws.update_pose();
    return ws.scene()->skin_posed();
  }
  // The same frame posed by the whole document's rig (what pose and export make).
  std::vector<glm::vec3> rig_skin(const Document& d) {
    auto rig = Rig::create(d);
    EXPECT_TRUE(rig.ok()) << rig.error().message;
    if (!rig.ok()) return {};
    std::vector<glm::vec3> skin(rig->num_skin_points());
    PosedCage cage;
    const auto& pb = ws.view.playback;
    EXPECT_TRUE(rig->pose_clip(d, pb.clip, pb.player.time(), pb.pose_override, cage, skin).ok());
    return skin;
  }
  static double largest_gap(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
    EXPECT_EQ(a.size(), b.size());
    double worst = 0.0;
    for (size_t i = 0; i < std::min(a.size(), b.size()); ++i) worst = std::max(worst, double(glm::distance(a[i], b[i])));
    return worst;
  }
};

TEST_F(WorkspaceStackTest, AnActiveLayerIsSculptedAndTheViewIsWhatTheRigShips) {
  finish_bind();
  const double diag = ws.scene()->skin_diagonal;
  const std::vector<glm::vec3> alone = shown();
  const size_t steps = undo_steps();

  // a layer from a cage file: one step, bound in the background
  ASSERT_TRUE(ws.run("deformer_add " + cage_path()));
  EXPECT_EQ(undo_steps(), steps + 1);
  ASSERT_EQ(ws.scene()->work().layers.size(), 1u);
  EXPECT_EQ(ws.scene()->work().layers[0].name, "demo_cage");
  finish_binds();
  EXPECT_TRUE(ws.scene()->stacked());
  // a copy of the own cage, in order: the skin is what it was
  EXPECT_LT(largest_gap(shown(), alone), 1e-5 * diag);

  // active: the tools act on the layer; the document's cage keeps its own offsets
  ASSERT_TRUE(ws.run("deformer_active 1"));
  EXPECT_EQ(ws.scene()->active_deformer(), 1u);
  EXPECT_EQ(undo_steps(), steps + 1) << "choosing the active deformer is not an edit";
  finish_binds();
  ws.run("mode cage_vertices");
  ws.run("select_cage_vertex 300");
  ASSERT_TRUE(ws.run("move 0 0.03 0"));
  EXPECT_EQ(undo_steps(), steps + 2);
  const Document& w = ws.scene()->work();
  ASSERT_EQ(w.layers[0].cage_offsets.size(), w.layers[0].cage->num_vertices());
  EXPECT_GT(glm::length(w.layers[0].cage_offsets[300]), 0.01f);
  EXPECT_TRUE(w.cage_offsets.empty() || glm::length(w.cage_offsets[300]) == 0.0f) << "the document's cage is not moved";
  finish_binds();
  const std::vector<glm::vec3> sculpted = shown();
  EXPECT_GT(largest_gap(sculpted, alone), 0.005) << "the layer's sculpt shows";
  // the view is what the whole stack's rig makes (pose, export)
  EXPECT_LT(largest_gap(sculpted, rig_skin(ws.scene()->work())), 1e-5 * diag);

  // mute: one step, the layer leaves the skin; undo brings it back
  ASSERT_TRUE(ws.run("deformer_mute 1 on"));
  EXPECT_EQ(undo_steps(), steps + 3);
  finish_binds();
  EXPECT_LT(largest_gap(shown(), alone), 1e-5 * diag);
  EXPECT_LT(largest_gap(shown(), rig_skin(ws.scene()->work())), 1e-5 * diag);
  ws.run("undo");
  finish_binds();
  EXPECT_LT(largest_gap(shown(), sculpted), 1e-5 * diag);
  // solo the document's cage: as if the layer were muted
  ASSERT_TRUE(ws.run("deformer_solo 0"));
  finish_binds();
  EXPECT_LT(largest_gap(shown(), alone), 1e-5 * diag);
  EXPECT_LT(largest_gap(shown(), rig_skin(ws.scene()->work())), 1e-5 * diag);
  ASSERT_TRUE(ws.run("deformer_solo off"));
  // mute the document's cage: in order, the layer alone moves the skin
  ASSERT_TRUE(ws.run("deformer_mute 0 on"));
  finish_binds();
  EXPECT_LT(largest_gap(shown(), sculpted), 1e-5 * diag);
  ASSERT_TRUE(ws.run("deformer_mute 0 off"));
  // a sum doubles the copy's motion: the view follows the mode, and agrees with the rig
  ASSERT_TRUE(ws.run("deformer_stack sum"));
  finish_binds();
  const std::vector<glm::vec3> summed = shown();
  EXPECT_GT(largest_gap(summed, sculpted), 0.01);
  EXPECT_LT(largest_gap(summed, rig_skin(ws.scene()->work())), 1e-5 * diag);
  ASSERT_TRUE(ws.run("deformer_stack in_order"));
  // a mask made in the editor: one arm's region keeps the sculpt (made at a shoulder), the other arm's not
  const size_t before_mask = undo_steps();
  ws.run("deformer_mask 1 joints shoulder.L,nope");
  EXPECT_TRUE(logged("has no node 'nope'")) << "an unknown joint is named";
  EXPECT_EQ(undo_steps(), before_mask);
  double kept[2];
  for (int side = 0; side < 2; ++side) {
    const std::string source = std::string("joints shoulder.") + "LR"[side];
    ASSERT_TRUE(ws.run("deformer_mask 1 " + source));
    EXPECT_EQ(undo_steps(), before_mask + 1 + side);
    ASSERT_TRUE(ws.scene()->work().layers[0].mask);
    EXPECT_EQ(ws.scene()->work().layers[0].mask_source, source);
    finish_binds();
    const std::vector<glm::vec3> masked = shown();
    EXPECT_LT(largest_gap(masked, rig_skin(ws.scene()->work())), 1e-5 * diag);
    kept[side] = largest_gap(masked, alone);
  }
  EXPECT_GT(std::max(kept[0], kept[1]), 0.005) << "the sculpted arm keeps the sculpt";
  EXPECT_LT(std::min(kept[0], kept[1]), 1e-3) << "the other arm does not";
  ASSERT_TRUE(ws.run("deformer_mask 1 none"));
  EXPECT_FALSE(ws.scene()->work().layers[0].mask);
  ws.run("undo");
  ws.run("undo");
  ws.run("undo");
  EXPECT_FALSE(ws.scene()->work().layers[0].mask);
  finish_binds();

  // a second layer, moved before the first: the active deformer follows its layer
  ws.run("deformer_add " + cage_path());
  EXPECT_TRUE(logged("there is a deformer named 'demo_cage' already")) << "names must differ";
  ASSERT_EQ(ws.scene()->work().layers.size(), 1u);
  ASSERT_TRUE(ws.add_deformer(cage_path(), "second"));
  ASSERT_TRUE(ws.run("deformer_hide 2 on"));
  EXPECT_TRUE(ws.scene()->work().layers[1].hidden);
  const size_t before_move = undo_steps();
  ASSERT_TRUE(ws.run("deformer_move 2 1"));
  EXPECT_EQ(undo_steps(), before_move + 1);
  EXPECT_EQ(ws.scene()->work().layers[0].name, "second");
  EXPECT_EQ(ws.scene()->active_deformer(), 2u) << "the sculpted layer is now second and still active";
  EXPECT_EQ(deformer_name(ws.scene()->work(), ws.scene()->active_deformer()), "demo_cage");
  ASSERT_TRUE(ws.run("deformer_rename 1 face"));
  EXPECT_EQ(ws.scene()->work().layers[0].name, "face");
  finish_binds();
  EXPECT_LT(largest_gap(shown(), rig_skin(ws.scene()->work())), 1e-5 * diag);

  // saved and opened again: the stack is the same work
  const fs::path dir = fs::path(testing::TempDir()) / "workspace_stack";
  fs::create_directories(dir);
  ASSERT_TRUE(save_project((dir / "stack.cagewrap").string(), ws.scene()->work()).ok());
  auto loaded = load_project((dir / "stack.cagewrap").string());
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  EXPECT_TRUE(same_content(loaded->document, ws.scene()->work()));
  EXPECT_TRUE(loaded->document.layers[0].hidden);

  // saved with caching on and the editor's bindings (the active layer's own, the other deformers' rigs'):
  // each goes to its deformer's cache file, and opened again each is used
  const std::vector<const Binding*> bindings = ws.scene()->deformer_bindings();
  ASSERT_EQ(bindings.size(), 3u);
  for (size_t d = 0; d < bindings.size(); ++d) EXPECT_NE(bindings[d], nullptr) << "deformer " << d;
  SaveOptions cache;
  cache.binding = bindings[0];
  cache.layer_bindings.assign(bindings.begin() + 1, bindings.end());
  const std::string cached_path = (dir / "cached.cagewrap").string();
  ASSERT_TRUE(save_project(cached_path, with_cache_binding(ws.scene()->work(), true), cache).ok());
  auto reopened = load_project(cached_path);
  ASSERT_TRUE(reopened.ok()) << reopened.error().message;
  const StackBindingCache caches = load_stack_binding_caches(reopened->document);
  EXPECT_EQ(caches.used, 3u);
  EXPECT_TRUE(caches.not_used.empty()) << caches.not_used.front();

  // remove the active layer: one step, the document's cage is active again; undo brings it back
  const size_t before_remove = undo_steps();
  ASSERT_TRUE(ws.run("deformer_remove 2"));
  EXPECT_EQ(undo_steps(), before_remove + 1);
  EXPECT_EQ(ws.scene()->active_deformer(), 0u);
  ASSERT_EQ(ws.scene()->work().layers.size(), 1u);
  ws.run("undo");
  ASSERT_EQ(ws.scene()->work().layers.size(), 2u);
  EXPECT_EQ(ws.scene()->work().layers[1].name, "demo_cage");
  EXPECT_TRUE(errors.empty()) << errors.front();
}

TEST_F(WorkspaceStackTest, BadRequestsAreNamedAndChangeNothing) {
  finish_bind();
  const size_t steps = undo_steps();
  ws.run("deformer_active 3");
  ws.run("deformer_remove 0");
  ws.run("deformer_move 1 1");
  ws.run("deformer_add /no/such/cage.obj");
  ws.run("deformer_stack blend -1");
  ws.run("deformer_mute 0 maybe");
  EXPECT_EQ(undo_steps(), steps);
  EXPECT_TRUE(logged("no deformer 3 (the deformers are 0 to 0)"));
  EXPECT_TRUE(logged("deformer 0 is the document's own cage"));
  EXPECT_TRUE(logged("/no/such/cage.obj") || (!errors.empty() && errors.back().find("/no/such/cage.obj") != std::string::npos));
  EXPECT_TRUE(logged("exponent must be a number >= 0"));
  EXPECT_TRUE(logged("deformer_mute D on|off"));
}

}  // namespace
}  // namespace cagewrap::app
