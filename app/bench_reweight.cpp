#include "app/bench_reweight.h"

#include <algorithm>
#include <chrono>

#include "core/deform/deformer.h"
#include "core/deform/registration.h"
#include "core/deform/rest_edit.h"
#include "core/document/cage_subdivide.h"

namespace cagewrap::app {

namespace {
double since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

Result<ReweightFigures> bench_reweight(std::span<const glm::vec3> skin, const Cage& cage, std::span<const glm::vec3> rest,
                                       const BindParams& params, bool verify) {
  ReweightFigures f;
  f.verified = verify;
  auto cache = CandidateCache::create(skin, cage, rest, params);
  if (!cache) return cache.error();
  f.cache_s = cache->seconds();
  f.cache_bytes = cache->bytes();
  f.entries_per_point = double(cache->entries()) / std::max<size_t>(1, skin.size());
  struct Drag {
    const char* slider;
    std::vector<double> values;
  };
  const std::vector<Drag> drags = {
      {"local", {params.local - 0.5, params.local - 1.0, params.local + 0.5, params.local + 1.0}},
      {"epsilon", {params.epsilon * 0.7, params.epsilon * 0.5, std::min(1.0, params.epsilon * 1.5), std::min(1.0, params.epsilon * 2)}},
      {"K",
       {double(std::max(1u, params.max_elements - 2)), double(params.max_elements + 2), double(params.max_elements + 4),
        double(std::min(64u, params.max_elements + 8))}}};
  for (const Drag& drag : drags) {
    for (double v : drag.values) {
      BindParams p = params;
      if (drag.slider == std::string("local")) p.local = std::max(0.0, v);
      else if (drag.slider == std::string("epsilon")) p.epsilon = v;
      else p.max_elements = static_cast<uint32_t>(v);
      ReweightStep step;
      step.slider = drag.slider;
      step.value = v;
      CandidateCacheStats stats;
      auto t0 = std::chrono::steady_clock::now();
      auto b = cache->bind(p, {}, {}, &stats);
      step.reweight_s = since(t0);
      if (!b) return b.error();
      step.cached_points = stats.cached_points;
      step.queried_points = stats.queried_points;
      t0 = std::chrono::steady_clock::now();
      auto d = Deformer::create(*b, skin);
      step.table_s = since(t0);
      if (!d) return d.error();
      if (verify) {
        t0 = std::chrono::steady_clock::now();
        auto fresh = bind_skin(skin, cage, rest, p);
        step.fresh_s = since(t0);
        if (!fresh) return fresh.error();
        step.difference = registration_difference(*b, *fresh);
      }
      f.steps.push_back(step);
    }
  }
  return f;
}

Result<TopologyEditFigures> bench_topology_edit(std::span<const glm::vec3> skin, const Cage& cage,
                                                std::span<const glm::vec3> rest, const BindParams& params) {
  TopologyEditFigures f;
  auto b = bind_skin(skin, cage, rest, params);
  if (!b) return b.error();
  BindParams fixed = params;
  fixed.scale = b->h;  // the editor keeps the bound h for a local edit
  b->params.scale = b->h;
  f.face = static_cast<uint32_t>(cage.polygons.num_faces() / 2);
  const uint32_t faces[] = {f.face};
  auto edit = refine_faces(cage, faces);
  if (!edit) return edit.error();
  const auto& new_rest = edit->cage.polygons.positions;
  auto t0 = std::chrono::steady_clock::now();
  auto r = rebind_new_topology(*b, skin, edit->cage, new_rest, {}, {}, nullptr, nullptr);
  f.seconds = since(t0);
  if (!r) return r.error();
  f.added_elements = r->added_elements;
  f.removed_elements = r->removed_elements;
  f.points = r->points;
  t0 = std::chrono::steady_clock::now();
  auto fresh = bind_skin(skin, edit->cage, new_rest, fixed);
  f.fresh_s = since(t0);
  if (!fresh) return fresh.error();
  f.difference = registration_difference(*b, *fresh);
  return f;
}

}  // namespace cagewrap::app
