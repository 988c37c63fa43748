// The cage simulation's cost per frame (core/cage/cage_sim.h) for a 2,000-vertex cloth cage on one
// thread: a 40 x 50 sheet hanging behind the demo character, pinned along its top row and swinging
// sideways, colliding with the character's bone capsules (core/cage/cage_sim.h skeleton_capsules) and a
// floor. One iteration = one frame of the default settings (8 substeps of 1/240 s); the argument is
// the edge-constraint sweeps per substep. The target is under 2 ms a frame (the CPU time column);
// figures in docs/simulation.md.
#include <cmath>

#include <benchmark/benchmark.h>

#include "core/cage/cage_sim.h"
#include "core/character/demo_character.h"
#include "core/rig/demo_sim.h"

namespace cagewrap {
namespace {

struct SheetSetup {
  PolyMesh sheet = grid_sheet({-0.5, 1.5, -0.15}, {1.0, 0.0, 0.0}, {0.0, -1.4, -0.2}, 39, 49);  // 2,000 vertices
  std::vector<std::vector<glm::vec3>> targets;  // 120 frames of the sheet swinging sideways
  std::vector<ColliderShape> colliders;
  SheetSetup() {
    const Character demo = make_demo_character();
    const auto capsules = skeleton_capsules(demo, 0, 1.0);
    const std::vector<Collider> floor = {{"floor", ColliderKind::kPlane, {0, 0, 0}, {0, 1, 0}, 0.0, -1}};
    const auto rest = demo.skeleton.global_transforms(demo.skeleton.rest_pose());
    std::vector<glm::mat4> identity(demo.skins[0].joints.size(), glm::mat4(1.0f));
    pose_colliders(floor, capsules, rest, rest, identity, colliders);
    for (int f = 0; f < 120; ++f) {
      const float dx = 0.15f * std::sin(static_cast<float>(f) * 0.2f);
      auto& t = targets.emplace_back(sheet.positions);
      for (glm::vec3& p : t) p.x += dx;
    }
  }
  SimSettings settings(int iterations) const {
    SimSettings s;
    s.enabled = true;
    s.params.iterations = iterations;
    s.params.skeleton_colliders = true;
    s.vertices.assign(sheet.num_vertices(), SimVertex{false, 1.0f, 0.1f});
    for (int i = 0; i < 40; ++i) s.vertices[i].pinned = true;
    return s;
  }
};

const SheetSetup& setup() {
  static const SheetSetup s;
  return s;
}

// state.range(0): edge-constraint sweeps per substep
void BM_CageSimFrame2k(benchmark::State& state) {
  const SheetSetup& s = setup();
  auto sim = CageSim::create(s.sheet, s.sheet.positions, s.settings(static_cast<int>(state.range(0))));
  if (!sim) {
    state.SkipWithError(sim.error().message.c_str());
    return;
  }
  sim->reset(s.targets[0], s.colliders);
  size_t f = 0;
  for (auto _ : state) {
    sim->step_frame(s.targets[++f % s.targets.size()], s.colliders);
    benchmark::DoNotOptimize(sim->positions().data());
  }
  state.counters["vertices"] = static_cast<double>(sim->num_vertices());
  state.counters["colliders"] = static_cast<double>(s.colliders.size());
}
BENCHMARK(BM_CageSimFrame2k)->Arg(1)->Arg(2)->Arg(4)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace cagewrap
