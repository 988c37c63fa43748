#include "core/deform/patch_binding.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "core/cage/cage.h"
#include "core/deform/set_editing.h"
#include "core/geometry/point_grid.h"

namespace cagewrap {

namespace {

// Mean length of the control-net edges (rows and columns of every grid): the default h.
double mean_control_edge_length(const PatchSurface& surface) {
  double sum = 0.0;
  size_t n = 0;
  for (const PatchGrid& g : surface.grids)
    for (uint32_t r = 0; r < g.rows; ++r)
      for (uint32_t c = 0; c < g.cols; ++c) {
        if (c + 1 < g.cols) sum += glm::length(g.at(r, c + 1) - g.at(r, c)), ++n;
        if (r + 1 < g.rows) sum += glm::length(g.at(r + 1, c) - g.at(r, c)), ++n;
      }
  return n ? sum / double(n) : 0.0;
}

// Samples whose frame is degenerate (S_u x S_v vanishes relative to the tangents' lengths, or is not
// finite): they get no weight and are reported in Binding::invalid_elements (as sample indices).
bool degenerate_frame(const glm::dvec3& du, const glm::dvec3& dv) {
  const double area = glm::length(glm::cross(du, dv));
  const double longest = std::max(glm::length(du), glm::length(dv));
  return !std::isfinite(area) || !(area > kDegenerateRatio * longest * longest);
}

}  // namespace

std::vector<glm::vec3> sample_positions(const PatchSurface& surface, std::span<const PatchSample> samples) {
  std::vector<glm::vec3> out(samples.size());
  for (size_t k = 0; k < samples.size(); ++k) out[k] = glm::vec3(sample_frame(surface, samples[k]).position);
  return out;
}

BindParams patch_bind_params(const BindParams& params) {
  BindParams p = params;
  p.variant = Variant::kBasic;
  p.separate = false;
  return p;
}

size_t patch_sample_count(const PatchSurface& rest, uint32_t density) {
  auto s = sample_patch_surface(rest, density);
  return s ? s->size() : 0;
}

Result<Binding> bind_skin_to_patches(std::span<const glm::vec3> skin, const PatchSurface& rest,
                                     uint32_t density, const BindParams& params_in,
                                     const BindProgress& progress, std::span<const SetEdit> edits_in) {
  const auto start = std::chrono::steady_clock::now();
  const BindParams params = patch_bind_params(params_in);
  if (auto v = validate(params); !v) return v.error();
  // a dense sampling takes a while before the points are bound: Cancel is honoured between stages
  auto stopped = [&progress] { return progress.cancel && progress.cancel->load(std::memory_order_relaxed); };
  const Error cancel_error{ErrorCode::kCancelled, "binding to the patch driver was cancelled"};
  auto sampled = sample_patch_surface(rest, density);
  if (!sampled) return sampled.error();
  if (stopped()) return cancel_error;
  const std::vector<PatchSample>& samples = *sampled;
  if (auto s = check_skin(skin); !s) return s.error();
  const double h = params.scale > 0 ? params.scale : mean_control_edge_length(rest);
  if (!(h > 0) || !std::isfinite(h))
    return make_error(ErrorCode::kInvalidArgument,
                      "the patch driver's control net has zero mean edge length; give a scale h");

  Binding b;
  b.params = params;
  b.h = h;
  b.origin = bounding_box(skin).center();
  b.num_points = static_cast<uint32_t>(skin.size());
  b.num_samples = static_cast<uint32_t>(samples.size());
  std::vector<glm::dvec3> position(samples.size());
  std::vector<glm::vec3> valid_position;
  std::vector<uint32_t> valid_ids;
  for (size_t k = 0; k < samples.size(); ++k) {
    if (k % 65536 == 0 && stopped()) return cancel_error;
    const SampleFrame f = sample_frame(rest, samples[k]);
    position[k] = f.position;
    if (degenerate_frame(f.du, f.dv)) {
      b.invalid_elements.push_back(static_cast<uint32_t>(k));
      continue;
    }
    valid_ids.push_back(static_cast<uint32_t>(k));
    valid_position.push_back(glm::vec3(f.position));
  }
  if (valid_ids.empty())
    return make_error(ErrorCode::kNoValidElements, "the patch driver has no valid sample: all " +
                                                       std::to_string(samples.size()) +
                                                       " samples have a degenerate frame (S_u x S_v = 0)");
  const PointGrid grid(valid_position);
  if (stopped()) return cancel_error;
  // the set edits, one per point (canonical), checked against the skin and the samples
  const std::vector<SetEdit> edits = canonical_set_edits(edits_in);
  for (const SetEdit& e : edits) {
    if (e.point >= skin.size())
      return make_error(ErrorCode::kIndexOutOfRange, "a set edit names skin point " + std::to_string(e.point) + ", but the skin has " +
                                                         std::to_string(skin.size()));
    for (const auto* list : {&e.exclude, &e.include})
      for (uint32_t k : *list)
        if (k >= samples.size())
          return make_error(ErrorCode::kIndexOutOfRange, "the set edit of skin point " + std::to_string(e.point) + " names sample " +
                                                             std::to_string(k) + ", but the driver has " + std::to_string(samples.size()) +
                                                             " at density " + std::to_string(density));
  }
  std::vector<uint8_t> valid(samples.size(), 0);
  for (uint32_t k : valid_ids) valid[k] = 1;

  // per point: the K + 1 nearest valid samples decide the set exactly (the threshold radius is
  // relative to the nearest; the (K+1)-th only sets the cut)
  const size_t n = skin.size(), K = params.max_elements;
  struct Block {
    std::vector<uint32_t> count, ids;  // per point; entries
    std::vector<float> weights;        // entries
  };
  std::vector<uint8_t> inside(n);
  std::atomic<size_t> done{0};
  std::atomic<bool> cancelled{false};
  const size_t block = 1024, blocks = (n + block - 1) / block;
  std::vector<Block> out(blocks);
  const size_t report_every = std::max<size_t>(1, blocks / 200);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, blocks), [&](const tbb::blocked_range<size_t>& r) {
    std::vector<std::pair<double, uint32_t>> near;
    std::vector<std::pair<double, uint32_t>> cands;
    std::vector<double> dist, w;
    for (size_t blk = r.begin(); blk != r.end(); ++blk) {
      if (cancelled.load(std::memory_order_relaxed)) return;
      if (stopped()) {
        cancelled = true;
        return;
      }
      Block& o = out[blk];
      for (size_t i = blk * block; i < std::min(n, (blk + 1) * block); ++i) {
        const glm::dvec3 p(skin[i]);
        // its set edit: excluded and included samples leave the automatic rule (included ones join after it)
        const auto at = std::lower_bound(edits.begin(), edits.end(), uint32_t(i),
                                         [](const SetEdit& e, uint32_t point) { return e.point < point; });
        const SetEdit* edit = at != edits.end() && at->point == i ? &*at : nullptr;
        const auto outside = [&](uint32_t k) {
          return edit && (edit->excludes(k) || std::binary_search(edit->include.begin(), edit->include.end(), k));
        };
        // the K + 1 nearest samples, or up to kMaxTiedMembers + 1 where the (K+1)-th is in the tie band
        // (those an edit leaves out not counted)
        const size_t skipped = edit ? edit->exclude.size() + edit->include.size() : 0;
        auto gather = [&](size_t count) {
          cands.clear();
          if (edit && edit->only) return;
          grid.nearest(p, count + skipped, near);
          for (const auto& [d2, local] : near) {
            const uint32_t k = valid_ids[local];
            if (!outside(k)) cands.push_back({glm::length(p - position[k]) / h, k});  // exact, in double
          }
          std::sort(cands.begin(), cands.end());
        };
        gather(K + 1);
        if (cands.size() > K) {
          const double band = std::sqrt(tie_band2(params, 1.0, cands.front().first * cands.front().first));
          if (cands[K].first <= band) gather(std::max<size_t>(K + 1, kMaxTiedMembers + 1));
        }
        std::vector<std::pair<double, uint32_t>> included;  // the edit's valid inclusions, with their distances
        if (edit)
          for (uint32_t k : edit->include)
            if (valid[k]) included.push_back({glm::length(p - position[k]) / h, k});
        if (cands.empty() && included.empty()) {  // the edit left nothing: the nearest valid sample
          grid.nearest(p, 1, near);
          const uint32_t k = valid_ids[near.front().second];
          cands.push_back({glm::length(p - position[k]) / h, k});
        }
        if (cands.empty()) {  // `only`: the included samples alone, each with its own weight
          inside[i] = 0;
          double sum = 0.0;
          w.resize(included.size());
          std::vector<double> own;
          for (const auto& [d, k] : included) own.push_back(d);
          std::sort(own.begin(), own.end());
          const Taper taper(params, h, own);  // (raw weights only: eq. 1 of each distance)
          for (size_t j = 0; j < included.size(); ++j) sum += (w[j] = taper.raw(included[j].first));
          uint32_t m = 0;
          for (size_t j = 0; j < included.size(); ++j) {
            o.ids.push_back(included[j].second);
            o.weights.push_back(static_cast<float>(sum > 0 ? w[j] / sum : 1.0 / included.size()));
            ++m;
          }
          o.count.push_back(m);
          continue;
        }
        // (beyond the max distance the nearest samples still drive: the tie band keeps them)
        const double nearest = cands.front().first;
        inside[i] = nearest <= params.close_distance;
        const double radius = threshold_radius(nearest, params.local, params.epsilon);
        std::erase_if(cands, [&](const auto& c) { return c.first > radius; });  // the max distance: Taper
        dist.resize(cands.size());
        for (size_t j = 0; j < cands.size(); ++j) dist[j] = cands[j].first;
        const Taper taper(params, h, dist);
        w.resize(cands.size());
        double sum = taper.weights(w);
        if (!(sum > 0)) {  // every candidate at the cut: plain weights over the first K
          sum = 0.0;
          for (size_t j = 0; j < cands.size(); ++j) sum += (w[j] = j < K ? taper.raw(dist[j]) : 0.0);
        }
        for (const auto& [d, k] : included) {  // inclusions: their own weight, on the taper's scale
          cands.push_back({d, k});
          w.push_back(taper.raw(d));
          sum += w.back();
        }
        uint32_t m = 0;
        for (size_t j = 0; j < cands.size(); ++j) {
          if (w[j] <= 0.0) continue;  // at the cut: contributes nothing
          o.ids.push_back(cands[j].second);
          o.weights.push_back(static_cast<float>(w[j] / sum));
          ++m;
        }
        o.count.push_back(m);
      }
      const size_t d = done.fetch_add(1) + 1;
      if (progress.on_progress && (d % report_every == 0 || d == blocks))
        progress.on_progress(double(d) / blocks);
    }
  });
  if (cancelled) return cancel_error;

  b.offsets.assign(n + 1, 0);
  for (size_t blk = 0; blk < blocks; ++blk)
    for (size_t j = 0; j < out[blk].count.size(); ++j) {
      const size_t i = blk * block + j;
      b.offsets[i + 1] = b.offsets[i] + out[blk].count[j];
      b.max_set_size = std::max(b.max_set_size, out[blk].count[j]);
      b.quality_inside += inside[i];
    }
  b.total_set_size = b.offsets[n];
  b.ids.reserve(b.offsets[n]);
  b.weights.reserve(b.offsets[n]);
  for (Block& o : out) {  // blocks hold consecutive points
    b.ids.insert(b.ids.end(), o.ids.begin(), o.ids.end());
    b.weights.insert(b.weights.end(), o.weights.begin(), o.weights.end());
  }
  b.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return b;
}

namespace {

std::vector<uint32_t> shape_of(const PatchSurface& s) {
  std::vector<uint32_t> out;
  for (const PatchGrid& g : s.grids) out.insert(out.end(), {g.rows, g.cols, uint32_t(g.basis)});
  return out;
}

glm::dvec3 unit_normal(const glm::dvec3& du, const glm::dvec3& dv, const glm::dvec3& fallback) {
  const glm::dvec3 n = glm::cross(du, dv);
  const double len = glm::length(n);
  return len > 0 && std::isfinite(len) ? n / len : fallback;
}

}  // namespace

Result<PatchDeformer> PatchDeformer::create(const Binding& binding, std::span<const glm::vec3> skin_rest,
                                            const PatchSurface& rest, uint32_t density) {
  auto sampled = sample_patch_surface(rest, density);
  if (!sampled) return sampled.error();
  if (binding.num_samples != sampled->size())
    return make_error(ErrorCode::kTopologyMismatch,
                      "the binding was made for " + std::to_string(binding.num_samples) +
                          " driver samples but the patch driver at density " + std::to_string(density) +
                          " has " + std::to_string(sampled->size()));
  auto d = Deformer::create(binding, skin_rest);
  if (!d) return d.error();
  PatchDeformer pd(std::move(*d));
  pd.shape_ = shape_of(rest);
  pd.samples_ = std::move(*sampled);
  const size_t ns = pd.samples_.size();
  pd.rest_point_.resize(ns);
  pd.rest_normal_.resize(ns);
  pd.rest_inv_.assign(ns, glm::dmat3(1.0));
  pd.valid_.assign(ns, 0);
  pd.maps_.resize(ns);
  for (size_t k = 0; k < ns; ++k) {
    const SampleFrame f = sample_frame(rest, pd.samples_[k]);
    pd.rest_point_[k] = f.position - binding.origin;
    pd.rest_normal_[k] = unit_normal(f.du, f.dv, glm::dvec3(0, 0, 1));
    if (degenerate_frame(f.du, f.dv)) continue;
    pd.valid_[k] = 1;
    pd.rest_inv_[k] = glm::inverse(glm::dmat3(f.du, f.dv, pd.rest_normal_[k]));
  }
  return pd;
}

Status PatchDeformer::update_maps(const PatchSurface& posed) {
  if (shape_of(posed) != shape_)
    return make_error(
        ErrorCode::kTopologyMismatch,
        "the posed patch driver's grids (count, sizes or basis) differ from the bound driver's");
  if (auto s = validate_patch_surface(posed, "the posed patch driver"); !s) return s;
  const glm::dvec3 origin = deformer_.binding().origin;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, samples_.size(), 256),
                    [&](const tbb::blocked_range<size_t>& r) {
                      for (size_t k = r.begin(); k != r.end(); ++k) {
                        if (!valid_[k]) {
                          maps_[k] = make_affine(glm::dmat3(1.0), glm::dvec3(0.0));
                          continue;
                        }
                        const SampleFrame f = sample_frame(posed, samples_[k]);
                        const glm::dvec3 n = unit_normal(f.du, f.dv, rest_normal_[k]);
                        const glm::dmat3 m = glm::dmat3(f.du, f.dv, n) * rest_inv_[k];
                        maps_[k] = make_affine(m, (f.position - origin) - m * rest_point_[k]);
                      }
                    });
  return Ok{};
}

Status PatchDeformer::deform(const PatchSurface& posed, std::span<glm::vec3> out) {
  if (auto s = update_maps(posed); !s) return s;
  return deformer_.deform_with_maps(maps_, out);
}

}  // namespace cagewrap
