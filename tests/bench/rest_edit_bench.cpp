// Moving rest cage vertices (core/deform/rest_edit.h): the points the moved elements can reach found with
// ReachIndex and re-registered with Rebinder::move_rest, against the full bind it replaces. The
// armadillo bench triplet (shared assets) subdivided to four sizes: a fixed region (the cage
// vertices nearest one cage vertex) moved on each, then regions of growing size on one skin. The
// cost should follow the region, not the skin. Figures in docs/benchmarks.md.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <map>
#include <memory>

#include <glm/geometric.hpp>

#include "core/cage/cage.h"
#include "core/geometry/mesh_io.h"
#include "core/deform/registration.h"
#include "core/deform/rest_edit.h"
#include "core/geometry/subdivide.h"
#include "tests/test_assets.h"

namespace cagewrap {
namespace {

struct RestEditSetup {
  PolyMesh skin;
  Cage cage;
  BindParams params;
  Binding binding;
  std::unique_ptr<ReachIndex> index;
  std::string error;  // set when the shared assets are missing
};

// One setup per subdivision, kept across benchmarks (a bind at a million points takes seconds).
const RestEditSetup& setup(uint32_t cuts) {
  static std::map<uint32_t, std::unique_ptr<RestEditSetup>> cache;
  auto& slot = cache[cuts];
  if (slot) return *slot;
  slot = std::make_unique<RestEditSetup>();
  RestEditSetup& s = *slot;
  auto mesh = test::shared_asset("bench/armadillo/mesh_10001.obj");
  auto cage_file = test::shared_asset("bench/armadillo/cage.obj");
  if (!mesh || !cage_file) {
    s.error = "shared assets not found (set CAGEWRAP_SHARED_ASSETS)";
    return s;
  }
  auto m = load_mesh(*mesh);
  auto c = load_mesh(*cage_file);
  if (!m || !c) {
    s.error = "cannot read the armadillo triplet";
    return s;
  }
  auto cage = make_cage(*c, *cage_file);
  if (!cage) {
    s.error = cage.error().message;
    return s;
  }
  s.cage = std::move(cage).value();
  s.skin = cuts ? subdivide_edges_uniform(*m, cuts) : *m;
  // a fixed h (the mean cage edge length of the rest cage): moves then keep every other weight
  s.params.scale = std::move(bind_skin(std::span(s.skin.positions).first(1), s.cage, s.cage.polygons.positions, s.params)).value().h;
  s.binding = std::move(bind_skin(s.skin.positions, s.cage, s.cage.polygons.positions, s.params)).value();
  s.index = std::make_unique<ReachIndex>(std::move(ReachIndex::create(s.binding, s.skin.positions)).value());
  return s;
}

// The `count` cage vertices nearest cage vertex 0 (a patch of the surface).
std::vector<uint32_t> region(const Cage& cage, size_t count) {
  const auto& v = cage.polygons.positions;
  std::vector<uint32_t> ids(v.size());
  for (uint32_t i = 0; i < ids.size(); ++i) ids[i] = i;
  auto d2 = [&](uint32_t i) { return glm::dot(glm::dvec3(v[i] - v[0]), glm::dvec3(v[i] - v[0])); };
  count = std::min(count, ids.size());
  std::partial_sort(ids.begin(), ids.begin() + static_cast<std::ptrdiff_t>(count), ids.end(),
                    [&](uint32_t a, uint32_t b) { return d2(a) < d2(b); });
  ids.resize(count);
  return ids;
}

// One edit: the region moved out by a small step (alternately out and back), the affected points
// found, a Rebinder made for the moved cage, the points re-registered, the index refreshed.
void run_edit(benchmark::State& state, uint32_t cuts, size_t region_size) {
  const RestEditSetup& base = setup(cuts);
  if (!base.error.empty()) {
    state.SkipWithError(base.error.c_str());
    return;
  }
  Binding live = base.binding;
  ReachIndex index = *base.index;
  const std::vector<uint32_t> moved = region(base.cage, region_size);
  std::vector<glm::vec3> rest = base.cage.polygons.positions;
  const float step = static_cast<float>(0.05 * base.params.scale);
  size_t points = 0, edits = 0;
  bool out = true;
  for (auto _ : state) {
    for (uint32_t v : moved) rest[v].y += out ? step : -step;
    out = !out;
    auto affected = index.affected_points(live, base.cage, rest, moved, {});
    auto rebinder = Rebinder::create(base.skin.positions, base.cage, rest, base.params);
    if (!affected || !rebinder) {
      state.SkipWithError("rest edit setup failed");
      return;
    }
    if (auto s = rebinder->move_rest(live, {}, *affected); !s) {
      state.SkipWithError(s.error().message.c_str());
      return;
    }
    index.refresh(live, *affected);
    points += affected->size();
    ++edits;
  }
  state.counters["skin"] = static_cast<double>(base.skin.num_vertices());
  state.counters["moved"] = static_cast<double>(moved.size());
  state.counters["affected"] = edits ? double(points) / double(edits) : 0.0;
}

// A fixed region of 8 cage vertices on skins of 10k to 1M vertices (subdivision 0, 2, 5, 9).
void BM_RestEditFixedRegion(benchmark::State& state) { run_edit(state, static_cast<uint32_t>(state.range(0)), 8); }
// Regions of growing size on the 360k-vertex skin (subdivision 5).
void BM_RestEditGrowingRegion(benchmark::State& state) { run_edit(state, 5, static_cast<size_t>(state.range(0))); }

// The full bind each edit replaces.
void BM_RestEditFullBind(benchmark::State& state) {
  const RestEditSetup& base = setup(static_cast<uint32_t>(state.range(0)));
  if (!base.error.empty()) {
    state.SkipWithError(base.error.c_str());
    return;
  }
  for (auto _ : state) {
    auto b = bind_skin(base.skin.positions, base.cage, base.cage.polygons.positions, base.params);
    benchmark::DoNotOptimize(b);
  }
  state.counters["skin"] = static_cast<double>(base.skin.num_vertices());
}

BENCHMARK(BM_RestEditFixedRegion)->Arg(0)->Arg(2)->Arg(5)->Arg(9)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RestEditGrowingRegion)->Arg(1)->Arg(8)->Arg(64)->Arg(256)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RestEditFullBind)->Arg(0)->Arg(2)->Arg(5)->Arg(9)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace cagewrap
