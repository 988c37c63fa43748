#include "core/deform/registration.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <numeric>
#include <optional>
#include <unordered_map>

#include <glm/vec2.hpp>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include "core/base/check.h"
#include "core/geometry/element_bvh.h"
#include "core/geometry/geometry.h"
#include "core/deform/set_editing.h"

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

Status check_skin(std::span<const glm::vec3> skin) {
  if (skin.empty()) return make_error(ErrorCode::kEmpty, "the skin has no vertices");
  for (size_t i = 0; i < skin.size(); ++i)
    if (!std::isfinite(skin[i].x) || !std::isfinite(skin[i].y) || !std::isfinite(skin[i].z))
      return make_error(ErrorCode::kNonFinite, "skin vertex " + std::to_string(i) + " has a non-finite coordinate");
  return Ok{};
}

Status validate(const BindParams& p) {
  auto bad = [](const std::string& m) { return make_error(ErrorCode::kInvalidArgument, m); };
  if (!(p.local >= 0 && std::isfinite(p.local))) return bad("local must be a finite number >= 0");
  if (!(p.epsilon > 0 && p.epsilon <= 1)) return bad("epsilon must be in (0, 1]");
  if (p.max_elements < 1 || p.max_elements > 64) return bad("max elements (K) must be between 1 and 64");
  if (!(p.scale >= 0 && std::isfinite(p.scale))) return bad("scale h must be >= 0 (0 = mean cage edge length)");
  if (!(p.max_distance >= 0 && std::isfinite(p.max_distance))) return bad("max distance must be >= 0 (0 = none)");
  if (!(p.close_distance > 0 && std::isfinite(p.close_distance))) return bad("close distance must be > 0");
  if (p.separation_steps > 64) return bad("separation steps must be between 0 and 64");
  return Ok{};
}

size_t Binding::bytes() const {
  return offsets.size() * 4 + ids.size() * 4 + weights.size() * 4 + bary.size() * 4 + rigid_points.size() * 4 +
         rigid_element.size() * 4 + rigid_bary.size() * 4;
}

bool SetEdit::excludes(uint32_t e) const {
  const bool included = std::binary_search(include.begin(), include.end(), e);
  return only ? !included : std::binary_search(exclude.begin(), exclude.end(), e) && !included;
}

Binding::SetsView Binding::sets() const {
  if (params.variant == Variant::kExtended) return {set_offsets, set_ids, set_weights};
  return {offsets, ids, weights};
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

Taper::Taper(const BindParams& prm, double h, std::span<const double> dist) : dist_(dist), local_(prm.local) {
  if (dist.empty()) return;
  d1_ = dist.front();
  // the scale max(1, d_1^local): beyond d_1 = 1 every p is taken relative to d_1^local, so that no
  // member's p overflows whatever `local` (they are within a few times d_1's weight)
  scaled_ = d1_ > 1.0 && local_ > 0.0;
  u_ = scaled_ ? power(1.0 / d1_, local_) : 1.0;  // 1 / scale
  const double r1 = ratio(d1_);
  double q = (u_ + r1) / prm.epsilon - u_;  // the relative threshold: epsilon f(d_1)
  // the tie band: p up to (1 + kTieBand) times the nearest's (and a floor of kTieFloor h for skin on the cage)
  const double tie = (1.0 + kTieBand) * r1 + kTieBand * (scaled_ ? power(kTieFloor / d1_, local_) : power(kTieFloor, local_));
  // the strongest element left out by K, and the max distance: never above the tie band's cut
  double out = dist.size() > prm.max_elements ? ratio(dist[prm.max_elements]) : std::numeric_limits<double>::infinity();
  if (prm.max_distance > 0) out = std::min(out, ratio(prm.max_distance / h));
  q = std::min(q, std::max(out, tie));
  if (dist.size() > kMaxTiedMembers) q = std::min(q, ratio(dist[kMaxTiedMembers]));
  q_ = q;
}

double Taper::ratio(double d) const { return scaled_ ? power(d / d1_, local_) : power(d, local_); }

double Taper::weight(size_t i) const {
  const double r = ratio(dist_[i]);
  if (!(r < q_)) return 0.0;  // at or beyond the cut (an overflowed r too)
  return (q_ - r) / ((u_ + r) * (u_ + q_));
}

double Taper::weights(std::span<double> w) const {
  CAGEWRAP_CHECK(w.size() == dist_.size(), "one weight per candidate");
  double sum = 0.0;
  for (size_t i = 0; i < w.size(); ++i) sum += (w[i] = weight(i));
  return sum;
}

double Taper::raw(double d) const { return 1.0 / (u_ + ratio(d)); }

double tie_band2(const BindParams& prm, double h, double best2) {
  const double l = prm.local, d1 = std::sqrt(best2) / h;
  if (!(l > 0)) return std::numeric_limits<double>::infinity();  // constant weights: every element ties
  // d^l = (1 + a) d1^l + a floor^l, factored by the larger of d1 and the floor (no overflow)
  const double r = d1 > kTieFloor ? d1 * std::pow(1.0 + kTieBand + kTieBand * power(kTieFloor / d1, l), 1.0 / l)
                                  : kTieFloor * std::pow((1.0 + kTieBand) * power(d1 / kTieFloor, l) + kTieBand, 1.0 / l);
  return std::max(h * h * r * r, best2);
}

namespace {
// needed_radius2, with the tie band's squared radius kept in `band2` (< 0: not known yet; computed
// when needed)
double needed_radius2_band(const BindParams& prm, double h, double best2, double next2, double last2, double radius2,
                           double& band2) {
  const double md2 = prm.max_distance > 0 ? prm.max_distance * prm.max_distance : std::numeric_limits<double>::infinity();
  const double out2 = std::min(next2, md2);  // K or fewer candidates and no max distance: the threshold radius
  if (!std::isfinite(out2)) return radius2;
  if (band2 < 0) band2 = tie_band2(prm, h, best2);
  return std::min({radius2, std::max(out2, band2), last2});
}
}  // namespace

double needed_radius2(const BindParams& prm, double h, double best2, double next2, double last2, double radius2) {
  double band2 = -1.0;
  return needed_radius2_band(prm, h, best2, next2, last2, radius2, band2);
}

double threshold_radius(double d_min, double local, double epsilon) {
  if (epsilon >= 1.0) return d_min;
  if (local <= 0.0) return 1e300;  // constant weights: every element passes
  double r = std::pow((1.0 + power(d_min, local)) / epsilon - 1.0, 1.0 / local);
  return std::max(r, d_min);  // guards rounding
}

namespace {

// The cage-quality test for one element of a point's set (algorithm.md section 4): close to it and
// projecting inside it. Registration and well_bound() share it, so the figure is a function of the table.
bool close_and_inside(std::span<const glm::vec3> rest, const Tri& t, const glm::dvec3& p, double dist2, double limit) {
  if (!(std::sqrt(dist2) <= limit)) return false;
  glm::dvec3 b = plane_barycentric(p, glm::dvec3(rest[t[0]]), glm::dvec3(rest[t[1]]), glm::dvec3(rest[t[2]]));
  const double tol = -1e-9;
  return b.x >= tol && b.y >= tol && b.z >= tol;
}

ClosestPoint closest_on(std::span<const glm::vec3> rest, const Tri& t, const glm::dvec3& p) {
  return closest_point_on_triangle(p, glm::dvec3(rest[t[0]]), glm::dvec3(rest[t[1]]), glm::dvec3(rest[t[2]]));
}

}  // namespace

bool well_bound(const Binding& b, std::span<const glm::vec3> skin, uint32_t point) {
  CAGEWRAP_CHECK(point < b.num_points && skin.size() == b.num_points, "a point of the bound skin");
  const glm::dvec3 p(skin[point]);
  const double limit = b.params.close_distance * b.h;
  const Binding::SetsView sets = b.sets();
  if (sets.offsets.size() == size_t(b.num_points) + 1) {
    for (uint32_t e : sets.of(point)) {
      const Tri& t = b.elements[e];
      if (close_and_inside(b.rest_cage, t, p, closest_on(b.rest_cage, t, p).dist2, limit)) return true;
    }
  }
  auto it = std::lower_bound(b.rigid_points.begin(), b.rigid_points.end(), point);
  if (it != b.rigid_points.end() && *it == point) {
    const Tri& t = b.elements[b.rigid_element[static_cast<size_t>(it - b.rigid_points.begin())]];
    return close_and_inside(b.rest_cage, t, p, closest_on(b.rest_cage, t, p).dist2, limit);
  }
  return false;
}

namespace {

constexpr uint32_t kUnlabelled = PartLabels::kUnlabelled;

// Everything registration shares between the hierarchy and the brute-force loop, built once per
// skin, cage, parameters and labels.
struct Context {
  std::span<const glm::vec3> skin;
  const Cage* cage;
  std::span<const glm::vec3> rest;
  BindParams params;
  double h;
  std::vector<ElementStatus> status;  // #E
  std::vector<uint8_t> valid;         // #E
  std::vector<uint32_t> valid_ids;
  // automatic separation: labels renumbered densely over those in use
  bool separate = false;
  std::vector<uint32_t> point_label;                   // #P dense label or kUnlabelled
  std::vector<std::array<uint32_t, 3>> element_label;  // #E dense labels of the corners
  uint32_t num_labels = 0;
  std::vector<uint8_t> connected;  // num_labels x num_labels
  std::vector<uint8_t> element_bridge;  // #E: corners on unrelated parts (drives only points related to all)
  std::vector<uint32_t> point_shell;    // #P owning cage shell (kUnlabelled: any) or empty
  std::vector<uint32_t> element_shell;  // #E shell of each element (with point_shell)

  // Whether element e may drive the point (always, without separation).
  bool allowed(uint32_t point, uint32_t e) const {
    if (!separate) return true;
    if (!point_shell.empty() && point_shell[point] != kUnlabelled && element_shell[e] != point_shell[point]) return false;
    const uint32_t lp = point_label[point];
    if (lp == kUnlabelled) return true;
    const uint8_t* row = connected.data() + size_t(lp) * num_labels;
    if (element_bridge[e]) {
      for (uint32_t l : element_label[e])
        if (l != kUnlabelled && !row[l]) return false;
      return true;
    }
    for (uint32_t l : element_label[e])
      if (l == kUnlabelled || row[l]) return true;
    return false;
  }
  double close_limit() const { return params.close_distance * h; }
};

// The set edits of a registration, canonical (set_editing.h), by point.
struct Edits {
  std::vector<SetEdit> canonical;
  std::unordered_map<uint32_t, const SetEdit*> by_point;
  const SetEdit* find(uint32_t point) const {
    if (by_point.empty()) return nullptr;
    auto it = by_point.find(point);
    return it == by_point.end() ? nullptr : it->second;
  }
};

struct Chunk {
  std::vector<uint32_t> counts;  // per point: entries in this chunk's stencil
  std::vector<uint32_t> ids;
  std::vector<float> weights;
  std::vector<float> bary;
  std::vector<uint32_t> set_counts;  // per point (extended only): members of its set
  std::vector<uint32_t> set_ids;
  std::vector<float> set_weights;
  std::vector<uint32_t> separated;  // per point (separating only)
  std::vector<uint8_t> inside;      // per point: passes the cage-quality test
  std::vector<float> reach;         // per point: Binding::reach
  std::vector<uint32_t> rigid_points, rigid_element;
  std::vector<float> rigid_bary;
  uint32_t max_set = 0;
  uint64_t total_set = 0;
};

bool closer(const Candidate& x, const Candidate& y) {
  return x.dist2 < y.dist2 || (x.dist2 == y.dist2 && x.element < y.element);
}

bool excluded(const SetEdit* edit, uint32_t e) { return edit && edit->excludes(e); }

bool included(const SetEdit* edit, uint32_t e) {
  return edit && std::binary_search(edit->include.begin(), edit->include.end(), e);
}

// Whether the point's automatic rule leaves element e out of its candidates: an exclusion, or an
// inclusion (inclusions join the set with their own weight, apart from the rule and its K).
bool outside_rule(const SetEdit* edit, uint32_t e) { return edit && (edit->excludes(e) || included(edit, e)); }

// The squared distance within which every allowed element must be known for the point's result to
// be exact (needed_radius2: the threshold radius, the (K+1)-th candidate, the tie band, the M+1-th).
// `out` is sorted; radius2 follows the nearest element.
// `band2` (optional): the tie band's squared radius, where it was needed (else left as it is).
double needed_bound2(const Context& ctx, const std::vector<Candidate>& out, double radius2, double* band2 = nullptr) {
  const double inf = std::numeric_limits<double>::infinity();
  const size_t k = ctx.params.max_elements;
  if (out.empty()) return radius2;
  double band = -1.0;
  const double need2 = needed_radius2_band(ctx.params, ctx.h, out.front().dist2, out.size() > k ? out[k].dist2 : inf,
                                           out.size() > kMaxTiedMembers ? out[kMaxTiedMembers].dist2 : inf, radius2, band);
  if (band2 && band >= 0) *band2 = band;
  return need2;
}

double radius2_of(const Context& ctx, double best2) {
  const double r = ctx.h * threshold_radius(std::sqrt(best2) / ctx.h, ctx.params.local, ctx.params.epsilon);
  return std::max(r * r, best2);  // rounding must never drop the nearest element
}

// Turns the gathered candidates of one point into its stencil entries.
// `cands` holds every allowed, non-excluded valid element within the threshold radius, sorted by
// distance (possibly more beyond the (K+1)-th: they are cut here).
// `need2`: the squared distance within which every element it depends on lies (needed_bound2).
void finish_point(const Context& ctx, uint32_t point, const glm::dvec3& p, std::vector<Candidate>& cands,
                  const SetEdit* edit, uint32_t separated, double need2, Chunk& out) {
  const BindParams& prm = ctx.params;
  if (ctx.separate) out.separated.push_back(separated);
  // rounded up, so that the stored reach never falls short of the exact one
  const float reach = static_cast<float>(std::sqrt(need2));
  out.reach.push_back(std::nextafter(reach, std::numeric_limits<float>::infinity()));
  // Taper (decision, see docs/algorithm-notes.md): the weight at which an element would leave the set
  // (the relative threshold; the strongest element left out by K and the max distance, unless they
  // nearly tie the nearest) is subtracted from every member's weight, so that elements enter and leave sets at
  // zero weight and the map is continuous in P.
  thread_local std::vector<double> dist, w;
  dist.resize(cands.size());
  for (size_t i = 0; i < cands.size(); ++i) dist[i] = std::sqrt(cands[i].dist2) / ctx.h;
  const Taper taper(prm, ctx.h, dist);
  w.resize(cands.size());
  size_t kept = 0;
  if (!(taper.weights(w) > 0)) {  // every candidate at the cut (epsilon = 1, exact ties beyond M): plain weights
    kept = std::min<size_t>(cands.size(), prm.max_elements);
    for (size_t i = 0; i < kept; ++i) w[i] = taper.raw(dist[i]);
  } else {
    for (size_t i = 0; i < cands.size(); ++i)
      if (w[i] > 0.0) kept = i + 1;  // members are a prefix of the sorted candidates
  }
  cands.resize(kept);
  w.resize(kept);
  if (edit) {  // inclusions: their own eq. 1 weight, on the taper's scale
    for (uint32_t e : edit->include) {
      if (!ctx.valid[e]) continue;
      ClosestPoint cp = closest_on(ctx.rest, ctx.cage->elements[e], p);
      cands.push_back({e, cp.dist2, cp.bary});
      w.push_back(taper.raw(std::sqrt(cp.dist2) / ctx.h));
    }
  }
  if (prm.variant == Variant::kExtended) out.set_counts.push_back(0);

  if (cands.empty()) {
    // Fall back to the nearest valid element (allowed and not excluded where possible), followed rigidly.
    uint32_t best = UINT32_MAX;
    ClosestPoint best_cp{};
    best_cp.dist2 = 1e300;
    for (int pass = 0; pass < 2 && best == UINT32_MAX; ++pass) {
      for (uint32_t e : ctx.valid_ids) {
        if (pass == 0 && (excluded(edit, e) || !ctx.allowed(point, e))) continue;
        ClosestPoint cp = closest_on(ctx.rest, ctx.cage->elements[e], p);
        if (cp.dist2 < best_cp.dist2) {
          best_cp = cp;
          best = e;
        }
      }
    }
    out.reach.back() = std::numeric_limits<float>::infinity();  // the nearest element of all
    out.counts.push_back(0);
    out.rigid_points.push_back(point);
    out.rigid_element.push_back(best);
    out.rigid_bary.push_back(static_cast<float>(best_cp.bary.y));
    out.rigid_bary.push_back(static_cast<float>(best_cp.bary.z));
    out.inside.push_back(close_and_inside(ctx.rest, ctx.cage->elements[best], p, best_cp.dist2, ctx.close_limit()));
    return;
  }

  const size_t n = cands.size();
  double sum = 0.0;
  for (size_t i = 0; i < n; ++i) sum += w[i];
  // the set: members with a weight (an element at the cut contributes nothing and is left out)
  bool inside = false;
  uint32_t members = 0;
  for (size_t i = 0; i < n; ++i) {
    if (w[i] <= 0.0) continue;
    ++members;
    inside = inside || close_and_inside(ctx.rest, ctx.cage->elements[cands[i].element], p, cands[i].dist2,
                                        ctx.close_limit());
  }
  out.inside.push_back(inside);
  out.max_set = std::max(out.max_set, members);
  out.total_set += members;

  if (prm.variant == Variant::kExtended) {
    out.set_counts.back() = members;
    // u_k = w_k / sum, once per member (the set's weight and the corners' share)
    thread_local std::vector<double> u;
    u.resize(n);
    for (size_t i = 0; i < n; ++i) {
      u[i] = w[i] / sum;
      if (w[i] <= 0.0) continue;
      out.set_ids.push_back(cands[i].element);
      out.set_weights.push_back(static_cast<float>(u[i]));
    }
    // W_j = sum_k u_k b_kj over the corners j of each contributing element
    thread_local std::vector<uint32_t> vid;
    thread_local std::vector<double> vw;
    vid.clear();
    vw.clear();
    size_t m = 0;
    for (size_t i = 0; i < n; ++i) {
      const Tri& t = ctx.cage->elements[cands[i].element];
      const double ui = u[i];
      for (int c = 0; c < 3; ++c) {
        const double wv = ui * cands[i].bary[c];
        if (wv <= 0.0) continue;
        const uint32_t v = t[static_cast<size_t>(c)];
        size_t j = 0;
        while (j < m && vid[j] != v) ++j;
        if (j == m) {
          vid.push_back(v);
          vw.push_back(0.0);
          ++m;
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
    if (w[i] <= 0.0) continue;  // at the cut: contributes nothing
    out.ids.push_back(cands[i].element);
    out.weights.push_back(static_cast<float>(w[i] / sum));
    if (prm.variant == Variant::kClamped) {
      out.bary.push_back(static_cast<float>(cands[i].bary.y));
      out.bary.push_back(static_cast<float>(cands[i].bary.z));
    }
  }
  out.counts.push_back(members);
}

// Label a and label b are at most `steps` edges apart in the forest: climb both towards their
// roots and look for a common ancestor reached in i + j <= steps.
bool within_steps(std::span<const int32_t> parent, uint32_t a, uint32_t b, uint32_t steps) {
  std::vector<uint32_t> up_a;
  for (int64_t x = a; x >= 0 && up_a.size() <= steps; x = parent[static_cast<size_t>(x)]) up_a.push_back(uint32_t(x));
  uint32_t j = 0;
  for (int64_t y = b; y >= 0 && j <= steps; y = parent[static_cast<size_t>(y)], ++j)
    for (size_t i = 0; i < up_a.size() && i + j <= steps; ++i)
      if (up_a[i] == uint32_t(y)) return true;
  return false;
}

Status set_labels(Context& ctx, const PartLabels& labels) {
  auto bad = [](const std::string& m) { return Status(make_error(ErrorCode::kInvalidArgument, m)); };
  const size_t nl = labels.parent.size();
  if (labels.point.size() != ctx.skin.size())
    return bad("the part labels name " + std::to_string(labels.point.size()) + " skin points but the skin has " +
               std::to_string(ctx.skin.size()));
  if (labels.cage_vertex.size() != ctx.cage->num_vertices())
    return bad("the part labels name " + std::to_string(labels.cage_vertex.size()) +
               " cage vertices but the cage has " + std::to_string(ctx.cage->num_vertices()));
  for (size_t l = 0; l < nl; ++l) {
    // a forest: every chain of parents ends at a root within nl steps
    int64_t x = labels.parent[l];
    size_t steps = 0;
    for (; x >= 0 && steps <= nl; ++steps) {
      if (size_t(x) >= nl) return bad("part label " + std::to_string(l) + " has parent " + std::to_string(x) +
                                      " but there are " + std::to_string(nl) + " labels");
      x = labels.parent[static_cast<size_t>(x)];
    }
    if (steps > nl) return bad("the part labels' parents form a cycle through label " + std::to_string(l));
  }
  // dense numbering of the labels in use
  std::vector<uint32_t> dense(nl, kUnlabelled), used;
  auto renumber = [&](uint32_t l, const char* what, size_t i) -> Result<uint32_t> {
    if (l == kUnlabelled) return kUnlabelled;
    if (l >= nl)
      return make_error(ErrorCode::kInvalidArgument, std::string(what) + " " + std::to_string(i) + " has part label " +
                                                         std::to_string(l) + " but there are " + std::to_string(nl) +
                                                         " labels");
    if (dense[l] == kUnlabelled) {
      dense[l] = static_cast<uint32_t>(used.size());
      used.push_back(l);
    }
    return dense[l];
  };
  ctx.point_label.resize(ctx.skin.size());
  for (size_t i = 0; i < ctx.skin.size(); ++i) {
    auto d = renumber(labels.point[i], "skin point", i);
    if (!d) return d.error();
    ctx.point_label[i] = *d;
  }
  std::vector<uint32_t> vertex(labels.cage_vertex.size());
  for (size_t v = 0; v < vertex.size(); ++v) {
    auto d = renumber(labels.cage_vertex[v], "cage vertex", v);
    if (!d) return d.error();
    vertex[v] = *d;
  }
  ctx.element_label.resize(ctx.cage->num_elements());
  for (size_t e = 0; e < ctx.element_label.size(); ++e)
    for (size_t c = 0; c < 3; ++c) ctx.element_label[e][c] = vertex[ctx.cage->elements[e][c]];
  ctx.num_labels = static_cast<uint32_t>(used.size());
  ctx.connected.assign(size_t(ctx.num_labels) * ctx.num_labels, 0);
  for (uint32_t a = 0; a < ctx.num_labels; ++a)
    for (uint32_t b = 0; b < ctx.num_labels; ++b)
      ctx.connected[size_t(a) * ctx.num_labels + b] =
          within_steps(labels.parent, used[a], used[b], ctx.params.separation_steps) ||
          (labels.related.size() == nl * nl && labels.related[size_t(used[a]) * nl + used[b]]);
  // an element whose corners follow unrelated parts (a face from the hand to the thigh where they
  // touch at rest, from one leg to the other where the legs are together) bridges them: it may
  // drive only points related to every corner, so neither part is pulled along when they separate
  if (!labels.point_shell.empty() || !labels.vertex_shell.empty()) {
    if (labels.point_shell.size() != ctx.skin.size() || labels.vertex_shell.size() != ctx.cage->num_vertices())
      return bad("the part labels' shells name " + std::to_string(labels.point_shell.size()) + " skin points and " +
                 std::to_string(labels.vertex_shell.size()) + " cage vertices; the skin has " +
                 std::to_string(ctx.skin.size()) + " and the cage " + std::to_string(ctx.cage->num_vertices()));
    ctx.point_shell = labels.point_shell;
    ctx.element_shell.resize(ctx.cage->num_elements());
    for (size_t e = 0; e < ctx.element_shell.size(); ++e) ctx.element_shell[e] = labels.vertex_shell[ctx.cage->elements[e][0]];
  }
  ctx.element_bridge.assign(ctx.element_label.size(), 0);
  // siblings (the two thighs under the hips) are bridged apart only away from where they branch: the
  // crotch's elements span both thighs, and cutting them creased it (the worst dent of the legs-apart
  // test doubled, 8 -> 19 mm), while legs held together need it lower down
  std::vector<uint8_t> near(size_t(ctx.num_labels) * ctx.num_labels, 0);
  for (uint32_t a = 0; a < ctx.num_labels; ++a)
    for (uint32_t b = 0; b < ctx.num_labels; ++b)
      near[size_t(a) * ctx.num_labels + b] = ctx.connected[size_t(a) * ctx.num_labels + b] ||
                                             within_steps(labels.parent, used[a], used[b], 2);
  const bool geometry = labels.head.size() == nl && labels.length.size() == nl;
  glm::dvec3 centroid(0.0);
  auto linked = [&](uint32_t a, uint32_t b) {
    if (a == kUnlabelled || b == kUnlabelled || ctx.connected[size_t(a) * ctx.num_labels + b]) return true;
    if (!near[size_t(a) * ctx.num_labels + b]) return false;
    if (!geometry) return true;
    const uint32_t ua = used[a], ub = used[b];
    const double reach = 0.5 * std::min(labels.length[ua], labels.length[ub]);
    return glm::length(centroid - glm::dvec3(labels.head[ua])) < reach ||
           glm::length(centroid - glm::dvec3(labels.head[ub])) < reach;
  };
  for (size_t e = 0; e < ctx.element_label.size(); ++e) {
    const auto& l = ctx.element_label[e];
    const Tri& t = ctx.cage->elements[e];
    centroid = (glm::dvec3(ctx.rest[t[0]]) + glm::dvec3(ctx.rest[t[1]]) + glm::dvec3(ctx.rest[t[2]])) / 3.0;
    const int links = int(linked(l[0], l[1])) + int(linked(l[1], l[2])) + int(linked(l[0], l[2]));
    ctx.element_bridge[e] = links < 2;  // the corners' parts are not one connected group
  }
  ctx.separate = true;
  return Ok{};
}

Result<Context> make_context(std::span<const glm::vec3> skin, const Cage& cage, std::span<const glm::vec3> rest,
                             const BindParams& params, const PartLabels* labels) {
  auto v = validate(params);
  if (!v) return v.error();
  if (auto s = check_skin(skin); !s) return s.error();
  if (rest.size() != cage.num_vertices())
    return make_error(ErrorCode::kTopologyMismatch, "the cage has " + std::to_string(cage.num_vertices()) +
                                                        " vertices but " + std::to_string(rest.size()) +
                                                        " positions were given");
  Context ctx;
  ctx.skin = skin;
  ctx.cage = &cage;
  ctx.rest = rest;
  ctx.params = params;
  ctx.status = classify_elements(cage, rest);
  ctx.valid.resize(ctx.status.size());
  for (size_t e = 0; e < ctx.status.size(); ++e) {
    ctx.valid[e] = ctx.status[e] == ElementStatus::kValid;
    if (ctx.valid[e]) ctx.valid_ids.push_back(static_cast<uint32_t>(e));
  }
  if (ctx.valid_ids.empty())
    return make_error(ErrorCode::kNoValidElements,
                      "the cage has no valid element: all " + std::to_string(ctx.status.size()) +
                          " triangles are zero-area, non-finite or duplicates");
  PolyMesh rest_mesh = cage.polygons;
  rest_mesh.positions.assign(rest.begin(), rest.end());
  ctx.h = params.scale > 0 ? params.scale : mean_edge_length(rest_mesh);
  if (!(ctx.h > 0) || !std::isfinite(ctx.h))
    return make_error(ErrorCode::kInvalidArgument, "the cage's mean edge length is zero; give a scale h");
  if (params.separate && labels && !labels->empty())
    if (auto s = set_labels(ctx, *labels); !s) return s.error();
  return ctx;
}

// Checks every edit, and keeps (canonical) those of `points` (ascending; all when empty).
Result<Edits> make_edits(const Context& ctx, std::span<const SetEdit> edits, std::span<const uint32_t> points = {}) {
  Edits out;
  std::vector<SetEdit> kept;
  for (const SetEdit& e : edits) {
    if (e.point >= ctx.skin.size())
      return make_error(ErrorCode::kIndexOutOfRange, "set edit names point " + std::to_string(e.point) +
                                                         " but the skin has " + std::to_string(ctx.skin.size()) +
                                                         " points");
    for (const auto* list : {&e.exclude, &e.include})
      for (uint32_t k : *list)
        if (k >= ctx.cage->num_elements())
          return make_error(ErrorCode::kIndexOutOfRange,
                            "set edit of point " + std::to_string(e.point) + " names element " + std::to_string(k) +
                                " but the cage has " + std::to_string(ctx.cage->num_elements()) + " elements");
    if (points.empty() || std::binary_search(points.begin(), points.end(), e.point)) kept.push_back(e);
  }
  out.canonical = canonical_set_edits(kept);
  for (const SetEdit& e : out.canonical) out.by_point[e.point] = &e;
  return out;
}

}  // namespace

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

namespace {

constexpr size_t kChunk = 128;

// Runs fn(source, c, chunk_points) over the chunks of `order` (kChunk consecutive entries each) on the
// worker threads, each task with its own source from new_source(); reports progress and stops when
// cancelled (false).
template <class NewSource, class Fn>
bool for_each_chunk(std::span<const uint32_t> order, const BindProgress& progress, NewSource new_source, Fn fn) {
  const size_t n = order.size();
  const size_t num_chunks = (n + kChunk - 1) / kChunk;
  std::atomic<size_t> done{0};
  std::atomic<bool> cancelled{false};
  const size_t report_every = std::max<size_t>(1, num_chunks / 200);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, num_chunks, 8), [&](const tbb::blocked_range<size_t>& r) {
    auto source = new_source();
    for (size_t c = r.begin(); c != r.end(); ++c) {
      if (cancelled.load(std::memory_order_relaxed)) return;
      if (progress.cancel && progress.cancel->load(std::memory_order_relaxed)) {
        cancelled = true;
        return;
      }
      fn(source, c, std::span<const uint32_t>(order.data() + c * kChunk, std::min(n, (c + 1) * kChunk) - c * kChunk));
      const size_t d = done.fetch_add(1) + 1;
      if (progress.on_progress && (d % report_every == 0 || d == num_chunks)) progress.on_progress(double(d) / num_chunks);
    }
  });
  return !cancelled;
}

// Registers the points of `order` in chunks of kChunk consecutive ones (chunk c holds
// order[c * kChunk ...]). `new_source()` gives per-thread candidate sources with
//   prepare(ctx, chunk_points)                 once per spatially compact chunk, and
//   gather(ctx, point, p, edit, out, need2) -> count  per point: every allowed, non-excluded valid
//                                              element within the threshold radius, sorted by distance;
//                                              need2: needed_bound2 of the point; returns how many
//                                              elements the labels kept out (see Binding).
// False when cancelled.
template <class NewSource>
bool register_points(const Context& ctx, const Edits& edits, std::span<const uint32_t> order, NewSource new_source,
                     const BindProgress& progress, std::vector<Chunk>& chunks) {
  chunks.assign((order.size() + kChunk - 1) / kChunk, Chunk{});
  return for_each_chunk(order, progress, new_source, [&](auto& source, size_t c, std::span<const uint32_t> pts) {
    thread_local std::vector<Candidate> cands;
    Chunk& out = chunks[c];
    source.prepare(ctx, pts);
    // room for a typical chunk (sets of ~8 elements, ~10 cage vertices): no regrowth on the way
    const size_t m = pts.size();
    out.counts.reserve(m);
    out.inside.reserve(m);
    out.reach.reserve(m);
    out.ids.reserve(12 * m);
    out.weights.reserve(12 * m);
    if (ctx.params.variant == Variant::kClamped) out.bary.reserve(24 * m);
    if (ctx.params.variant == Variant::kExtended) {
      out.set_counts.reserve(m);
      out.set_ids.reserve(10 * m);
      out.set_weights.reserve(10 * m);
    }
    if (ctx.separate) out.separated.reserve(m);
    for (size_t j = 0; j < pts.size(); ++j) {
      const uint32_t i = pts[j];
      if (j + 4 < pts.size()) __builtin_prefetch(&ctx.skin[pts[j + 4]]);  // points in Morton order: scattered
      const SetEdit* edit = edits.find(i);
      glm::dvec3 p(ctx.skin[i]);
      double need2 = 0.0;
      const uint32_t separated = source.gather(ctx, i, p, edit, cands, need2);
      finish_point(ctx, i, p, cands, edit, separated, need2, out);
    }
  });
}

// Fallback points in point order (deterministic whatever the scheduling).
void sort_rigid(Binding& b) {
  std::vector<uint32_t> perm(b.rigid_points.size());
  for (size_t i = 0; i < perm.size(); ++i) perm[i] = static_cast<uint32_t>(i);
  std::sort(perm.begin(), perm.end(), [&](uint32_t x, uint32_t y) { return b.rigid_points[x] < b.rigid_points[y]; });
  std::vector<uint32_t> points, elements;
  std::vector<float> bary;
  for (uint32_t k : perm) {
    points.push_back(b.rigid_points[k]);
    elements.push_back(b.rigid_element[k]);
    bary.push_back(b.rigid_bary[2 * k]);
    bary.push_back(b.rigid_bary[2 * k + 1]);
  }
  b.rigid_points = std::move(points);
  b.rigid_element = std::move(elements);
  b.rigid_bary = std::move(bary);
}

// The rest cage a binding is made on, with its elements' statuses.
void take_rest_cage(Binding& b, const Context& ctx) {
  b.rest_cage.assign(ctx.rest.begin(), ctx.rest.end());
  b.element_status = ctx.status;
  b.invalid_elements.clear();
  for (size_t e = 0; e < ctx.status.size(); ++e)
    if (ctx.status[e] != ElementStatus::kValid) b.invalid_elements.push_back(static_cast<uint32_t>(e));
}

// The binding of every point from the chunks of register_points(order = all points).
Binding assemble(const Context& ctx, std::span<const uint32_t> order, std::vector<Chunk>& chunks) {
  const BindParams& params = ctx.params;
  const size_t n = order.size(), num_chunks = chunks.size();
  Binding b;
  b.params = params;
  b.h = ctx.h;
  b.origin = bounding_box(ctx.skin).center();
  b.num_points = static_cast<uint32_t>(n);
  b.num_cage_vertices = static_cast<uint32_t>(ctx.cage->num_vertices());
  b.elements = ctx.cage->elements;
  take_rest_cage(b, ctx);

  // chunks hold points in Morton order: count per point, prefix-sum, then scatter back to point order
  const bool extended = params.variant == Variant::kExtended;
  b.offsets.assign(n + 1, 0);
  if (extended) b.set_offsets.assign(n + 1, 0);
  b.separation_applied = ctx.separate;
  if (ctx.separate) b.separated.assign(n, 0);
  b.reach.assign(n, 0.f);
  for (size_t c = 0; c < num_chunks; ++c) {
    const auto& ch = chunks[c];
    for (size_t k = 0; k < ch.counts.size(); ++k) {
      const uint32_t i = order[c * kChunk + k];
      b.offsets[i + 1] = ch.counts[k];
      if (extended) b.set_offsets[i + 1] = ch.set_counts[k];
      if (ctx.separate) b.separated[i] = ch.separated[k];
      b.reach[i] = ch.reach[k];
      b.quality_inside += ch.inside[k];
    }
  }
  for (size_t i = 0; i < n; ++i) b.offsets[i + 1] += b.offsets[i];
  if (extended)
    for (size_t i = 0; i < n; ++i) b.set_offsets[i + 1] += b.set_offsets[i];
  const size_t total = b.offsets[n];
  const bool clamped = params.variant == Variant::kClamped;
  b.ids.resize(total);
  b.weights.resize(total);
  if (clamped) b.bary.resize(2 * total);
  if (extended) {
    b.set_ids.resize(b.set_offsets[n]);
    b.set_weights.resize(b.set_offsets[n]);
  }
  tbb::parallel_for(tbb::blocked_range<size_t>(0, num_chunks, 16), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t c = r.begin(); c != r.end(); ++c) {
      Chunk& ch = chunks[c];
      size_t src = 0, set_src = 0;
      for (size_t k = 0; k < ch.counts.size(); ++k) {
        const uint32_t i = order[c * kChunk + k];
        const uint32_t dst = b.offsets[i];
        for (uint32_t j = 0; j < ch.counts[k]; ++j, ++src) {
          b.ids[dst + j] = ch.ids[src];
          b.weights[dst + j] = ch.weights[src];
          if (clamped) {
            b.bary[2 * (dst + j)] = ch.bary[2 * src];
            b.bary[2 * (dst + j) + 1] = ch.bary[2 * src + 1];
          }
        }
        if (!extended) continue;
        const uint32_t set_dst = b.set_offsets[i];
        for (uint32_t j = 0; j < ch.set_counts[k]; ++j, ++set_src) {
          b.set_ids[set_dst + j] = ch.set_ids[set_src];
          b.set_weights[set_dst + j] = ch.set_weights[set_src];
        }
      }
      std::vector<uint32_t>().swap(ch.ids);  // release as we go
      std::vector<float>().swap(ch.weights);
      std::vector<float>().swap(ch.bary);
      std::vector<uint32_t>().swap(ch.set_ids);
      std::vector<float>().swap(ch.set_weights);
    }
  });
  for (auto& ch : chunks) {
    for (size_t k = 0; k < ch.rigid_points.size(); ++k) {
      b.rigid_points.push_back(ch.rigid_points[k]);
      b.rigid_element.push_back(ch.rigid_element[k]);
      b.rigid_bary.push_back(ch.rigid_bary[2 * k]);
      b.rigid_bary.push_back(ch.rigid_bary[2 * k + 1]);
    }
    b.max_set_size = std::max(b.max_set_size, ch.max_set);
    b.total_set_size += ch.total_set;
  }
  sort_rigid(b);
  for (uint32_t s : b.separated) {
    b.total_separated += s;
    b.separated_points += s > 0;
  }
  return b;
}

// `order`: the order to register the points in (empty: morton_order(ctx.skin), spatial chunks for the
// hierarchy's queries).
template <class NewSource>
Result<Binding> run_registration(const Context& ctx, std::span<const SetEdit> edit_list, const BindProgress& progress,
                                 NewSource new_source, std::chrono::steady_clock::time_point t0,
                                 std::span<const uint32_t> order_given = {}) {
  auto edits = make_edits(ctx, edit_list);
  if (!edits) return edits.error();
  const std::vector<uint32_t> own = order_given.empty() ? morton_order(ctx.skin) : std::vector<uint32_t>{};
  const std::span<const uint32_t> order = order_given.empty() ? std::span<const uint32_t>(own) : order_given;
  std::vector<Chunk> chunks;
  if (!register_points(ctx, *edits, order, new_source, progress, chunks))
    return make_error(ErrorCode::kCancelled, "bind cancelled");
  Binding b = assemble(ctx, order, chunks);
  b.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return b;
}

// Candidates for a chunk of nearby points: the elements any of them could reach, found once with the
// hierarchy, then a tight loop per point with box rejection. A point whose answer could lie beyond
// what the chunk gathered (its nearest elements excluded by an edit or the labels) asks the
// hierarchy itself.
class ChunkedBvhSource {
 public:
  explicit ChunkedBvhSource(const ElementBvh& bvh) : bvh_(bvh) {}
  void prepare(const Context& ctx, std::span<const uint32_t> pts) {
    Aabb box;
    for (uint32_t i : pts) box.extend(glm::dvec3(ctx.skin[i]));
    centre_ = box.center();
    const double half = 0.5 * box.diagonal();
    // any point p of the chunk has d_min(p) <= d_min(c) + half, and its elements lie within
    // radius(d_min(p)) of p, hence within radius(d_min(c) + half) + half of c
    const double dc = bvh_.nearest_distance(centre_);
    reach_ = ctx.h * threshold_radius((dc + half) / ctx.h, ctx.params.local, ctx.params.epsilon) + half;
    bvh_.boxes_within(centre_, reach_, elems_);
    keys_.resize(elems_.size());
    order_.resize(elems_.size());
    for (size_t i = 0; i < elems_.size(); ++i) {
      keys_[i] = std::sqrt(ElementBvh::box_dist2(centre_, elems_[i].lo, elems_[i].hi)) - half;
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
  uint32_t gather(const Context& ctx, uint32_t point, const glm::dvec3& p, const SetEdit* edit,
                  std::vector<Candidate>& out, double& need2) {
    out.clear();
    rejected_.clear();
    // Only the K nearest elements within the threshold radius survive, with those in the tie band
    // (Taper), so once K + 1 are known the (K+1)-th distance or the band bounds the search too (ties
    // are kept: the final order breaks them by id).
    const size_t k = ctx.params.max_elements + 1;  // the (K+1)-th sets the taper's cut
    double best2 = 1e300, radius2 = 1e300, kth2 = 1e300, band2 = 1e300, bounds_at2 = 1e300;
    size_t prune_at = 2 * k;
    for (size_t i = 0; i < sorted_.size(); ++i) {
      const double bound2 = std::min(radius2, std::max(kth2, band2));
      // keys are lower bounds of the distance from any point of the chunk: the rest are farther
      if (sorted_keys_[i] > 0 && sorted_keys_[i] * sorted_keys_[i] > bound2) break;
      const auto& e = sorted_[i];
      if (ElementBvh::box_dist2(p, e.lo, e.hi) > bound2) continue;
      if (outside_rule(edit, e.id)) continue;
      ClosestPoint cp = closest_point_on_triangle(p, e.a, e.b, e.c);
      if (cp.dist2 > bound2) continue;
      if (!ctx.allowed(point, e.id)) {
        rejected_.push_back(cp.dist2);
        continue;
      }
      out.push_back({e.id, cp.dist2, cp.bary});
      if (cp.dist2 < best2) {
        best2 = cp.dist2;
        // the radii grow with the nearest distance, so those of an earlier, farther nearest bound the
        // search safely (a few more elements looked at); they are made again (two pow calls) only when
        // the nearest came much closer, and exactly once at the end
        if (!(best2 >= 0.6 * bounds_at2)) {
          bounds_at2 = best2;
          radius2 = radius2_of(ctx, best2);
          band2 = tie_band2(ctx.params, ctx.h, best2);
        }
      }
      if (out.size() >= prune_at) {
        std::nth_element(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(k - 1), out.end(), closer);
        kth2 = out[k - 1].dist2;
        const double keep2 = std::max(kth2, band2);
        out.erase(std::remove_if(out.begin() + static_cast<std::ptrdiff_t>(k), out.end(),
                                 [&](const Candidate& x) { return x.dist2 > keep2; }),
                  out.end());
        prune_at = std::max(2 * k, 2 * out.size());  // many in the band: prune again only when doubled
      }
    }
    if (bounds_at2 != best2 && !out.empty()) radius2 = radius2_of(ctx, best2);  // the exact radius
    std::erase_if(out, [&](const Candidate& x) { return x.dist2 > radius2; });
    std::sort(out.begin(), out.end(), closer);
    // Every element within `cover` of p is among the chunk's; the answer is exact when all it
    // depends on lies within that.
    need2 = needed_bound2(ctx, out, radius2);
    const double cover = reach_ - glm::length(p - centre_);
    if (out.empty() || !(cover > 0 && need2 <= cover * cover)) return direct(ctx, point, p, edit, out, need2);
    return static_cast<uint32_t>(std::count_if(rejected_.begin(), rejected_.end(), [&](double d2) { return d2 <= need2; }));
  }

  // Every valid element (whatever the labels and edits) within squared distance r2 of p, sorted by
  // distance (ties by id): from the chunk's elements where they cover it, else from the hierarchy.
  void collect_within(const glm::dvec3& p, double r2, std::vector<Candidate>& out) {
    out.clear();
    const double cover = reach_ - glm::length(p - centre_);
    const bool chunk = cover > 0 && r2 <= cover * cover;
    if (!chunk) bvh_.boxes_within(p, std::sqrt(r2) * (1 + 1e-9), direct_elems_);
    for (const auto& e : chunk ? sorted_ : direct_elems_) {
      // the box's distance can round above the element's own where they touch (an axis-aligned edge):
      // a margin, then the exact test
      if (ElementBvh::box_dist2(p, e.lo, e.hi) > r2 * (1 + 1e-9)) continue;
      ClosestPoint cp = closest_point_on_triangle(p, e.a, e.b, e.c);
      if (cp.dist2 <= r2) out.push_back({e.id, cp.dist2, cp.bary});
    }
    std::sort(out.begin(), out.end(), closer);
  }

  // The point's own query of the whole hierarchy (what gather() does where the chunk falls short).
  uint32_t direct(const Context& ctx, uint32_t point, const glm::dvec3& p, const SetEdit* edit,
                  std::vector<Candidate>& out, double& need2) {
    auto skip = [&](uint32_t e) { return outside_rule(edit, e) || !ctx.allowed(point, e); };
    auto radius = [&](double d) {
      return ctx.h * threshold_radius(d / ctx.h, ctx.params.local, ctx.params.epsilon);
    };
    bvh_.within_adaptive_radius(p, radius, skip, out);
    need2 = needed_bound2(ctx, out, out.empty() ? 1e300 : radius2_of(ctx, out.front().dist2));
    if (!ctx.separate) return 0;
    bvh_.boxes_within(p, std::sqrt(need2) * (1 + 1e-9), direct_elems_);
    uint32_t count = 0;
    for (const auto& e : direct_elems_)
      if (!outside_rule(edit, e.id) && !ctx.allowed(point, e.id) && closest_point_on_triangle(p, e.a, e.b, e.c).dist2 <= need2)
        ++count;
    return count;
  }

 private:
  const ElementBvh& bvh_;
  std::vector<ElementBvh::Element> elems_, sorted_, direct_elems_;
  std::vector<double> keys_, sorted_keys_;  // distance from the chunk centre minus the chunk's half size
  std::vector<uint32_t> order_;
  std::vector<double> rejected_;  // squared distances of the elements the labels kept out
  glm::dvec3 centre_{0.0};
  double reach_ = 0.0;  // the chunk holds every element within reach_ of centre_
};

// Reference: every valid element for every point, no pruning.
struct BruteForceSource {
  std::vector<double> rejected;
  void prepare(const Context&, std::span<const uint32_t>) {}
  uint32_t gather(const Context& ctx, uint32_t point, const glm::dvec3& p, const SetEdit* edit,
                  std::vector<Candidate>& out, double& need2) {
    out.clear();
    rejected.clear();
    double best = 1e300;
    for (uint32_t e : ctx.valid_ids) {
      if (outside_rule(edit, e)) continue;
      ClosestPoint cp = closest_on(ctx.rest, ctx.cage->elements[e], p);
      if (!ctx.allowed(point, e)) {
        rejected.push_back(cp.dist2);
        continue;
      }
      out.push_back({e, cp.dist2, cp.bary});
      best = std::min(best, cp.dist2);
    }
    const double radius2 = out.empty() ? 1e300 : radius2_of(ctx, best);
    std::erase_if(out, [&](const Candidate& c) { return c.dist2 > radius2; });
    std::sort(out.begin(), out.end(), closer);
    need2 = needed_bound2(ctx, out, radius2);
    return static_cast<uint32_t>(std::count_if(rejected.begin(), rejected.end(), [&](double d2) { return d2 <= need2; }));
  }
};

// Rows of a table with `width` values per entry, rows of `touched` (ascending) replaced: old rows are
// copied in runs, new_row(i) gives the i-th touched point's new values.
template <class T, class NewRow>
std::vector<T> splice_rows(const std::vector<T>& old, std::span<const uint32_t> old_offsets,
                           std::span<const uint32_t> new_offsets, std::span<const uint32_t> touched, size_t width,
                           NewRow new_row) {
  std::vector<T> out(size_t(new_offsets.back()) * width);
  uint32_t from = 0;  // first point of the current run of untouched points
  auto copy_run = [&](uint32_t to) {
    const size_t count = size_t(old_offsets[to] - old_offsets[from]) * width;
    if (count) std::memcpy(out.data() + size_t(new_offsets[from]) * width, old.data() + size_t(old_offsets[from]) * width, count * sizeof(T));
  };
  for (size_t i = 0; i < touched.size(); ++i) {
    const uint32_t p = touched[i];
    copy_run(p);
    std::span<const T> row = new_row(i);
    if (!row.empty()) std::memcpy(out.data() + size_t(new_offsets[p]) * width, row.data(), row.size() * sizeof(T));
    from = p + 1;
  }
  copy_run(static_cast<uint32_t>(old_offsets.size() - 1));
  return out;
}

// Offsets with the rows of `touched` (ascending) given new sizes.
std::vector<uint32_t> splice_offsets(std::span<const uint32_t> old_offsets, std::span<const uint32_t> touched,
                                     std::span<const uint32_t> new_counts) {
  std::vector<uint32_t> out(old_offsets.size());
  out[0] = 0;
  size_t t = 0;
  for (size_t p = 0; p + 1 < old_offsets.size(); ++p) {
    uint32_t count = old_offsets[p + 1] - old_offsets[p];
    if (t < touched.size() && touched[t] == p) count = new_counts[t++];
    out[p + 1] = out[p] + count;
  }
  return out;
}

}  // namespace

struct Rebinder::State {
  Context ctx;
  std::unique_ptr<ElementBvh> bvh;
  auto new_source() const {
    return [tree = bvh.get()] { return ChunkedBvhSource(*tree); };
  }
};

Rebinder::Rebinder(Rebinder&&) noexcept = default;
Rebinder& Rebinder::operator=(Rebinder&&) noexcept = default;
Rebinder::~Rebinder() = default;

Result<Rebinder> Rebinder::create(std::span<const glm::vec3> skin, const Cage& cage,
                                  std::span<const glm::vec3> rest, const BindParams& params,
                                  const PartLabels* labels) {
  auto ctx = make_context(skin, cage, rest, params, labels);
  if (!ctx) return ctx.error();
  Rebinder r;
  r.state_ = std::make_unique<State>();
  r.state_->ctx = std::move(ctx).value();
  const Context& c = r.state_->ctx;
  r.state_->bvh = std::make_unique<ElementBvh>(c.rest, c.cage->elements, c.valid_ids);
  return r;
}

double Rebinder::h() const { return state_->ctx.h; }

Result<Binding> Rebinder::bind(std::span<const SetEdit> edits, const BindProgress& progress) const {
  return run_registration(state_->ctx, edits, progress, state_->new_source(), std::chrono::steady_clock::now());
}

Status Rebinder::update(Binding& b, std::span<const SetEdit> edit_list, std::span<const uint32_t> points) const {
  const Context& ctx = state_->ctx;
  if (b.elements != ctx.cage->elements || b.rest_cage.size() != ctx.rest.size() ||
      !std::equal(b.rest_cage.begin(), b.rest_cage.end(), ctx.rest.begin()))
    return make_error(ErrorCode::kTopologyMismatch, "the binding was made for another cage; bind again");
  return update_points(b, edit_list, points);
}

Status Rebinder::move_rest(Binding& b, std::span<const SetEdit> edit_list, std::span<const uint32_t> points) const {
  const Context& ctx = state_->ctx;
  if (b.elements != ctx.cage->elements || b.rest_cage.size() != ctx.rest.size())
    return make_error(ErrorCode::kTopologyMismatch, "the binding was made for a cage of another topology; bind again");
  if (b.h != ctx.h)
    return make_error(ErrorCode::kInvalidArgument,
                      "the moved rest cage changes the distance scale h (" + std::to_string(b.h) + " -> " +
                          std::to_string(ctx.h) + ", the mean cage edge length) and so every weight; bind again, "
                          "or give a fixed scale to keep rest edits local");
  if (auto s = update_points(b, edit_list, points); !s) return s;
  take_rest_cage(b, ctx);
  return Ok{};
}

Status Rebinder::update_points(Binding& b, std::span<const SetEdit> edit_list, std::span<const uint32_t> points) const {
  const Context& ctx = state_->ctx;
  const size_t np = ctx.skin.size();
  if (b.num_points != np || b.offsets.size() != np + 1)
    return make_error(ErrorCode::kTopologyMismatch, "the binding was made for " + std::to_string(b.num_points) +
                                                        " skin points but the skin has " + std::to_string(np));
  if (b.params != ctx.params || b.separation_applied != ctx.separate)
    return make_error(ErrorCode::kInvalidArgument, "the binding was made with other parameters or labels; bind again");
  if (!b.has_sets())
    return make_error(ErrorCode::kInvalidArgument,
                      "the binding has no contributing-set table (made by an older cagewrap); bind again");
  std::vector<uint32_t> touched(points.begin(), points.end());
  std::sort(touched.begin(), touched.end());
  touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
  if (!touched.empty() && touched.back() >= np)
    return make_error(ErrorCode::kIndexOutOfRange, "point " + std::to_string(touched.back()) +
                                                       " to re-register, but the skin has " + std::to_string(np) +
                                                       " points");
  auto edits = make_edits(ctx, edit_list, touched);
  if (!edits) return edits.error();
  if (touched.empty()) return Ok{};

  // register the touched points, in Morton order among themselves
  std::vector<glm::vec3> positions(touched.size());
  for (size_t i = 0; i < touched.size(); ++i) positions[i] = ctx.skin[touched[i]];
  std::vector<uint32_t> order = morton_order(positions);
  for (uint32_t& i : order) i = touched[i];
  std::vector<Chunk> chunks;
  register_points(ctx, *edits, order, state_->new_source(), {}, chunks);

  // where each touched point's results are: chunk, index in it, first entry, first set member
  struct Slot {
    uint32_t chunk, k, entry, member;
  };
  std::vector<Slot> slots(touched.size());
  const bool extended = ctx.params.variant == Variant::kExtended, clamped = ctx.params.variant == Variant::kClamped;
  std::vector<uint32_t> counts(touched.size()), set_counts(touched.size());
  for (uint32_t c = 0; c < chunks.size(); ++c) {
    uint32_t entry = 0, member = 0;
    for (uint32_t k = 0; k < chunks[c].counts.size(); ++k) {
      const uint32_t point = order[c * kChunk + k];
      const size_t t = static_cast<size_t>(std::lower_bound(touched.begin(), touched.end(), point) - touched.begin());
      slots[t] = {c, k, entry, member};
      counts[t] = chunks[c].counts[k];
      entry += counts[t];
      if (extended) {
        set_counts[t] = chunks[c].set_counts[k];
        member += set_counts[t];
      }
    }
  }
  // the report figures of the touched points, before (on the binding's own rest cage)
  if (b.reach.size() == np)
    for (size_t t = 0; t < touched.size(); ++t) b.reach[touched[t]] = chunks[slots[t].chunk].reach[slots[t].k];
  int64_t inside = 0;
  for (uint32_t p : touched) inside -= well_bound(b, ctx.skin, p);
  for (size_t t = 0; t < touched.size(); ++t) inside += chunks[slots[t].chunk].inside[slots[t].k];
  b.quality_inside = static_cast<uint32_t>(int64_t(b.quality_inside) + inside);
  if (ctx.separate) {
    for (size_t t = 0; t < touched.size(); ++t) {
      uint32_t& s = b.separated[touched[t]];
      b.total_separated -= s;
      b.separated_points -= s > 0;
      s = chunks[slots[t].chunk].separated[slots[t].k];
      b.total_separated += s;
      b.separated_points += s > 0;
    }
  }

  // the stencil, then the sets (extended)
  auto new_row = [&](size_t t, auto member, uint32_t first, uint32_t count, size_t width) {
    const auto& v = chunks[slots[t].chunk].*member;
    using T = typename std::remove_cvref_t<decltype(v)>::value_type;
    return std::span<const T>(v.data() + size_t(first) * width, size_t(count) * width);
  };
  // Same row sizes as before (the usual case for a small edit): written in place, so the cost follows
  // the touched points and not the skin. Otherwise the tables are spliced (a copy of the whole table).
  const Binding::SetsView old_sets = b.sets();
  uint32_t old_max_touched = 0, new_max_touched = 0;
  int64_t set_delta = 0;
  bool same_sizes = true;
  for (size_t t = 0; t < touched.size(); ++t) {
    const uint32_t p = touched[t];
    same_sizes = same_sizes && counts[t] == b.offsets[p + 1] - b.offsets[p] &&
                 (!extended || set_counts[t] == b.set_offsets[p + 1] - b.set_offsets[p]);
    const uint32_t before = old_sets.offsets[p + 1] - old_sets.offsets[p], after = extended ? set_counts[t] : counts[t];
    old_max_touched = std::max(old_max_touched, before);
    new_max_touched = std::max(new_max_touched, after);
    set_delta += int64_t(after) - int64_t(before);
  }
  if (same_sizes) {
    for (size_t t = 0; t < touched.size(); ++t) {
      const size_t first = b.offsets[touched[t]];
      std::ranges::copy(new_row(t, &Chunk::ids, slots[t].entry, counts[t], 1), b.ids.begin() + first);
      std::ranges::copy(new_row(t, &Chunk::weights, slots[t].entry, counts[t], 1), b.weights.begin() + first);
      if (clamped) std::ranges::copy(new_row(t, &Chunk::bary, slots[t].entry, counts[t], 2), b.bary.begin() + 2 * first);
      if (extended) {
        const size_t m = b.set_offsets[touched[t]];
        std::ranges::copy(new_row(t, &Chunk::set_ids, slots[t].member, set_counts[t], 1), b.set_ids.begin() + m);
        std::ranges::copy(new_row(t, &Chunk::set_weights, slots[t].member, set_counts[t], 1), b.set_weights.begin() + m);
      }
    }
  } else {
    std::vector<uint32_t> offsets = splice_offsets(b.offsets, touched, counts);
    b.ids = splice_rows(b.ids, b.offsets, offsets, touched, 1,
                        [&](size_t t) { return new_row(t, &Chunk::ids, slots[t].entry, counts[t], 1); });
    b.weights = splice_rows(b.weights, b.offsets, offsets, touched, 1,
                            [&](size_t t) { return new_row(t, &Chunk::weights, slots[t].entry, counts[t], 1); });
    if (clamped)
      b.bary = splice_rows(b.bary, b.offsets, offsets, touched, 2,
                           [&](size_t t) { return new_row(t, &Chunk::bary, slots[t].entry, counts[t], 2); });
    b.offsets = std::move(offsets);
    if (extended) {
      std::vector<uint32_t> set_offsets = splice_offsets(b.set_offsets, touched, set_counts);
      b.set_ids = splice_rows(b.set_ids, b.set_offsets, set_offsets, touched, 1,
                              [&](size_t t) { return new_row(t, &Chunk::set_ids, slots[t].member, set_counts[t], 1); });
      b.set_weights = splice_rows(b.set_weights, b.set_offsets, set_offsets, touched, 1, [&](size_t t) {
        return new_row(t, &Chunk::set_weights, slots[t].member, set_counts[t], 1);
      });
      b.set_offsets = std::move(set_offsets);
    }
  }

  // fallback points: the untouched ones kept, the touched ones' new entries added, in point order
  Binding rigid;
  for (size_t k = 0; k < b.rigid_points.size(); ++k) {
    if (std::binary_search(touched.begin(), touched.end(), b.rigid_points[k])) continue;
    rigid.rigid_points.push_back(b.rigid_points[k]);
    rigid.rigid_element.push_back(b.rigid_element[k]);
    rigid.rigid_bary.insert(rigid.rigid_bary.end(), {b.rigid_bary[2 * k], b.rigid_bary[2 * k + 1]});
  }
  for (const Chunk& ch : chunks)
    for (size_t k = 0; k < ch.rigid_points.size(); ++k) {
      rigid.rigid_points.push_back(ch.rigid_points[k]);
      rigid.rigid_element.push_back(ch.rigid_element[k]);
      rigid.rigid_bary.insert(rigid.rigid_bary.end(), {ch.rigid_bary[2 * k], ch.rigid_bary[2 * k + 1]});
    }
  sort_rigid(rigid);
  b.rigid_points = std::move(rigid.rigid_points);
  b.rigid_element = std::move(rigid.rigid_element);
  b.rigid_bary = std::move(rigid.rigid_bary);

  // set sizes: the largest over the whole skin only when a touched point that may have held it shrank
  b.total_set_size = uint64_t(int64_t(b.total_set_size) + set_delta);
  if (new_max_touched >= b.max_set_size || old_max_touched < b.max_set_size) {
    b.max_set_size = std::max(b.max_set_size, new_max_touched);
  } else {
    const Binding::SetsView sets = b.sets();
    b.max_set_size = 0;
    for (size_t p = 0; p < np; ++p) b.max_set_size = std::max(b.max_set_size, sets.offsets[p + 1] - sets.offsets[p]);
  }
  return Ok{};
}

// ---- CandidateCache -------------------------------------------------------------------------------

struct CandidateCache::State {
  std::vector<glm::vec3> skin, rest;
  Cage cage;
  std::optional<PartLabels> labels;
  std::unique_ptr<ElementBvh> bvh;  // over the valid elements (they depend on the rest positions alone)
  // per point: its list of every valid element within sqrt(cover2), sorted as candidates are
  // (distance, then id); cover2 < 0: none (always asks the hierarchy)
  std::vector<uint32_t> offsets;  // #P+1
  // an entry: the element id (top bit: its closest point's first barycentric is 0, else it is
  // 1 - b1 - b2, as closest_point_on_triangle makes it), the squared distance and (b1, b2)
  std::vector<uint32_t> ids;
  std::vector<double> dist2;
  std::vector<glm::dvec2> bary;
  std::vector<double> cover2;  // #P
  static constexpr uint32_t kZeroFirst = 0x80000000u;
  double seconds = 0.0;
  const PartLabels* label_ptr() const { return labels ? &*labels : nullptr; }
};

namespace {

// Candidates from a point's cached list: what ChunkedBvhSource::gather finds (every allowed,
// non-excluded element within the threshold radius, sorted, with the same distances and barycentrics),
// cut to what its pruning always keeps (the K+1 nearest and the tie band; any more weigh nothing,
// Taper). A point whose needed radius exceeds its list's cover asks the hierarchy (the same query as
// gather's own fallback).
class CachedSource {
 public:
  CachedSource(const CandidateCache::State& cache, std::atomic<uint64_t>& queried)
      : cache_(cache), fallback_(*cache.bvh), queried_(queried) {}
  void prepare(const Context&, std::span<const uint32_t>) {}
  uint32_t gather(const Context& ctx, uint32_t point, const glm::dvec3& p, const SetEdit* edit,
                  std::vector<Candidate>& out, double& need2) {
    out.clear();
    rejected_.clear();
    double radius2 = std::numeric_limits<double>::infinity();
    for (uint32_t i = cache_.offsets[point]; i < cache_.offsets[point + 1]; ++i) {
      const double d2 = cache_.dist2[i];
      if (d2 > radius2) break;
      const uint32_t e = cache_.ids[i] & ~CandidateCache::State::kZeroFirst;
      if (outside_rule(edit, e)) continue;
      if (!ctx.allowed(point, e)) {
        rejected_.push_back(d2);
        continue;
      }
      if (out.empty()) radius2 = radius2_of(ctx, d2);  // the nearest allowed element
      const glm::dvec2 b = cache_.bary[i];
      out.push_back({e, d2, {(cache_.ids[i] & CandidateCache::State::kZeroFirst) ? 0.0 : 1 - b.x - b.y, b.x, b.y}});
    }
    double band2 = -1.0;
    need2 = needed_bound2(ctx, out, radius2, &band2);
    if (out.empty() || !(need2 <= cache_.cover2[point])) {
      queried_.fetch_add(1, std::memory_order_relaxed);  // rare: the slider left the cover
      return fallback_.direct(ctx, point, p, edit, out, need2);
    }
    // what gather() always keeps (its pruning may keep more, which weigh nothing): the K+1 nearest and
    // the tie band; the rest would only cost finish_point time
    const size_t k = ctx.params.max_elements + 1;
    if (out.size() > k) {
      if (band2 < 0) band2 = tie_band2(ctx.params, ctx.h, out.front().dist2);
      const double keep2 = std::max(out[k - 1].dist2, band2);
      while (out.back().dist2 > keep2) out.pop_back();
    }
    return static_cast<uint32_t>(std::count_if(rejected_.begin(), rejected_.end(), [&](double d2) { return d2 <= need2; }));
  }

 private:
  const CandidateCache::State& cache_;
  ChunkedBvhSource fallback_;
  std::atomic<uint64_t>& queried_;
  std::vector<double> rejected_;
};

}  // namespace

CandidateCache::CandidateCache(CandidateCache&&) noexcept = default;
CandidateCache& CandidateCache::operator=(CandidateCache&&) noexcept = default;
CandidateCache::~CandidateCache() = default;

BindParams CandidateCache::cover_params(const BindParams& params) {
  BindParams c = params;
  c.max_elements = std::min<uint32_t>(64, std::max(2 * params.max_elements, params.max_elements + 8));
  c.epsilon = params.epsilon / 4;
  c.local = params.local > 1.0 ? params.local - 1.0 : 0.5 * params.local;  // never above the given local
  c.max_distance = 0;  // none: the cover must hold whatever the max distance
  return c;
}

Result<CandidateCache> CandidateCache::create(std::span<const glm::vec3> skin, const Cage& cage,
                                              std::span<const glm::vec3> rest, const BindParams& params,
                                              const PartLabels* labels, const BindProgress& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  CandidateCache cache;
  cache.state_ = std::make_unique<State>();
  State& st = *cache.state_;
  st.skin.assign(skin.begin(), skin.end());
  st.rest.assign(rest.begin(), rest.end());
  st.cage = cage;
  if (labels && !labels->empty()) st.labels = *labels;
  if (cage.num_elements() >= State::kZeroFirst)
    return make_error(ErrorCode::kInvalidArgument, "the cage has " + std::to_string(cage.num_elements()) +
                                                       " elements; the candidate cache takes at most 2^31");
  auto made = make_context(st.skin, st.cage, st.rest, cover_params(params), st.label_ptr());
  if (!made) return made.error();
  const Context& ctx = *made;
  st.bvh = std::make_unique<ElementBvh>(ctx.rest, ctx.cage->elements, ctx.valid_ids);
  const std::vector<uint32_t> morton = morton_order(st.skin);  // chunks for the hierarchy's queries

  // per chunk of the Morton order: each point's list, then scattered to point order
  struct Lists {
    std::vector<uint32_t> counts, ids;
    std::vector<double> dist2, cover2;
    std::vector<glm::dvec2> bary;
  };
  const size_t n = st.skin.size(), num_chunks = (n + kChunk - 1) / kChunk;
  std::vector<Lists> chunks(num_chunks);
  const bool finished = for_each_chunk(morton, progress, [&] { return ChunkedBvhSource(*st.bvh); },
                                       [&](ChunkedBvhSource& source, size_t c, std::span<const uint32_t> pts) {
    thread_local std::vector<Candidate> cands, all;
    Lists& out = chunks[c];
    source.prepare(ctx, pts);
    for (uint32_t i : pts) {
      const glm::dvec3 p(st.skin[i]);
      double need2 = 0.0;
      source.gather(ctx, i, p, nullptr, cands, need2);  // what the widened parameters need
      double cover2 = -1.0;
      all.clear();
      if (!cands.empty() && need2 < 1e300) {
        source.collect_within(p, need2, all);
        cover2 = need2;
        if (all.size() > kMaxEntries) {  // cut before the first left out (ties with it go too)
          cover2 = std::nextafter(all[kMaxEntries].dist2, 0.0);
          while (!all.empty() && all.back().dist2 > cover2) all.pop_back();
        }
      }
      out.counts.push_back(static_cast<uint32_t>(all.size()));
      out.cover2.push_back(cover2);
      for (const Candidate& x : all) {
        // the first barycentric from the other two: 1 - b1 - b2 (interior, vertices, edges AB and AC)
        // or 0 (edge BC, where 1 - b1 - b2 may round to a tiny number)
        const bool zero_first = x.bary.x != 1 - x.bary.y - x.bary.z;
        CAGEWRAP_CHECK(!zero_first || x.bary.x == 0.0, "closest_point_on_triangle's barycentrics");
        out.ids.push_back(x.element | (zero_first ? State::kZeroFirst : 0u));
        out.dist2.push_back(x.dist2);
        out.bary.push_back({x.bary.y, x.bary.z});
      }
    }
  });
  if (!finished) return make_error(ErrorCode::kCancelled, "making the candidate cache was cancelled");
  st.offsets.assign(n + 1, 0);
  st.cover2.assign(n, -1.0);
  for (size_t c = 0; c < num_chunks; ++c)
    for (size_t k = 0; k < chunks[c].counts.size(); ++k) {
      const uint32_t i = morton[c * kChunk + k];
      st.offsets[i + 1] = chunks[c].counts[k];
      st.cover2[i] = chunks[c].cover2[k];
    }
  uint64_t total = 0;
  for (size_t i = 0; i < n; ++i) {
    total += st.offsets[i + 1];
    if (total > UINT32_MAX)
      return make_error(ErrorCode::kInvalidArgument, "the candidate cache would hold more than 2^32 entries (" +
                                                         std::to_string(n) + " skin points); bind without it");
    st.offsets[i + 1] = static_cast<uint32_t>(total);
  }
  st.ids.resize(total);
  st.dist2.resize(total);
  st.bary.resize(total);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, num_chunks, 16), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t c = r.begin(); c != r.end(); ++c) {
      Lists& ch = chunks[c];
      size_t src = 0;
      for (size_t k = 0; k < ch.counts.size(); ++k) {
        const uint32_t dst = st.offsets[morton[c * kChunk + k]];
        std::copy_n(ch.ids.begin() + static_cast<std::ptrdiff_t>(src), ch.counts[k], st.ids.begin() + dst);
        std::copy_n(ch.dist2.begin() + static_cast<std::ptrdiff_t>(src), ch.counts[k], st.dist2.begin() + dst);
        std::copy_n(ch.bary.begin() + static_cast<std::ptrdiff_t>(src), ch.counts[k], st.bary.begin() + dst);
        src += ch.counts[k];
      }
      ch = Lists{};
    }
  });
  st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return cache;
}

Result<Binding> CandidateCache::bind(const BindParams& params, std::span<const SetEdit> edits,
                                     const BindProgress& progress, CandidateCacheStats* stats) const {
  const auto t0 = std::chrono::steady_clock::now();
  const State& st = *state_;
  auto ctx = make_context(st.skin, st.cage, st.rest, params, st.label_ptr());
  if (!ctx) return ctx.error();
  std::atomic<uint64_t> queried{0};
  // in point order: from the lists no spatial chunks are needed, and the lists and the binding's tables
  // are then read and written as they lie
  std::vector<uint32_t> order(st.skin.size());
  std::iota(order.begin(), order.end(), 0u);
  auto b = run_registration(*ctx, edits, progress, [&] { return CachedSource(st, queried); }, t0, order);
  if (b && stats) *stats = {st.skin.size() - queried.load(), queried.load()};
  return b;
}

bool CandidateCache::fits(std::span<const glm::vec3> skin, const Cage& cage, std::span<const glm::vec3> rest,
                          const PartLabels* labels) const {
  const State& st = *state_;
  auto same = [](std::span<const glm::vec3> a, std::span<const glm::vec3> b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size_bytes()) == 0);
  };
  const bool labelled = labels && !labels->empty();
  if (labelled != st.labels.has_value() || (labelled && !(*st.labels == *labels))) return false;
  return same(st.skin, skin) && same(st.rest, rest) && st.cage.elements == cage.elements &&
         st.cage.polygons.num_vertices() == cage.polygons.num_vertices() &&
         st.cage.polygons.face_start == cage.polygons.face_start &&
         st.cage.polygons.face_vertices == cage.polygons.face_vertices;  // h: the polygons' mean edge
}

std::string registration_difference(const Binding& a, const Binding& b) {
  auto same_bits = [](const auto& x, const auto& y) {
    return x.size() == y.size() && (x.empty() || std::memcmp(x.data(), y.data(), x.size() * sizeof(x[0])) == 0);
  };
#define CAGEWRAP_COMPARE(field) \
  if (!same_bits(a.field, b.field)) return #field;
  CAGEWRAP_COMPARE(offsets) CAGEWRAP_COMPARE(ids) CAGEWRAP_COMPARE(weights) CAGEWRAP_COMPARE(bary)
  CAGEWRAP_COMPARE(set_offsets) CAGEWRAP_COMPARE(set_ids) CAGEWRAP_COMPARE(set_weights)
  CAGEWRAP_COMPARE(rigid_points) CAGEWRAP_COMPARE(rigid_element) CAGEWRAP_COMPARE(rigid_bary)
  CAGEWRAP_COMPARE(separated) CAGEWRAP_COMPARE(reach) CAGEWRAP_COMPARE(invalid_elements)
  CAGEWRAP_COMPARE(element_status) CAGEWRAP_COMPARE(rest_cage)
#undef CAGEWRAP_COMPARE
  if (!(a.params == b.params)) return "params";
  if (a.h != b.h) return "h";
  if (a.origin != b.origin) return "origin";
  if (a.num_points != b.num_points || a.num_cage_vertices != b.num_cage_vertices) return "sizes";
  if (a.quality_inside != b.quality_inside) return "quality_inside";
  if (a.max_set_size != b.max_set_size || a.total_set_size != b.total_set_size) return "set sizes";
  if (a.separation_applied != b.separation_applied || a.total_separated != b.total_separated ||
      a.separated_points != b.separated_points)
    return "separation figures";
  if (a.elements != b.elements) return "elements";
  return {};
}

size_t CandidateCache::num_points() const { return state_->skin.size(); }
uint64_t CandidateCache::entries() const { return state_->ids.size(); }
size_t CandidateCache::bytes() const {
  const State& st = *state_;
  return st.offsets.size() * 4 + st.ids.size() * 4 + st.dist2.size() * 8 + st.bary.size() * 16 + st.cover2.size() * 8;
}
double CandidateCache::seconds() const { return state_->seconds; }

Result<Binding> rebind_points(const Binding& binding, std::span<const glm::vec3> skin, const Cage& cage,
                              std::span<const glm::vec3> rest, const BindParams& params,
                              std::span<const SetEdit> edits, std::span<const uint32_t> points,
                              const PartLabels* labels) {
  auto r = Rebinder::create(skin, cage, rest, params, labels);
  if (!r) return r.error();
  Binding out = binding;
  if (auto s = r->update(out, edits, points); !s) return s.error();
  return out;
}

Result<Binding> bind_skin(std::span<const glm::vec3> skin, const Cage& cage, std::span<const glm::vec3> rest,
                          const BindParams& params, std::span<const SetEdit> edits, const BindProgress& progress,
                          const PartLabels* labels) {
  const auto t0 = std::chrono::steady_clock::now();
  auto ctx = make_context(skin, cage, rest, params, labels);
  if (!ctx) return ctx.error();
  ElementBvh bvh(ctx->rest, ctx->cage->elements, ctx->valid_ids);
  return run_registration(*ctx, edits, progress, [&bvh] { return ChunkedBvhSource(bvh); }, t0);
}

Result<Binding> bind_skin_brute_force(std::span<const glm::vec3> skin, const Cage& cage,
                                      std::span<const glm::vec3> rest, const BindParams& params,
                                      std::span<const SetEdit> edits, const PartLabels* labels) {
  const auto t0 = std::chrono::steady_clock::now();
  auto ctx = make_context(skin, cage, rest, params, labels);
  if (!ctx) return ctx.error();
  return run_registration(*ctx, edits, {}, [] { return BruteForceSource{}; }, t0);
}

Result<std::vector<uint32_t>> quality_failures(const Binding& binding, std::span<const glm::vec3> skin,
                                               std::span<const SetEdit>) {
  if (skin.size() != binding.num_points)
    return make_error(ErrorCode::kTopologyMismatch, "the binding has " + std::to_string(binding.num_points) +
                                                        " points but the skin has " + std::to_string(skin.size()));
  // the binding's own sets (they already hold the edits it was made with), point by point
  std::vector<uint32_t> failures;
  for (uint32_t p = 0; p < binding.num_points; ++p)
    if (!well_bound(binding, skin, p)) failures.push_back(p);
  return failures;
}

}  // namespace cagewrap
