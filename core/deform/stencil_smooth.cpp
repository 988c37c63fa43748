#include "core/deform/stencil_smooth.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <glm/geometric.hpp>

#include "core/cage/cage_attachment.h"
#include "core/character/character.h"
#include "core/character/skinning.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

namespace cagewrap {

namespace {
// |a - b|_1 of two sparse weight lists
double influence_distance(const Influences& a, const Influences& b) {
  double d = 0.0;
  for (const auto& [j, w] : a) {
    float o = 0.0f;
    for (const auto& [k, x] : b)
      if (k == j) o = x;
    d += std::abs(double(w) - double(o));
  }
  for (const auto& [k, x] : b) {
    bool in_a = false;
    for (const auto& [j, w] : a) in_a |= j == k;
    if (!in_a) d += std::abs(double(x));
  }
  return d;
}
}  // namespace

SkinGraph build_skin_graph(std::span<const glm::vec3> positions, std::span<const Tri> triangles,
                           std::span<const Influences> influences) {
  SkinGraph g;
  const bool have_t = influences.size() == positions.size();
  const size_t n = positions.size();
  if (n == 0) return g;
  // weld exact duplicates: sort by position, one node per run
  std::vector<uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  auto less = [&](uint32_t a, uint32_t b) {
    const glm::vec3 &p = positions[a], &q = positions[b];
    if (p.x != q.x) return p.x < q.x;
    if (p.y != q.y) return p.y < q.y;
    if (p.z != q.z) return p.z < q.z;
    return a < b;
  };
  std::sort(order.begin(), order.end(), less);
  g.node.assign(n, 0);
  uint32_t nodes = 0;
  for (size_t i = 0; i < n; ++i) {
    if (i > 0 && (positions[order[i]] != positions[order[i - 1]] ||
                  (have_t && influence_distance(influences[order[i]], influences[order[i - 1]]) > 1e-3)))
      ++nodes;
    g.node[order[i]] = nodes;
  }
  ++nodes;
  struct Edge {
    uint32_t a, b;
    float w;
  };
  std::vector<Edge> edges;
  edges.reserve(triangles.size() * 6);
  for (const Tri& t : triangles)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = t[k], b = t[(k + 1) % 3];
      if (a >= n || b >= n) continue;
      const uint32_t na = g.node[a], nb = g.node[b];
      if (na == nb) continue;
      float w = 1.0f;
      if (have_t) {
        const double x = std::max(0.0, 1.0 - influence_distance(influences[a], influences[b]) / kSmoothWeightJump);
        w = static_cast<float>(x * x);
      }
      edges.push_back({na, nb, w});
      edges.push_back({nb, na, w});
    }
  std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) {
    return x.a != y.a ? x.a < y.a : (x.b != y.b ? x.b < y.b : x.w < y.w);
  });
  // one entry per neighbour (the smallest weight of its edges)
  edges.erase(std::unique(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) { return x.a == y.a && x.b == y.b; }),
              edges.end());
  g.offsets.assign(size_t(nodes) + 1, 0);
  for (const auto& e : edges) ++g.offsets[e.a + 1];
  for (size_t i = 0; i < nodes; ++i) g.offsets[i + 1] += g.offsets[i];
  g.neighbours.resize(edges.size());
  g.weights.resize(edges.size());
  for (size_t i = 0; i < edges.size(); ++i) g.neighbours[i] = edges[i].b, g.weights[i] = edges[i].w;
  g.positions.resize(nodes);
  for (size_t i = 0; i < n; ++i) g.positions[g.node[i]] = positions[i];
  if (have_t) {
    g.influence.resize(nodes);
    for (size_t i = 0; i < n; ++i) g.influence[g.node[i]] = influences[i];
  }
  return g;
}

SkinGraph character_skin_graph(const Character& ch) {
  const PointJoints pj = point_joint_nodes(ch);
  std::vector<Influences> infl(pj.start.size() - 1);
  for (size_t p = 0; p < infl.size(); ++p)
    for (uint32_t i = pj.start[p]; i < pj.start[p + 1]; ++i) infl[p].emplace_back(pj.node[i], pj.weight[i]);
  const PolyMesh skin = combined_topology(ch);
  const Triangulation tris = triangulate(skin);
  return build_skin_graph(skin.positions, tris.triangles, infl);
}

namespace {
using Entry = std::pair<uint32_t, float>;  // cage vertex, weight

// Adds w to vertex v's entry in `acc` (unsorted, merged by id).
void add_entry(std::vector<Entry>& acc, uint32_t v, float w) {
  auto it = std::find_if(acc.begin(), acc.end(), [&](const Entry& a) { return a.first == v; });
  if (it == acc.end())
    acc.emplace_back(v, w);
  else
    it->second += w;
}

// Keeps the `max_entries` heaviest, sorted by id, renormalized to sum to one.
void finish_row(std::vector<Entry>& acc, uint32_t max_entries) {
  if (acc.size() > max_entries) {
    std::partial_sort(acc.begin(), acc.begin() + max_entries, acc.end(),
                      [](const Entry& a, const Entry& b) { return a.second > b.second || (a.second == b.second && a.first < b.first); });
    acc.resize(max_entries);
  }
  std::sort(acc.begin(), acc.end());
  double sum = 0.0;
  for (const Entry& e : acc) sum += e.second;
  if (sum > 0)
    for (Entry& e : acc) e.second = static_cast<float>(e.second / sum);
}
}  // namespace

namespace {
// E per node (from the first member with a row; empty: none)
std::vector<Influences> rig_weights(const Binding& b, const SkinGraph& g, const Character& ch, const CageAttachment& att) {
  const size_t nodes = g.num_nodes();
  std::vector<Influences> e(nodes);
  if (b.params.variant != Variant::kExtended || g.node.size() != b.num_points || att.skin >= ch.skins.size() ||
      att.influence_start.size() != size_t(b.num_cage_vertices) + 1)
    return e;
  const Skin& skin = ch.skins[att.skin];
  std::vector<uint8_t> have(nodes, 0);
  for (uint32_t p = 0; p < b.num_points; ++p) {
    const uint32_t nd = g.node[p];
    if (have[nd] || b.offsets[p] == b.offsets[p + 1]) continue;
    have[nd] = 1;
    Influences& row = e[nd];
    for (uint32_t k = b.offsets[p]; k < b.offsets[p + 1]; ++k) {
      const uint32_t v = b.ids[k];
      if (v >= b.num_cage_vertices) continue;
      for (uint32_t i = att.influence_start[v]; i < att.influence_start[v + 1]; ++i) {
        const uint32_t j = att.influence_joint[i];
        if (j >= skin.joints.size()) continue;
        const uint32_t node = skin.joints[j];
        const float w = b.weights[k] * att.influence_weight[i];
        auto it = std::find_if(row.begin(), row.end(), [&](const auto& x) { return x.first == node; });
        if (it == row.end()) row.emplace_back(node, w);
        else it->second += w;
      }
    }
  }
  return e;
}
}  // namespace

std::vector<float> rig_weight_excess(const Binding& b, const SkinGraph& g, const Character& ch,
                                     const CageAttachment& att) {
  const size_t nodes = g.num_nodes();
  std::vector<float> out(nodes, 0.0f);
  if (g.influence.size() != nodes) return out;
  const std::vector<Influences> e = rig_weights(b, g, ch, att);
  std::vector<uint8_t> have(nodes, 0);
  for (size_t nd = 0; nd < nodes; ++nd) have[nd] = !e[nd].empty();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, nodes, 1024), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t nd = r.begin(); nd != r.end(); ++nd) {
      if (!have[nd]) continue;
      double worst = 0.0;
      for (uint32_t k = g.offsets[nd]; k < g.offsets[nd + 1]; ++k) {
        const uint32_t m = g.neighbours[k];
        if (!have[m]) continue;
        const double len = glm::length(glm::dvec3(g.positions[nd]) - glm::dvec3(g.positions[m]));
        if (!(len > 0)) continue;
        const double excess = influence_distance(e[nd], e[m]) - influence_distance(g.influence[nd], g.influence[m]);
        worst = std::max(worst, excess / len * b.h);
      }
      out[nd] = static_cast<float>(worst);
    }
  });
  return out;
}

std::function<bool(uint32_t, uint32_t)> related_to_file_weights(const SkinGraph& g, const Character& ch,
                                                               const CageAttachment& att) {
  const Skin* skin = att.skin < ch.skins.size() ? &ch.skins[att.skin] : nullptr;
  return [&g, &ch, &att, skin](uint32_t node, uint32_t v) {
    if (!skin || node >= g.influence.size() || v >= att.label_joint.size() || att.label_joint[v] >= skin->joints.size())
      return true;
    const uint32_t label = skin->joints[att.label_joint[v]];
    for (const auto& [j, w] : g.influence[node]) {
      if (w <= 0.0f) continue;
      if (j == label) return true;
      if (j < ch.skeleton.size() && ch.skeleton.node(j).parent == static_cast<int32_t>(label)) return true;
    }
    return false;
  };
}

void smooth_stencil(Binding& b, const SkinGraph& g, const StencilSmoothing& opt, std::span<const float> jump,
                    const std::function<bool(uint32_t, uint32_t)>& allowed) {
  if (b.params.variant != Variant::kExtended || opt.iterations == 0 || g.empty() || g.node.size() != b.num_points ||
      b.offsets.size() != size_t(b.num_points) + 1)
    return;
  const size_t nodes = g.num_nodes();
  const uint32_t cap = std::max<uint32_t>(1, opt.max_entries);
  // node rows: the mean of the rows of the node's vertices that have one
  std::vector<std::vector<Entry>> rows(nodes);
  for (uint32_t p = 0; p < b.num_points; ++p)
    for (uint32_t e = b.offsets[p]; e < b.offsets[p + 1]; ++e) add_entry(rows[g.node[p]], b.ids[e], b.weights[e]);
  for (auto& row : rows)
    if (!row.empty()) finish_row(row, UINT32_MAX);  // sorted by id, the mean of the members
  // each node's own cage vertices (always allowed)
  std::vector<std::vector<uint32_t>> raw(allowed ? nodes : 0);
  for (size_t nd = 0; nd < raw.size(); ++nd)
    for (const Entry& e : rows[nd]) raw[nd].push_back(e.first);
  // where to smooth: smoothstep(jump_low, jump_high, g) per node, spread over the rings; without
  // g, everywhere
  std::vector<float> need(nodes, 1.0f);
  const bool local = !jump.empty();
  if (local) {
    if (jump.size() != nodes) return;
    for (size_t nd = 0; nd < nodes; ++nd) {
      const double x = std::clamp((double(jump[nd]) - opt.jump_low) / std::max(1e-9, opt.jump_high - opt.jump_low), 0.0, 1.0);
      need[nd] = static_cast<float>(x * x * (3 - 2 * x));
    }
    std::vector<float> spread = need;
    for (uint32_t it = 0; it < opt.iterations; ++it) {
      for (size_t nd = 0; nd < nodes; ++nd)
        for (uint32_t k = g.offsets[nd]; k < g.offsets[nd + 1]; ++k)
          spread[nd] = std::max(spread[nd], static_cast<float>(opt.spread) * need[g.neighbours[k]]);
      need = spread;
    }
    // a faint reach leaves the row as it was: the change stays where it is needed
    for (float& x : need)
      if (x < kSmoothMinNeed) x = 0.0f;
  }
  // an edge longer than h / edge_scale blends less, by the square of the ratio: the smoothing then
  // reaches about as far on a coarse skin as on a dense one (a few cage edges), not 32 long edges
  std::vector<float> edge(g.neighbours.size());
  for (size_t nd = 0; nd < nodes; ++nd)
    for (uint32_t k = g.offsets[nd]; k < g.offsets[nd + 1]; ++k) {
      double w = g.weights.size() == g.neighbours.size() ? double(g.weights[k]) : 1.0;
      if (opt.edge_scale > 0 && g.positions.size() == nodes) {
        const double len = glm::length(glm::dvec3(g.positions[nd]) - glm::dvec3(g.positions[g.neighbours[k]]));
        const double f = b.h / (opt.edge_scale * len);
        if (f < 1) w *= f * f;
      }
      edge[k] = static_cast<float>(w);
    }
  // the nodes that blend (a row, a share to take, neighbours with rows across edges of some weight),
  // with their neighbour count and weight sum, which stay the same through the steps; the others'
  // rows never change
  struct Active {
    uint32_t node, count;
    double wsum;
  };
  std::vector<Active> active;
  for (size_t nd = 0; nd < nodes; ++nd) {
    if (rows[nd].empty() || !(need[nd] > 0)) continue;
    uint32_t count = 0;
    double wsum = 0.0;
    for (uint32_t k = g.offsets[nd]; k < g.offsets[nd + 1]; ++k)
      if (!rows[g.neighbours[k]].empty()) ++count, wsum += edge[k];
    if (count > 0 && wsum > 0) active.push_back({static_cast<uint32_t>(nd), count, wsum});
  }
  std::vector<std::vector<Entry>> next(active.size());
  // per thread: a dense accumulator over the cage vertices and the ones it touched
  struct Scratch {
    std::vector<float> w;
    std::vector<uint32_t> touched;
  };
  tbb::enumerable_thread_specific<Scratch> scratch;
  for (uint32_t it = 0; it < opt.iterations; ++it) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, active.size(), 256), [&](const tbb::blocked_range<size_t>& r) {
      Scratch& sc = scratch.local();
      if (sc.w.size() < b.num_cage_vertices) sc.w.assign(b.num_cage_vertices, 0.0f);
      auto add = [&](const std::vector<Entry>& row, float scale) {
        for (const Entry& e : row) {
          if (e.first >= sc.w.size()) continue;
          if (sc.w[e.first] == 0.0f) sc.touched.push_back(e.first);
          sc.w[e.first] += scale * e.second;
        }
      };
      for (size_t i = r.begin(); i != r.end(); ++i) {
        const auto [nd, count, wsum] = active[i];
        // x + blend * sum_k w_k (x_k - x) / count, over the neighbours with a row
        const double blend = opt.blend * need[nd];
        sc.touched.clear();
        add(rows[nd], static_cast<float>(1.0 - blend * wsum / count));
        for (uint32_t k = g.offsets[nd]; k < g.offsets[nd + 1]; ++k)
          if (!rows[g.neighbours[k]].empty() && edge[k] > 0)
            add(rows[g.neighbours[k]], static_cast<float>(blend * edge[k] / count));
        std::vector<Entry>& acc = next[i];
        acc.clear();
        for (uint32_t v : sc.touched) {
          const float x = sc.w[v];
          sc.w[v] = 0.0f;
          if (x == 0.0f) continue;
          // a vertex the node's own row does not hold joins only when the rule allows it
          if (allowed && !std::binary_search(raw[nd].begin(), raw[nd].end(), v) && !allowed(nd, v)) continue;
          acc.emplace_back(v, x);
        }
        finish_row(acc, cap);
      }
    });
    for (size_t i = 0; i < active.size(); ++i) std::swap(rows[active[i].node], next[i]);
  }
  // write the rows back; a point whose node was not blended keeps its own row bit for bit
  auto own = [&](uint32_t p) { return b.offsets[p] == b.offsets[p + 1] || need[g.node[p]] == 0.0f; };
  std::vector<uint32_t> offsets(size_t(b.num_points) + 1, 0);
  for (uint32_t p = 0; p < b.num_points; ++p)
    offsets[p + 1] = offsets[p] + (own(p) ? b.offsets[p + 1] - b.offsets[p] : static_cast<uint32_t>(rows[g.node[p]].size()));
  std::vector<uint32_t> ids(offsets.back());
  std::vector<float> weights(offsets.back());
  for (uint32_t p = 0; p < b.num_points; ++p) {
    uint32_t o = offsets[p];
    if (own(p)) {
      for (uint32_t e = b.offsets[p]; e < b.offsets[p + 1]; ++e) ids[o] = b.ids[e], weights[o] = b.weights[e], ++o;
    } else {
      for (const Entry& e : rows[g.node[p]]) ids[o] = e.first, weights[o] = e.second, ++o;
    }
  }
  b.offsets = std::move(offsets);
  b.ids = std::move(ids);
  b.weights = std::move(weights);
}

namespace {

// Cholesky factor (lower, in place) of the symmetric positive definite n x n block of G (row stride
// `stride`) over the indices `free`; false when it is not positive definite.
bool cholesky(const std::vector<double>& G, size_t stride, const std::vector<uint32_t>& free, std::vector<double>& L) {
  const size_t n = free.size();
  L.assign(n * n, 0.0);
  for (size_t i = 0; i < n; ++i)
    for (size_t j = 0; j <= i; ++j) {
      double x = G[free[i] * stride + free[j]];
      for (size_t k = 0; k < j; ++k) x -= L[i * n + k] * L[j * n + k];
      if (i == j) {
        if (!(x > 0)) return false;
        L[i * n + i] = std::sqrt(x);
      } else {
        L[i * n + j] = x / L[j * n + j];
      }
    }
  return true;
}

// Solves L L^T x = b in place.
void cholesky_solve(const std::vector<double>& L, size_t n, std::vector<double>& x) {
  for (size_t i = 0; i < n; ++i) {
    for (size_t k = 0; k < i; ++k) x[i] -= L[i * n + k] * x[k];
    x[i] /= L[i * n + i];
  }
  for (size_t i = n; i-- > 0;) {
    for (size_t k = i + 1; k < n; ++k) x[i] -= L[k * n + i] * x[k];
    x[i] /= L[i * n + i];
  }
}

// min a^T G a / 2 - c^T a over the simplex {a >= 0, sum a = 1}, G (m x m) positive definite, by the
// primal active-set method from the feasible `a` (the result replaces it): each step solves the
// problem with the working set's entries held at zero, walks toward its solution until an entry
// reaches zero, and frees the entry whose multiplier is most negative when none does. A handful of
// steps for the rows here (at most 3K cage vertices, 16 after the smoothing); bounded at 8m + 8, when
// `a` is still feasible and no worse than it came in.
void solve_simplex_qp(const std::vector<double>& G, const std::vector<double>& c, uint32_t m, std::vector<double>& a,
                      std::vector<double>& u, std::vector<double>& v, std::vector<double>& grad) {
  grad.assign(m, 0.0);
  std::vector<uint8_t> fixed(m, 0);
  for (uint32_t k = 0; k < m; ++k) fixed[k] = !(a[k] > 0);
  std::vector<uint32_t> free;
  std::vector<double> L;
  for (uint32_t step = 0; step < 8 * m + 8; ++step) {
    for (uint32_t k = 0; k < m; ++k) {
      double x = -c[k];
      for (uint32_t l = 0; l < m; ++l) x += G[k * m + l] * a[l];
      grad[k] = x;
    }
    free.clear();
    for (uint32_t k = 0; k < m; ++k)
      if (!fixed[k]) free.push_back(k);
    const size_t n = free.size();
    double mu = 0.0;
    std::vector<double>& p = u;  // the step on the free entries
    p.assign(n, 0.0);
    if (n > 0) {
      if (!cholesky(G, m, free, L)) return;
      // p = -G^-1 (g + mu 1) with sum p = 0: mu = -(1^T G^-1 g) / (1^T G^-1 1)
      v.assign(n, 0.0);
      for (size_t i = 0; i < n; ++i) p[i] = grad[free[i]], v[i] = 1.0;
      cholesky_solve(L, n, p);
      cholesky_solve(L, n, v);
      double num = 0.0, den = 0.0;
      for (size_t i = 0; i < n; ++i) num += p[i], den += v[i];
      mu = -num / den;
      for (size_t i = 0; i < n; ++i) p[i] = -(p[i] + mu * v[i]);
    }
    double size = 0.0;
    for (size_t i = 0; i < n; ++i) size = std::max(size, std::abs(p[i]));
    if (size < 1e-12) {
      // optimal on this working set: multipliers of the fixed entries, g_k + mu >= 0
      if (n == 0) return;
      int worst = -1;
      double most = -1e-12;
      for (uint32_t k = 0; k < m; ++k)
        if (fixed[k] && grad[k] + mu < most) most = grad[k] + mu, worst = static_cast<int>(k);
      if (worst < 0) return;
      fixed[static_cast<uint32_t>(worst)] = 0;
      continue;
    }
    double alpha = 1.0;
    int blocking = -1;
    for (size_t i = 0; i < n; ++i)
      if (p[i] < 0) {
        const double t = -a[free[i]] / p[i];
        if (t < alpha) alpha = t, blocking = static_cast<int>(free[i]);
      }
    for (size_t i = 0; i < n; ++i) a[free[i]] = std::max(0.0, a[free[i]] + alpha * p[i]);
    if (blocking >= 0) {
      a[static_cast<uint32_t>(blocking)] = 0.0;
      fixed[static_cast<uint32_t>(blocking)] = 1;
    }
  }
}

}  // namespace

void reweight_rows(Binding& b, const Character& ch, const CageAttachment& att, double lambda) {
  if (b.params.variant != Variant::kExtended || b.num_points != ch.num_vertices() || att.skin >= ch.skins.size() ||
      att.influence_start.size() != size_t(b.num_cage_vertices) + 1 || b.offsets.size() != size_t(b.num_points) + 1 ||
      !(lambda > 0))
    return;
  const Skin& skin = ch.skins[att.skin];
  const PointJoints T = point_joint_nodes(ch);
  if (T.start.size() != size_t(b.num_points) + 1) return;
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, b.num_points, 512), [&](const tbb::blocked_range<uint32_t>& r) {
    std::vector<uint32_t> joints;  // skeleton nodes of the point's problem
    std::vector<double> A, t, G, c, a, u, v, grad;
    for (uint32_t p = r.begin(); p != r.end(); ++p) {
      const uint32_t begin = b.offsets[p], m = b.offsets[p + 1] - begin;
      if (m < 2) continue;
      joints.clear();
      for (uint32_t i = T.start[p]; i < T.start[p + 1]; ++i) joints.push_back(T.node[i]);
      for (uint32_t k = 0; k < m; ++k) {
        const uint32_t cv = b.ids[begin + k];
        if (cv >= b.num_cage_vertices) continue;
        for (uint32_t i = att.influence_start[cv]; i < att.influence_start[cv + 1]; ++i)
          if (att.influence_joint[i] < skin.joints.size()) joints.push_back(skin.joints[att.influence_joint[i]]);
      }
      std::sort(joints.begin(), joints.end());
      joints.erase(std::unique(joints.begin(), joints.end()), joints.end());
      const size_t nj = joints.size();
      auto index = [&](uint32_t j) { return size_t(std::lower_bound(joints.begin(), joints.end(), j) - joints.begin()); };
      A.assign(nj * m, 0.0);  // column k: cage vertex k's joint weights
      t.assign(nj, 0.0);      // the file's weights
      for (uint32_t i = T.start[p]; i < T.start[p + 1]; ++i) t[index(T.node[i])] += T.weight[i];
      for (uint32_t k = 0; k < m; ++k) {
        const uint32_t cv = b.ids[begin + k];
        if (cv >= b.num_cage_vertices) continue;
        for (uint32_t i = att.influence_start[cv]; i < att.influence_start[cv + 1]; ++i)
          if (att.influence_joint[i] < skin.joints.size())
            A[index(skin.joints[att.influence_joint[i]]) * m + k] += att.influence_weight[i];
      }
      // a point whose file weights no vertex of its row carries (a rigid piece under a node that
      // is not a joint) cannot come closer to them: its row stays as it is
      double reachable = 0.0;
      for (size_t j = 0; j < nj; ++j) {
        bool carried = false;
        for (uint32_t k = 0; k < m && !carried; ++k) carried = A[j * m + k] > 0;
        if (carried) reachable += t[j];
      }
      if (!(reachable > 1e-6)) continue;
      // G = A^T A + lambda I, c = A^T t + lambda a0: minimize a^T G a / 2 - c^T a on the simplex
      a.assign(m, 0.0);
      for (uint32_t k = 0; k < m; ++k) a[k] = b.weights[begin + k];
      G.assign(size_t(m) * m, 0.0);
      c.assign(m, 0.0);
      for (uint32_t k = 0; k < m; ++k) {
        for (uint32_t l = k; l < m; ++l) {
          double x = 0.0;
          for (size_t j = 0; j < nj; ++j) x += A[j * m + k] * A[j * m + l];
          G[k * m + l] = G[l * m + k] = x;
        }
        G[k * m + k] += lambda;
        double x = lambda * a[k];
        for (size_t j = 0; j < nj; ++j) x += A[j * m + k] * t[j];
        c[k] = x;
      }
      solve_simplex_qp(G, c, m, a, u, v, grad);
      for (uint32_t k = 0; k < m; ++k) b.weights[begin + k] = static_cast<float>(a[k]);
    }
  });
}

}  // namespace cagewrap
