// Google Benchmark microbenchmarks of bind and deform on the generated arm fixture, refined to
// several sizes. The figures of record (1,000,000 vertices, real data) come from `cagewrap bench`;
// these track the kernels on any machine, without shared assets.
#include <benchmark/benchmark.h>

#include "core/deform/deformer.h"
#include "core/deform/registration.h"
#include "core/geometry/subdivide.h"
#include "tests/fixtures.h"

namespace cagewrap {
namespace {

struct Setup {
  PolyMesh skin;
  Cage cage = fixtures::cylinder_cage();
  std::vector<glm::vec3> posed;
  explicit Setup(int cuts) {
    skin = subdivide_edges_uniform(fixtures::cylinder_skin(), static_cast<uint32_t>(cuts));
    posed = fixtures::bent(cage.polygons.positions, 2.0, 45);
  }
};

void BM_Bind(benchmark::State& state) {
  Setup s(static_cast<int>(state.range(0)));
  BindParams p;
  p.variant = static_cast<Variant>(state.range(1));
  for (auto _ : state) {
    auto b = bind_skin(s.skin.positions, s.cage, s.cage.polygons.positions, p);
    benchmark::DoNotOptimize(b);
  }
  state.counters["points"] = static_cast<double>(s.skin.num_vertices());
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(s.skin.num_vertices()));
}

void BM_Deform(benchmark::State& state) {
  Setup s(static_cast<int>(state.range(0)));
  BindParams p;
  p.variant = static_cast<Variant>(state.range(1));
  Binding b = std::move(bind_skin(s.skin.positions, s.cage, s.cage.polygons.positions, p)).value();
  Deformer d = std::move(Deformer::create(b, s.skin.positions)).value();
  std::vector<glm::vec3> out(s.skin.num_vertices());
  for (auto _ : state) {
    auto st = d.deform(s.posed, out);
    benchmark::DoNotOptimize(out.data());
    if (!st.ok()) state.SkipWithError(st.error().message.c_str());
  }
  state.counters["points"] = static_cast<double>(s.skin.num_vertices());
  state.counters["bytes_per_point"] = double(b.bytes()) / b.num_points;
  state.SetBytesProcessed(state.iterations() * static_cast<int64_t>(d.bytes_read_per_call() + d.bytes_written_per_call()));
}

// cuts 0, 3, 15: about 1.3k, 21k and 330k skin vertices; variants basic, clamped, extended
BENCHMARK(BM_Bind)->ArgsProduct({{0, 3, 15}, {0, 1, 2}})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Deform)->ArgsProduct({{0, 3, 15}, {0, 1, 2}})->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace cagewrap
