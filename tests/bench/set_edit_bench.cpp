// Live set editing on a ~50k-vertex skin (the generated arm refined, as in deform_bench.cpp): one
// brush stroke of ~2k points re-registered with Rebinder::update (and the deformer told), against the
// full bind it replaces; the brush dab and the display queries. Figures in docs/algorithm-notes.md.
#include <benchmark/benchmark.h>

#include "core/deform/deformer.h"
#include "core/deform/registration.h"
#include "core/deform/set_editing.h"
#include "core/document/set_queries.h"
#include "core/document/skin_brush.h"
#include "core/geometry/subdivide.h"
#include "tests/fixtures.h"

namespace cagewrap {
namespace {

struct StrokeSetup {
  PolyMesh skin = subdivide_edges_uniform(fixtures::cylinder_skin(), 5);  // ~48k vertices
  Cage cage = fixtures::cylinder_cage();
  Triangulation tri = triangulate(skin);
  SkinBrush brush{skin.positions, tri.triangles};
  std::vector<uint32_t> stroke;  // ~2k points around the middle of the arm, on top
  IndexSet faces{17, 18};        // cage quads near them
  explicit StrokeSetup(double radius = 0.45) {
    uint32_t hit = 0;
    double best = 1e9;
    for (uint32_t k = 0; k < tri.triangles.size(); ++k) {
      glm::dvec3 c(0.0);
      for (uint32_t v : tri.triangles[k]) c += glm::dvec3(skin.positions[v]) / 3.0;
      double d = glm::length(c - glm::dvec3(2.0, 0.0, 0.5));
      if (d < best) best = d, hit = k;
    }
    glm::dvec3 at(0.0);
    for (uint32_t v : tri.triangles[hit]) at += glm::dvec3(skin.positions[v]) / 3.0;
    stroke = std::move(brush.points_within(hit, at, radius)).value().points;
    hit_triangle = hit;
    hit_point = at;
  }
  uint32_t hit_triangle = 0;
  glm::dvec3 hit_point{0.0};
};

// One stroke: the edit (remove two faces from ~2k points, then reset them, alternately), the
// re-registration of the changed points, and the deformer's refresh.
void BM_StrokeUpdate(benchmark::State& state) {
  StrokeSetup s;
  BindParams p;
  p.variant = static_cast<Variant>(state.range(0));
  auto rebinder = std::move(Rebinder::create(s.skin.positions, s.cage, s.cage.polygons.positions, p)).value();
  Binding live = std::move(rebinder.bind({})).value();
  Deformer deformer = std::move(Deformer::create(live, s.skin.positions)).value();
  std::vector<SetEdit> edits;
  bool remove = true;
  for (auto _ : state) {
    auto r = apply_set_edit(edits, remove ? SetEditMode::kRemove : SetEditMode::kReset, IndexSet(s.stroke),
                            s.faces, s.cage, s.skin.num_vertices());
    edits = std::move(r->edits);
    if (auto st = rebinder.update(live, edits, r->changed_points); !st.ok())
      state.SkipWithError(st.error().message.c_str());
    if (auto st = deformer.stencil_changed(r->changed_points); !st.ok()) state.SkipWithError(st.error().message.c_str());
    remove = !remove;
  }
  state.counters["points"] = static_cast<double>(s.skin.num_vertices());
  state.counters["stroke"] = static_cast<double>(s.stroke.size());
}

// The full bind a stroke would otherwise cost.
void BM_StrokeFullBind(benchmark::State& state) {
  StrokeSetup s;
  BindParams p;
  p.variant = static_cast<Variant>(state.range(0));
  auto r =
      apply_set_edit({}, SetEditMode::kRemove, IndexSet(s.stroke), s.faces, s.cage, s.skin.num_vertices());
  for (auto _ : state) {
    auto b = bind_skin(s.skin.positions, s.cage, s.cage.polygons.positions, p, r->edits);
    benchmark::DoNotOptimize(b);
  }
  state.counters["points"] = static_cast<double>(s.skin.num_vertices());
}

void BM_BrushDab(benchmark::State& state) {
  StrokeSetup s;
  for (auto _ : state) {
    auto r = s.brush.points_within(s.hit_triangle, s.hit_point, 0.45);
    benchmark::DoNotOptimize(r);
  }
  state.counters["stroke"] = static_cast<double>(s.stroke.size());
}

void BM_DisplayQueries(benchmark::State& state) {
  StrokeSetup s;
  BindParams p;
  Binding b = std::move(bind_skin(s.skin.positions, s.cage, s.cage.polygons.positions, p)).value();
  for (auto _ : state) {
    auto heat = face_influence(b, s.cage, s.faces);
    auto overview = set_overview(b, s.skin.positions);
    benchmark::DoNotOptimize(heat);
    benchmark::DoNotOptimize(overview);
  }
  state.counters["points"] = static_cast<double>(s.skin.num_vertices());
}

BENCHMARK(BM_StrokeUpdate)->Arg(0)->Arg(2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StrokeFullBind)->Arg(0)->Arg(2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BrushDab)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DisplayQueries)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace cagewrap
