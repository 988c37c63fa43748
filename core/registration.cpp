#include "core/registration.h"

#include <algorithm>
#include <chrono>
#include <memory>
#include <cmath>
#include <unordered_map>

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include "core/element_bvh.h"
#include "core/geometry.h"

namespace cagewrap {

const char* variant_name(Variant v) {
  switch (v) {
    case Variant::kBasic: return "basic";
    case Variant::kClamped: return "clamped";
    case Variant::kExtended: return "extended";
  }
  return "?";
}

bool parse_variant(const std::string& s, Variant& out) {
  if (s == "basic") out = Variant::kBasic;
  else if (s == "clamped") out = Variant::kClamped;
  else if (s == "extended") out = Variant::kExtended;
  else return false;
  return true;
}

Status validate(const BindParams& p) {
  auto bad = [](const std::string& m) { return make_error(ErrorCode::kInvalidArgument, m); };
  if (!(p.local >= 0 && std::isfinite(p.local))) return bad("local must be a finite number >= 0");
  if (!(p.epsilon > 0 && p.epsilon <= 1)) return bad("epsilon must be in (0, 1]");
  if (p.max_elements < 1 || p.max_elements > 64) return bad("max elements (K) must be between 1 and 64");
  if (!(p.scale >= 0 && std::isfinite(p.scale))) return bad("scale h must be >= 0 (0 = mean cage edge length)");
  if (!(p.max_distance >= 0 && std::isfinite(p.max_distance))) return bad("max distance must be >= 0 (0 = none)");
  if (!(p.close_distance > 0 && std::isfinite(p.close_distance))) return bad("close distance must be > 0");
  return Ok{};
}

size_t Binding::bytes() const {
  return offsets.size() * 4 + ids.size() * 4 + weights.size() * 4 + bary.size() * 4 + rigid_points.size() * 4 +
         rigid_element.size() * 4 + rigid_bary.size() * 4;
}

namespace {
// d^local, by repeated squaring when local is a small whole number (the usual case).
double power(double d, double local) {
  const double whole = std::floor(local);
  if (whole == local && local <= 32) {
    double result = 1.0, base = d;
    for (unsigned e = static_cast<unsigned>(local); e; e >>= 1, base *= base)
      if (e & 1) result *= base;
    return result;
  }
  return std::pow(d, local);
}
}  // namespace

double falloff(double d, double local) { return 1.0 / (1.0 + power(d, local)); }

double threshold_radius(double d_min, double local, double epsilon) {
  if (epsilon >= 1.0) return d_min;
  if (local <= 0.0) return 1e300;  // constant weights: every element passes
  double r = std::pow((1.0 + power(d_min, local)) / epsilon - 1.0, 1.0 / local);
  return std::max(r, d_min);  // guards rounding
}

namespace {

// Everything registration shares between the hierarchy and the brute-force loop.
struct Context {
  std::span<const glm::vec3> skin;
  const Cage* cage;
  std::span<const glm::vec3> rest;
  BindParams params;
  double h;
  std::vector<uint8_t> valid;             // #E
  std::vector<uint32_t> valid_ids;
  std::unordered_map<uint32_t, const SetEdit*> edits;
  bool collect_failures = false;  // list the points failing the cage-quality test (quality_failures)
};

struct Chunk {
  std::vector<uint32_t> counts;  // per point: entries in this chunk's stencil
  std::vector<uint32_t> ids;
  std::vector<float> weights;
  std::vector<float> bary;
  std::vector<uint32_t> rigid_points, rigid_element;
  std::vector<float> rigid_bary;
  uint32_t inside = 0, max_set = 0;
  uint64_t total_set = 0;
  std::vector<uint32_t> failed;  // points failing the quality test, when the context collects them
};

bool contains(const std::vector<uint32_t>& v, uint32_t x) { return std::find(v.begin(), v.end(), x) != v.end(); }

ClosestPoint closest_to_element(const Context& ctx, const glm::dvec3& p, uint32_t e) {
  const Tri& t = ctx.cage->elements[e];
  return closest_point_on_triangle(p, glm::dvec3(ctx.rest[t[0]]), glm::dvec3(ctx.rest[t[1]]),
                                   glm::dvec3(ctx.rest[t[2]]));
}

bool projects_inside(const Context& ctx, const glm::dvec3& p, uint32_t e) {
  const Tri& t = ctx.cage->elements[e];
  glm::dvec3 b = plane_barycentric(p, glm::dvec3(ctx.rest[t[0]]), glm::dvec3(ctx.rest[t[1]]),
                                   glm::dvec3(ctx.rest[t[2]]));
  const double tol = -1e-9;
  return b.x >= tol && b.y >= tol && b.z >= tol;
}

// Turns the gathered candidates of one point into its stencil entries.
// `cands` holds every non-excluded valid element within the threshold radius, sorted by distance.
void finish_point(const Context& ctx, uint32_t point, const glm::dvec3& p, std::vector<Candidate>& cands,
                  const SetEdit* edit, Chunk& out) {
  const BindParams& prm = ctx.params;
  if (prm.max_distance > 0) {
    const double md2 = prm.max_distance * prm.max_distance;
    std::erase_if(cands, [&](const Candidate& c) { return c.dist2 > md2; });
  }
  // Taper (decision, see docs/algorithm-notes.md): the weight at which an element would leave the set
  // (the relative threshold, the strongest element left out by K, the max distance) is subtracted from
  // every member's weight, so that elements enter and leave sets at zero weight and the map is
  // continuous in P. `cands` holds up to K + 1 elements: the (K+1)-th only sets the cut.
  double w_cut = 0.0;
  if (!cands.empty()) {
    w_cut = prm.epsilon * falloff(std::sqrt(cands.front().dist2) / ctx.h, prm.local);
    if (cands.size() > prm.max_elements)
      w_cut = std::max(w_cut, falloff(std::sqrt(cands[prm.max_elements].dist2) / ctx.h, prm.local));
    if (prm.max_distance > 0) w_cut = std::max(w_cut, falloff(prm.max_distance / ctx.h, prm.local));
  }
  if (cands.size() > prm.max_elements) cands.resize(prm.max_elements);
  const size_t automatic = cands.size();  // members chosen by the rule; inclusions follow
  if (edit) {
    for (uint32_t e : edit->include) {
      if (!ctx.valid[e]) continue;
      bool present = false;
      for (const auto& c : cands) present = present || c.element == e;
      if (present) continue;
      ClosestPoint cp = closest_to_element(ctx, p, e);
      cands.push_back({e, cp.dist2, cp.bary});
    }
  }

  if (cands.empty()) {
    // Fall back to the nearest valid element (not excluded where possible), followed rigidly.
    uint32_t best = UINT32_MAX;
    ClosestPoint best_cp{};
    best_cp.dist2 = 1e300;
    for (int pass = 0; pass < 2 && best == UINT32_MAX; ++pass) {
      for (uint32_t e : ctx.valid_ids) {
        if (pass == 0 && edit && contains(edit->exclude, e)) continue;
        ClosestPoint cp = closest_to_element(ctx, p, e);
        if (cp.dist2 < best_cp.dist2) {
          best_cp = cp;
          best = e;
        }
      }
    }
    out.counts.push_back(0);
    out.rigid_points.push_back(point);
    out.rigid_element.push_back(best);
    out.rigid_bary.push_back(static_cast<float>(best_cp.bary.y));
    out.rigid_bary.push_back(static_cast<float>(best_cp.bary.z));
    if (std::sqrt(best_cp.dist2) <= prm.close_distance * ctx.h && projects_inside(ctx, p, best))
      ++out.inside;
    else if (ctx.collect_failures)
      out.failed.push_back(point);
    return;
  }

  double sum = 0.0, raw_sum = 0.0;
  double w[128], raw[128];
  const size_t n = std::min<size_t>(cands.size(), 128);
  cands.resize(n);
  for (size_t i = 0; i < n; ++i) {
    raw[i] = falloff(std::sqrt(cands[i].dist2) / ctx.h, prm.local);
    // user inclusions keep their own weight: they are outside the rule by the user's choice
    w[i] = i < automatic ? std::max(raw[i] - w_cut, 0.0) : raw[i];
    sum += w[i];
    raw_sum += raw[i];
  }
  if (!(sum > 1e-12 * raw_sum)) {  // every member sits at the cut (epsilon = 1, ties): no taper
    for (size_t i = 0; i < n; ++i) w[i] = raw[i];
    sum = raw_sum;
  }
  bool inside = false;
  for (size_t i = 0; i < n && !inside; ++i)
    inside = std::sqrt(cands[i].dist2) <= prm.close_distance * ctx.h && projects_inside(ctx, p, cands[i].element);
  out.inside += inside ? 1 : 0;
  if (!inside && ctx.collect_failures) out.failed.push_back(point);
  const auto members = static_cast<uint32_t>(std::count_if(w, w + n, [](double x) { return x > 0.0; }));
  out.max_set = std::max(out.max_set, members);
  out.total_set += members;

  if (prm.variant == Variant::kExtended) {
    // W_j = sum_k u_k b_kj over the corners j of each contributing element
    uint32_t vid[384];
    double vw[384];
    size_t m = 0;
    for (size_t i = 0; i < n; ++i) {
      const Tri& t = ctx.cage->elements[cands[i].element];
      for (int c = 0; c < 3; ++c) {
        double wv = w[i] / sum * cands[i].bary[c];
        if (wv <= 0.0) continue;
        size_t j = 0;
        while (j < m && vid[j] != t[static_cast<size_t>(c)]) ++j;
        if (j == m) {
          vid[m] = t[static_cast<size_t>(c)];
          vw[m++] = 0.0;
        }
        vw[j] += wv;
      }
    }
    double total = 0.0;
    for (size_t j = 0; j < m; ++j) total += vw[j];
    for (size_t j = 0; j < m; ++j) {
      out.ids.push_back(vid[j]);
      out.weights.push_back(static_cast<float>(vw[j] / total));
    }
    out.counts.push_back(static_cast<uint32_t>(m));
    return;
  }
  uint32_t kept = 0;
  for (size_t i = 0; i < n; ++i) {
    if (w[i] <= 0.0) continue;  // at the cut: contributes nothing
    ++kept;
    out.ids.push_back(cands[i].element);
    out.weights.push_back(static_cast<float>(w[i] / sum));
    if (prm.variant == Variant::kClamped) {
      out.bary.push_back(static_cast<float>(cands[i].bary.y));
      out.bary.push_back(static_cast<float>(cands[i].bary.z));
    }
  }
  out.counts.push_back(kept);
}

Result<Context> make_context(std::span<const glm::vec3> skin, const Cage& cage, std::span<const glm::vec3> rest,
                             const BindParams& params, std::span<const SetEdit> edits,
                             std::vector<ElementStatus>& status) {
  auto v = validate(params);
  if (!v) return v.error();
  if (skin.empty()) return make_error(ErrorCode::kEmpty, "the skin has no vertices");
  if (rest.size() != cage.num_vertices())
    return make_error(ErrorCode::kTopologyMismatch, "the cage has " + std::to_string(cage.num_vertices()) +
                                                        " vertices but " + std::to_string(rest.size()) +
                                                        " positions were given");
  for (size_t i = 0; i < skin.size(); ++i)
    if (!std::isfinite(skin[i].x) || !std::isfinite(skin[i].y) || !std::isfinite(skin[i].z))
      return make_error(ErrorCode::kNonFinite, "skin vertex " + std::to_string(i) + " has a non-finite coordinate");
  Context ctx;
  ctx.skin = skin;
  ctx.cage = &cage;
  ctx.rest = rest;
  ctx.params = params;
  status = classify_elements(cage, rest);
  ctx.valid.resize(status.size());
  for (size_t e = 0; e < status.size(); ++e) {
    ctx.valid[e] = status[e] == ElementStatus::kValid;
    if (ctx.valid[e]) ctx.valid_ids.push_back(static_cast<uint32_t>(e));
  }
  if (ctx.valid_ids.empty())
    return make_error(ErrorCode::kNoValidElements,
                      "the cage has no valid element: all " + std::to_string(status.size()) +
                          " triangles are zero-area, non-finite or duplicates");
  PolyMesh rest_mesh = cage.polygons;
  rest_mesh.positions.assign(rest.begin(), rest.end());
  ctx.h = params.scale > 0 ? params.scale : mean_edge_length(rest_mesh);
  if (!(ctx.h > 0) || !std::isfinite(ctx.h))
    return make_error(ErrorCode::kInvalidArgument, "the cage's mean edge length is zero; give a scale h");
  for (const SetEdit& e : edits) {
    if (e.point >= skin.size())
      return make_error(ErrorCode::kIndexOutOfRange, "set edit names point " + std::to_string(e.point) +
                                                         " but the skin has " + std::to_string(skin.size()) +
                                                         " points");
    for (const auto* list : {&e.exclude, &e.include})
      for (uint32_t k : *list)
        if (k >= cage.num_elements())
          return make_error(ErrorCode::kIndexOutOfRange,
                            "set edit of point " + std::to_string(e.point) + " names element " + std::to_string(k) +
                                " but the cage has " + std::to_string(cage.num_elements()) + " elements");
    ctx.edits[e.point] = &e;
  }
  return ctx;
}

// Orders points along a Morton curve so that chunks of consecutive entries are spatially compact.
std::vector<uint32_t> morton_order(std::span<const glm::vec3> pts) {
  Aabb box = bounding_box(pts);
  glm::dvec3 ext = glm::max(box.hi - box.lo, glm::dvec3(1e-30));
  auto spread = [](uint64_t x) {  // 21 bits -> every third bit
    x &= 0x1fffff;
    x = (x | x << 32) & 0x1f00000000ffffULL;
    x = (x | x << 16) & 0x1f0000ff0000ffULL;
    x = (x | x << 8) & 0x100f00f00f00f00fULL;
    x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
    x = (x | x << 2) & 0x1249249249249249ULL;
    return x;
  };
  std::vector<std::pair<uint64_t, uint32_t>> keys(pts.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, pts.size(), 16384), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      glm::dvec3 q = (glm::dvec3(pts[i]) - box.lo) / ext * 2097151.0;
      uint64_t code = spread(uint64_t(q.x)) | spread(uint64_t(q.y)) << 1 | spread(uint64_t(q.z)) << 2;
      keys[i] = {code, static_cast<uint32_t>(i)};
    }
  });
  tbb::parallel_sort(keys.begin(), keys.end());
  std::vector<uint32_t> order(pts.size());
  for (size_t i = 0; i < keys.size(); ++i) order[i] = keys[i].second;
  return order;
}

// `make_source(ctx)` returns a factory of per-thread candidate sources with
//   prepare(ctx, chunk_points)                  once per spatially compact chunk, and
//   gather(ctx, p, edit, out)                   per point: every non-excluded valid element within
//                                               the threshold radius, sorted by distance.
template <class MakeSource>
Result<Binding> run_registration(std::span<const glm::vec3> skin, const Cage& cage, std::span<const glm::vec3> rest,
                                 const BindParams& params, std::span<const SetEdit> edits,
                                 const BindProgress& progress, MakeSource make_source,
                                 std::vector<uint32_t>* failures = nullptr) {
  auto t0 = std::chrono::steady_clock::now();
  std::vector<ElementStatus> status;
  auto ctx_r = make_context(skin, cage, rest, params, edits, status);
  if (!ctx_r) return ctx_r.error();
  ctx_r.value().collect_failures = failures != nullptr;
  const Context& ctx = ctx_r.value();
  auto new_source = make_source(ctx);

  constexpr size_t kChunk = 128;
  const size_t n = skin.size();
  const std::vector<uint32_t> order = morton_order(skin);
  const size_t num_chunks = (n + kChunk - 1) / kChunk;
  std::vector<Chunk> chunks(num_chunks);
  std::atomic<size_t> done{0};
  std::atomic<bool> cancelled{false};
  const size_t report_every = std::max<size_t>(1, num_chunks / 200);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, num_chunks, 8), [&](const tbb::blocked_range<size_t>& r) {
    std::vector<Candidate> cands;
    auto source = new_source();
    for (size_t c = r.begin(); c != r.end(); ++c) {
      if (cancelled.load(std::memory_order_relaxed)) return;
      if (progress.cancel && progress.cancel->load(std::memory_order_relaxed)) {
        cancelled = true;
        return;
      }
      Chunk& out = chunks[c];
      std::span<const uint32_t> pts(order.data() + c * kChunk, std::min(n, (c + 1) * kChunk) - c * kChunk);
      source.prepare(ctx, pts);
      out.counts.reserve(pts.size());
      for (uint32_t i : pts) {
        auto it = ctx.edits.empty() ? ctx.edits.end() : ctx.edits.find(i);
        const SetEdit* edit = it == ctx.edits.end() ? nullptr : it->second;
        glm::dvec3 p(skin[i]);
        source.gather(ctx, p, edit, cands);
        finish_point(ctx, i, p, cands, edit, out);
      }
      size_t d = done.fetch_add(1) + 1;
      if (progress.on_progress && (d % report_every == 0 || d == num_chunks)) progress.on_progress(double(d) / num_chunks);
    }
  });
  if (cancelled) return make_error(ErrorCode::kCancelled, "bind cancelled");

  Binding b;
  b.params = params;
  b.h = ctx.h;
  b.origin = bounding_box(skin).center();
  b.num_points = static_cast<uint32_t>(n);
  b.num_cage_vertices = static_cast<uint32_t>(cage.num_vertices());
  b.rest_cage.assign(rest.begin(), rest.end());
  b.elements = cage.elements;
  b.element_status = status;
  for (size_t e = 0; e < status.size(); ++e)
    if (status[e] != ElementStatus::kValid) b.invalid_elements.push_back(static_cast<uint32_t>(e));

  // chunks hold points in Morton order: count per point, prefix-sum, then scatter back to point order
  b.offsets.assign(n + 1, 0);
  for (size_t c = 0; c < num_chunks; ++c) {
    const auto& ch = chunks[c];
    for (size_t k = 0; k < ch.counts.size(); ++k) b.offsets[order[c * kChunk + k] + 1] = ch.counts[k];
  }
  for (size_t i = 0; i < n; ++i) b.offsets[i + 1] += b.offsets[i];
  const size_t total = b.offsets[n];
  const bool clamped = params.variant == Variant::kClamped;
  b.ids.resize(total);
  b.weights.resize(total);
  if (clamped) b.bary.resize(2 * total);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, num_chunks, 16), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t c = r.begin(); c != r.end(); ++c) {
      Chunk& ch = chunks[c];
      size_t src = 0;
      for (size_t k = 0; k < ch.counts.size(); ++k) {
        const uint32_t dst = b.offsets[order[c * kChunk + k]];
        for (uint32_t j = 0; j < ch.counts[k]; ++j, ++src) {
          b.ids[dst + j] = ch.ids[src];
          b.weights[dst + j] = ch.weights[src];
          if (clamped) {
            b.bary[2 * (dst + j)] = ch.bary[2 * src];
            b.bary[2 * (dst + j) + 1] = ch.bary[2 * src + 1];
          }
        }
      }
      std::vector<uint32_t>().swap(ch.ids);  // release as we go
      std::vector<float>().swap(ch.weights);
      std::vector<float>().swap(ch.bary);
    }
  });
  std::vector<std::array<uint32_t, 2>> rigid;  // (point, index into the chunk's rigid list) for sorting
  for (auto& ch : chunks) {
    for (size_t k = 0; k < ch.rigid_points.size(); ++k) {
      b.rigid_points.push_back(ch.rigid_points[k]);
      b.rigid_element.push_back(ch.rigid_element[k]);
      b.rigid_bary.push_back(ch.rigid_bary[2 * k]);
      b.rigid_bary.push_back(ch.rigid_bary[2 * k + 1]);
    }
    b.quality_inside += ch.inside;
    if (failures) failures->insert(failures->end(), ch.failed.begin(), ch.failed.end());
    b.max_set_size = std::max(b.max_set_size, ch.max_set);
    b.total_set_size += ch.total_set;
  }
  // fallback points in point order (deterministic whatever the scheduling)
  std::vector<uint32_t> perm(b.rigid_points.size());
  for (size_t i = 0; i < perm.size(); ++i) perm[i] = static_cast<uint32_t>(i);
  std::sort(perm.begin(), perm.end(), [&](uint32_t x, uint32_t y) { return b.rigid_points[x] < b.rigid_points[y]; });
  Binding sorted_rigid;
  for (uint32_t k : perm) {
    sorted_rigid.rigid_points.push_back(b.rigid_points[k]);
    sorted_rigid.rigid_element.push_back(b.rigid_element[k]);
    sorted_rigid.rigid_bary.push_back(b.rigid_bary[2 * k]);
    sorted_rigid.rigid_bary.push_back(b.rigid_bary[2 * k + 1]);
  }
  b.rigid_points = std::move(sorted_rigid.rigid_points);
  b.rigid_element = std::move(sorted_rigid.rigid_element);
  b.rigid_bary = std::move(sorted_rigid.rigid_bary);
  if (failures) std::sort(failures->begin(), failures->end());
  b.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return b;
}

}  // namespace

namespace {

// Candidates for a chunk of nearby points: the elements any of them could reach, found once with the
// hierarchy, then a tight loop per point with box rejection.
class ChunkedBvhSource {
 public:
  explicit ChunkedBvhSource(const ElementBvh& bvh) : bvh_(bvh) {}
  void prepare(const Context& ctx, std::span<const uint32_t> pts) {
    Aabb box;
    for (uint32_t i : pts) box.extend(glm::dvec3(ctx.skin[i]));
    const glm::dvec3 c = box.center();
    const double half = 0.5 * box.diagonal();
    // any point p of the chunk has d_min(p) <= d_min(c) + half, and its elements lie within
    // radius(d_min(p)) of p, hence within radius(d_min(c) + half) + half of c
    const double dc = bvh_.nearest_distance(c);
    const double reach = ctx.h * threshold_radius((dc + half) / ctx.h, ctx.params.local, ctx.params.epsilon) + half;
    bvh_.boxes_within(c, reach, elems_);
    keys_.resize(elems_.size());
    order_.resize(elems_.size());
    for (size_t i = 0; i < elems_.size(); ++i) {
      keys_[i] = std::sqrt(ElementBvh::box_dist2(c, elems_[i].lo, elems_[i].hi)) - half;
      order_[i] = static_cast<uint32_t>(i);
    }
    std::sort(order_.begin(), order_.end(), [&](uint32_t x, uint32_t y) { return keys_[x] < keys_[y]; });
    sorted_.resize(elems_.size());
    sorted_keys_.resize(elems_.size());
    for (size_t i = 0; i < order_.size(); ++i) {
      sorted_[i] = elems_[order_[i]];
      sorted_keys_[i] = keys_[order_[i]];
    }
  }
  void gather(const Context& ctx, const glm::dvec3& p, const SetEdit* edit, std::vector<Candidate>& out) const {
    out.clear();
    const double h = ctx.h, local = ctx.params.local, eps = ctx.params.epsilon;
    // Only the K nearest elements within the threshold radius survive, so once K are known the
    // K-th distance bounds the search too (ties are kept: the final order breaks them by id).
    const size_t k = ctx.params.max_elements + 1;  // the (K+1)-th sets the taper's cut
    auto closer = [](const Candidate& x, const Candidate& y) {
      return x.dist2 < y.dist2 || (x.dist2 == y.dist2 && x.element < y.element);
    };
    double best2 = 1e300, radius2 = 1e300, kth2 = 1e300;
    for (size_t i = 0; i < sorted_.size(); ++i) {
      const double bound2 = std::min(radius2, kth2);
      // keys are lower bounds of the distance from any point of the chunk: the rest are farther
      if (sorted_keys_[i] > 0 && sorted_keys_[i] * sorted_keys_[i] > bound2) break;
      const auto& e = sorted_[i];
      if (ElementBvh::box_dist2(p, e.lo, e.hi) > bound2) continue;
      if (edit && contains(edit->exclude, e.id)) continue;
      ClosestPoint cp = closest_point_on_triangle(p, e.a, e.b, e.c);
      if (cp.dist2 > bound2) continue;
      out.push_back({e.id, cp.dist2, cp.bary});
      if (cp.dist2 < best2) {
        best2 = cp.dist2;
        double r = h * threshold_radius(std::sqrt(best2) / h, local, eps);
        radius2 = std::max(r * r, best2);
      }
      if (out.size() >= 2 * k) {
        std::nth_element(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(k - 1), out.end(), closer);
        kth2 = out[k - 1].dist2;
        out.erase(std::remove_if(out.begin() + static_cast<std::ptrdiff_t>(k), out.end(),
                                 [&](const Candidate& x) { return x.dist2 > kth2; }),
                  out.end());
      }
    }
    std::erase_if(out, [&](const Candidate& x) { return x.dist2 > radius2; });
    std::sort(out.begin(), out.end(), closer);
  }

 private:
  const ElementBvh& bvh_;
  std::vector<ElementBvh::Element> elems_, sorted_;
  std::vector<double> keys_, sorted_keys_;  // distance from the chunk centre minus the chunk's half size
  std::vector<uint32_t> order_;
};

// Reference: every valid element for every point, no pruning.
struct BruteForceSource {
  void prepare(const Context&, std::span<const uint32_t>) {}
  void gather(const Context& ctx, const glm::dvec3& p, const SetEdit* edit, std::vector<Candidate>& out) const {
    out.clear();
    double best = 1e300;
    for (uint32_t e : ctx.valid_ids) {
      if (edit && contains(edit->exclude, e)) continue;
      ClosestPoint cp = closest_to_element(ctx, p, e);
      out.push_back({e, cp.dist2, cp.bary});
      best = std::min(best, cp.dist2);
    }
    double r = ctx.h * threshold_radius(std::sqrt(best) / ctx.h, ctx.params.local, ctx.params.epsilon);
    const double bound2 = std::max(r * r, best);
    std::erase_if(out, [&](const Candidate& c) { return c.dist2 > bound2; });
    std::sort(out.begin(), out.end(), [](const Candidate& x, const Candidate& y) {
      return x.dist2 < y.dist2 || (x.dist2 == y.dist2 && x.element < y.element);
    });
  }
};

}  // namespace

Result<Binding> bind_skin(std::span<const glm::vec3> skin, const Cage& cage, std::span<const glm::vec3> rest,
                          const BindParams& params, std::span<const SetEdit> edits, const BindProgress& progress) {
  std::unique_ptr<ElementBvh> bvh;
  auto make_source = [&bvh](const Context& ctx) {
    bvh = std::make_unique<ElementBvh>(ctx.rest, ctx.cage->elements, ctx.valid_ids);
    return [tree = bvh.get()] { return ChunkedBvhSource(*tree); };
  };
  return run_registration(skin, cage, rest, params, edits, progress, make_source);
}

Result<Binding> bind_skin_brute_force(std::span<const glm::vec3> skin, const Cage& cage,
                                      std::span<const glm::vec3> rest, const BindParams& params,
                                      std::span<const SetEdit> edits) {
  auto make_source = [](const Context&) { return [] { return BruteForceSource{}; }; };
  return run_registration(skin, cage, rest, params, edits, {}, make_source);
}

Result<std::vector<uint32_t>> quality_failures(const Binding& binding, std::span<const glm::vec3> skin,
                                               std::span<const SetEdit> edits) {
  if (skin.size() != binding.num_points)
    return make_error(ErrorCode::kTopologyMismatch, "the binding has " + std::to_string(binding.num_points) +
                                                        " points but the skin has " + std::to_string(skin.size()));
  // The binding's reference cage as its control elements, with the distance scale it used: the
  // registration below then sees exactly the elements, sets and closeness the binding saw.
  Cage cage;
  cage.polygons.positions = binding.rest_cage;
  for (const Tri& t : binding.elements) cage.polygons.add_face({t[0], t[1], t[2]});
  cage.elements = binding.elements;
  cage.element_face.resize(binding.elements.size());
  for (uint32_t e = 0; e < cage.element_face.size(); ++e) cage.element_face[e] = e;
  BindParams params = binding.params;
  params.scale = binding.h;
  std::vector<uint32_t> failures;
  std::unique_ptr<ElementBvh> bvh;
  auto make_source = [&bvh](const Context& ctx) {
    bvh = std::make_unique<ElementBvh>(ctx.rest, ctx.cage->elements, ctx.valid_ids);
    return [tree = bvh.get()] { return ChunkedBvhSource(*tree); };
  };
  auto b = run_registration(skin, cage, binding.rest_cage, params, edits, {}, make_source, &failures);
  if (!b) return b.error();
  return failures;
}

}  // namespace cagewrap
