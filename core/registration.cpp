#include "core/registration.h"

#include <algorithm>
#include <chrono>
#include <memory>
#include <cmath>
#include <unordered_map>

#include <tbb/parallel_for.h>

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

double falloff(double d, double local) { return 1.0 / (1.0 + std::pow(d, local)); }

double threshold_radius(double d_min, double local, double epsilon) {
  if (epsilon >= 1.0) return d_min;
  if (local <= 0.0) return 1e300;  // constant weights: every element passes
  double r = std::pow((1.0 + std::pow(d_min, local)) / epsilon - 1.0, 1.0 / local);
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
  if (cands.size() > prm.max_elements) cands.resize(prm.max_elements);
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
    if (std::sqrt(best_cp.dist2) <= prm.close_distance * ctx.h && projects_inside(ctx, p, best)) ++out.inside;
    return;
  }

  double sum = 0.0;
  double w[128];
  const size_t n = std::min<size_t>(cands.size(), 128);
  cands.resize(n);
  for (size_t i = 0; i < n; ++i) {
    w[i] = falloff(std::sqrt(cands[i].dist2) / ctx.h, prm.local);
    sum += w[i];
  }
  bool inside = false;
  for (size_t i = 0; i < n && !inside; ++i)
    inside = std::sqrt(cands[i].dist2) <= prm.close_distance * ctx.h && projects_inside(ctx, p, cands[i].element);
  out.inside += inside ? 1 : 0;
  out.max_set = std::max<uint32_t>(out.max_set, static_cast<uint32_t>(n));
  out.total_set += n;

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
  for (size_t i = 0; i < n; ++i) {
    out.ids.push_back(cands[i].element);
    out.weights.push_back(static_cast<float>(w[i] / sum));
    if (prm.variant == Variant::kClamped) {
      out.bary.push_back(static_cast<float>(cands[i].bary.y));
      out.bary.push_back(static_cast<float>(cands[i].bary.z));
    }
  }
  out.counts.push_back(static_cast<uint32_t>(n));
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

// `make_gather(ctx)` returns the candidate search for one point: f(ctx, p, edit, out).
template <class MakeGather>
Result<Binding> run_registration(std::span<const glm::vec3> skin, const Cage& cage, std::span<const glm::vec3> rest,
                                 const BindParams& params, std::span<const SetEdit> edits,
                                 const BindProgress& progress, MakeGather make_gather) {
  auto t0 = std::chrono::steady_clock::now();
  std::vector<ElementStatus> status;
  auto ctx_r = make_context(skin, cage, rest, params, edits, status);
  if (!ctx_r) return ctx_r.error();
  const Context& ctx = ctx_r.value();
  auto gather = make_gather(ctx);

  constexpr size_t kChunk = 2048;
  const size_t n = skin.size();
  const size_t num_chunks = (n + kChunk - 1) / kChunk;
  std::vector<Chunk> chunks(num_chunks);
  std::atomic<size_t> done{0};
  std::atomic<bool> cancelled{false};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, num_chunks, 1), [&](const tbb::blocked_range<size_t>& r) {
    std::vector<Candidate> cands;
    for (size_t c = r.begin(); c != r.end(); ++c) {
      if (cancelled.load(std::memory_order_relaxed)) return;
      if (progress.cancel && progress.cancel->load(std::memory_order_relaxed)) {
        cancelled = true;
        return;
      }
      Chunk& out = chunks[c];
      size_t end = std::min(n, (c + 1) * kChunk);
      out.counts.reserve(end - c * kChunk);
      for (size_t i = c * kChunk; i < end; ++i) {
        auto it = ctx.edits.find(static_cast<uint32_t>(i));
        const SetEdit* edit = it == ctx.edits.end() ? nullptr : it->second;
        glm::dvec3 p(skin[i]);
        gather(ctx, p, edit, cands);
        finish_point(ctx, static_cast<uint32_t>(i), p, cands, edit, out);
      }
      size_t d = done.fetch_add(1) + 1;
      if (progress.on_progress) progress.on_progress(double(d) / double(num_chunks));
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
  size_t total = 0;
  for (const auto& ch : chunks) total += ch.ids.size();
  b.offsets.reserve(n + 1);
  b.ids.reserve(total);
  b.weights.reserve(total);
  b.offsets.push_back(0);
  for (auto& ch : chunks) {
    for (uint32_t cnt : ch.counts) b.offsets.push_back(b.offsets.back() + cnt);
    b.ids.insert(b.ids.end(), ch.ids.begin(), ch.ids.end());
    b.weights.insert(b.weights.end(), ch.weights.begin(), ch.weights.end());
    b.bary.insert(b.bary.end(), ch.bary.begin(), ch.bary.end());
    b.rigid_points.insert(b.rigid_points.end(), ch.rigid_points.begin(), ch.rigid_points.end());
    b.rigid_element.insert(b.rigid_element.end(), ch.rigid_element.begin(), ch.rigid_element.end());
    b.rigid_bary.insert(b.rigid_bary.end(), ch.rigid_bary.begin(), ch.rigid_bary.end());
    b.quality_inside += ch.inside;
    b.max_set_size = std::max(b.max_set_size, ch.max_set);
    b.total_set_size += ch.total_set;
    ch = Chunk{};  // release as we go: peak memory stays near one copy of the table
  }
  b.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return b;
}

}  // namespace

Result<Binding> bind_skin(std::span<const glm::vec3> skin, const Cage& cage, std::span<const glm::vec3> rest,
                     const BindParams& params, std::span<const SetEdit> edits, const BindProgress& progress) {
  std::unique_ptr<ElementBvh> bvh;
  auto make_gather = [&bvh](const Context& ctx) {
    bvh = std::make_unique<ElementBvh>(ctx.rest, ctx.cage->elements, ctx.valid_ids);
    return [tree = bvh.get()](const Context& c, const glm::dvec3& p, const SetEdit* edit,
                              std::vector<Candidate>& out) {
      const double h = c.h, local = c.params.local, eps = c.params.epsilon;
      auto radius = [=](double d) { return h * threshold_radius(d / h, local, eps); };
      if (edit && !edit->exclude.empty())
        tree->within_adaptive_radius(p, radius, [edit](uint32_t e) { return contains(edit->exclude, e); }, out);
      else
        tree->within_adaptive_radius(p, radius, [](uint32_t) { return false; }, out);
    };
  };
  return run_registration(skin, cage, rest, params, edits, progress, make_gather);
}

Result<Binding> bind_skin_brute_force(std::span<const glm::vec3> skin, const Cage& cage, std::span<const glm::vec3> rest,
                                 const BindParams& params, std::span<const SetEdit> edits) {
  auto make_gather = [](const Context&) {
    return [](const Context& ctx, const glm::dvec3& p, const SetEdit* edit, std::vector<Candidate>& out) {
      out.clear();
      double best = 1e300;
      for (uint32_t e : ctx.valid_ids) {
        if (edit && contains(edit->exclude, e)) continue;
        ClosestPoint cp = closest_to_element(ctx, p, e);
        out.push_back({e, cp.dist2, cp.bary});
        best = std::min(best, cp.dist2);
      }
      double r = ctx.h * threshold_radius(std::sqrt(best) / ctx.h, ctx.params.local, ctx.params.epsilon);
      std::erase_if(out, [&](const Candidate& c) { return c.dist2 > r * r; });
      std::sort(out.begin(), out.end(), [](const Candidate& x, const Candidate& y) {
        return x.dist2 < y.dist2 || (x.dist2 == y.dist2 && x.element < y.element);
      });
    };
  };
  return run_registration(skin, cage, rest, params, edits, {}, make_gather);
}

}  // namespace cagewrap
