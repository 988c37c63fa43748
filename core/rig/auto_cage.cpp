#include "core/rig/auto_cage.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <memory>
#include <thread>
#include <unordered_map>
#include <unordered_set>

// the mesh header first: QuadricT.hh needs the vector traits it brings
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <tbb/parallel_for.h>
#include <OpenMesh/Core/Geometry/QuadricT.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModAspectRatioT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_inverse.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include "core/cage/cage.h"
#include "core/cage/cage_attachment.h"
#include "core/deform/part_labels.h"
#include "core/geometry/element_bvh.h"
#include "core/cage/offset_wrap.h"
#include "core/cage/quad_pairing.h"
#include "core/deform/registration.h"
#include "core/character/skinning.h"
#include "core/geometry/surface_distance.h"
#include "core/geometry/triangle_bvh.h"
#include "core/geometry/weld.h"

namespace cagewrap {

namespace {

// Decimation guards.
constexpr float kMaxAspect = 5.0f;            // no collapse may leave a triangle worse than this (L / h)
constexpr double kMaxNormalDeviation = 60.0;  // degrees a face normal may turn in one collapse
// Error added per collapse: isotropy * |edge|^4, so flat regions still prefer short edges (rounder
// triangles). Area-weighted quadric errors are length^4 too, so the balance does not depend on units.
constexpr double kIsotropy = 1e-3;
constexpr double kJointBoost = 8.0;  // error factor at a joint per unit of joint_detail
// Shells: a group of skin pieces wrapped on its own gets at least this many triangles (a piece
// whose share of the budget would be smaller joins its nearest neighbour's group instead).
constexpr uint32_t kMinShellFaces = 20;
// Inflation.
constexpr double kEdgeShare = 0.25;  // per step, a vertex moves at most this share of its shortest edge
constexpr double kRoomShare = 0.4;   // ... and this share of the free distance in front of it
constexpr int kMaxInflateSteps = 64;
constexpr double kRelax = 0.5;  // tangential relaxation weight between steps
constexpr int kMaxFitRounds = 12;
constexpr double kFullBend =
    0.35;  // radians (20 degrees): a valley this sharp gets only concave_share of the clearance
constexpr double kFitMargin = 0.2;  // fitted skin points end at least this share of the clearance inside

struct CageTraits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
};
using OmMesh = OpenMesh::TriMesh_ArrayKernelT<CageTraits>;

// Area-weighted error quadrics (Garland-Heckbert) times a per-vertex factor that grows near joints,
// plus a small edge-length term.
template <class MeshT>
class ModCageQuadricT : public OpenMesh::Decimater::ModBaseT<MeshT> {
 public:
  DECIMATING_MODULE(ModCageQuadricT, MeshT, CageQuadric);
  using Quadric = OpenMesh::Geometry::QuadricT<double>;

  explicit ModCageQuadricT(MeshT& mesh) : Base(mesh, false) { mesh.add_property(quadrics_); }
  ~ModCageQuadricT() override { Base::mesh().remove_property(quadrics_); }
  // A vertex property of the mesh holding each vertex's error factor (>= 1).
  void set_factors(OpenMesh::VPropHandleT<double> factor) { factor_ = factor; }

  void initialize() override {
    MeshT& m = Base::mesh();
    for (auto v : m.vertices()) m.property(quadrics_, v).clear();
    for (auto f : m.faces()) {
      auto fv = m.fv_iter(f);
      const auto v0 = *fv, v1 = *(++fv), v2 = *(++fv);
      const OpenMesh::Vec3d p0 = m.point(v0), p1 = m.point(v1), p2 = m.point(v2);
      OpenMesh::Vec3d n = (p1 - p0) % (p2 - p0);
      const double twice_area = n.norm();
      if (twice_area <= 0) continue;
      n /= twice_area;
      Quadric q(n[0], n[1], n[2], -(p0 | n));
      q *= 0.5 * twice_area;
      m.property(quadrics_, v0) += q;
      m.property(quadrics_, v1) += q;
      m.property(quadrics_, v2) += q;
    }
  }

  float collapse_priority(const CollapseInfo& ci) override {
    const MeshT& m = Base::mesh();
    Quadric q = m.property(quadrics_, ci.v0);
    q += m.property(quadrics_, ci.v1);
    const double len2 = (ci.p1 - ci.p0).sqrnorm();
    const double err = q(ci.p1) + isotropy_ * len2 * len2;
    return static_cast<float>(err * std::max(m.property(factor_, ci.v0), m.property(factor_, ci.v1)));
  }

  void postprocess_collapse(const CollapseInfo& ci) override {
    Base::mesh().property(quadrics_, ci.v1) += Base::mesh().property(quadrics_, ci.v0);
  }

 private:
  OpenMesh::VPropHandleT<Quadric> quadrics_;
  OpenMesh::VPropHandleT<double> factor_;
  double isotropy_ = kIsotropy;
};

double face_aspect(const OmMesh& m, OmMesh::FaceHandle f) {
  auto fv = m.cfv_iter(f);
  const OpenMesh::Vec3d a = m.point(*fv), b = m.point(*(++fv)), c = m.point(*(++fv));
  return triangle_aspect({a[0], a[1], a[2]}, {b[0], b[1], b[2]}, {c[0], c[1], c[2]});
}

// Worst aspect of the faces around `v` were it moved to `to`, or infinity when a face would turn
// by more than the decimater's normal guard allows.
double ring_aspect_if_moved(OmMesh& m, OmMesh::VertexHandle v, const OpenMesh::Vec3d& to,
                            OmMesh::FaceHandle skip0, OmMesh::FaceHandle skip1) {
  const OpenMesh::Vec3d from = m.point(v);
  std::vector<std::pair<OmMesh::FaceHandle, OpenMesh::Vec3d>> before;
  for (auto f : m.vf_range(v))
    if (f != skip0 && f != skip1) before.emplace_back(f, m.calc_face_normal(f));
  m.set_point(v, to);
  double worst = 0.0;
  const double min_cos = std::cos(kMaxNormalDeviation * 3.141592653589793 / 180.0);
  for (const auto& [f, n] : before) {
    if ((m.calc_face_normal(f) | n) < min_cos)
      worst = INFINITY;
    else
      worst = std::max(worst, face_aspect(m, f));
  }
  m.set_point(v, from);
  return worst;
}

// What the decimater's aspect guard cannot fix (slivers it inherited): flips the longest edge of a
// cap, or collapses the shortest edge of a needle, whenever that makes the neighbourhood better.
void clean_slivers(OmMesh& m) {
  m.request_vertex_status();
  m.request_edge_status();
  m.request_face_status();
  for (int pass = 0; pass < 4; ++pass) {
    bool changed = false;
    for (auto f : m.faces()) {
      if (m.status(f).deleted()) continue;
      const double aspect = face_aspect(m, f);
      if (aspect <= kMaxAspect) continue;
      OmMesh::HalfedgeHandle longest, shortest;
      double lmax = -1, lmin = INFINITY;
      for (auto h : m.fh_range(f)) {
        const double l = m.calc_edge_length(h);
        if (l > lmax) lmax = l, longest = h;
        if (l < lmin) lmin = l, shortest = h;
      }
      // a cap: flip its longest edge when both new triangles are better than the worse old one
      const auto e = m.edge_handle(longest);
      if (!m.is_boundary(e) && m.is_flip_ok(e)) {
        const auto g = m.opposite_face_handle(longest);
        const double old_worst = std::max(aspect, face_aspect(m, g));
        const OpenMesh::Vec3d n0 = m.calc_face_normal(f) + m.calc_face_normal(g);
        m.flip(e);
        const double new_worst =
            std::max(face_aspect(m, m.face_handle(longest)), face_aspect(m, m.opposite_face_handle(longest)));
        const bool folded = (m.calc_face_normal(m.face_handle(longest)) | n0) <= 0 ||
                            (m.calc_face_normal(m.opposite_face_handle(longest)) | n0) <= 0;
        if (new_worst < old_worst && !folded) {
          changed = true;
          continue;
        }
        m.flip(e);  // undo
      }
      // a needle: collapse its shortest edge onto either end
      for (auto h : {shortest, m.opposite_halfedge_handle(shortest)}) {
        if (!m.is_collapse_ok(h)) continue;
        const auto from = m.from_vertex_handle(h), to = m.to_vertex_handle(h);
        const double after =
            ring_aspect_if_moved(m, from, m.point(to), m.face_handle(h), m.opposite_face_handle(h));
        if (after < aspect && after <= kNeedleAspect) {
          m.collapse(h);
          changed = true;
          break;
        }
      }
    }
    if (!changed) break;
  }
  m.garbage_collection();
}

class Cancelled {};

struct Stage {
  const AutoCageProgress& progress;
  bool cancelled() const { return progress.cancel && progress.cancel->load(std::memory_order_relaxed); }
  void report(const char* stage, double share) const {
    if (progress.on_progress) progress.on_progress(stage, std::clamp(share, 0.0, 1.0));
  }
  void check() const {
    if (cancelled()) throw Cancelled{};
  }
};

// Triangle surface as flat arrays with the adjacency the inflation needs.
struct Surface {
  std::vector<glm::dvec3> p;               // #V
  std::vector<Tri> tris;                   // #T
  std::vector<std::vector<uint32_t>> nbr;  // #V one-ring vertices
  std::vector<uint32_t> piece;             // #V connected piece of each vertex

  void build_adjacency() {
    nbr.assign(p.size(), {});
    for (const Tri& t : tris)
      for (int k = 0; k < 3; ++k) {
        nbr[t[k]].push_back(t[(k + 1) % 3]);
        nbr[t[k]].push_back(t[(k + 2) % 3]);
      }
    for (auto& n : nbr) {
      std::sort(n.begin(), n.end());
      n.erase(std::unique(n.begin(), n.end()), n.end());
    }
    piece.assign(p.size(), UINT32_MAX);
    uint32_t count = 0;
    std::vector<uint32_t> stack;
    for (uint32_t seed = 0; seed < p.size(); ++seed) {
      if (piece[seed] != UINT32_MAX) continue;
      piece[seed] = count;
      stack.push_back(seed);
      while (!stack.empty()) {
        const uint32_t v = stack.back();
        stack.pop_back();
        for (uint32_t u : nbr[v])
          if (piece[u] == UINT32_MAX) {
            piece[u] = count;
            stack.push_back(u);
          }
      }
      ++count;
    }
  }
  std::vector<glm::dvec3> normals() const {  // area-weighted, unit
    std::vector<glm::dvec3> n(p.size(), glm::dvec3(0.0));
    for (const Tri& t : tris) {
      const glm::dvec3 c = glm::cross(p[t[1]] - p[t[0]], p[t[2]] - p[t[0]]);
      for (uint32_t v : t) n[v] += c;
    }
    for (auto& x : n) {
      const double l = glm::length(x);
      x = l > 0 ? x / l : glm::dvec3(0.0);
    }
    return n;
  }
  double shortest_edge(uint32_t v) const {
    double s = INFINITY;
    for (uint32_t u : nbr[v]) s = std::min(s, glm::length(p[u] - p[v]));
    return s;
  }
  std::vector<glm::vec3> float_positions() const { return {p.begin(), p.end()}; }
};

// Free distance in front of each vertex along its normal: the first triangle of the surface itself
// met from its outer side (one met from behind belongs to a piece this one already overlaps), on
// a piece this one does not already overlap (`overlapping`: sorted piece pairs lo << 32 | hi).
std::vector<double> room_ahead(const Surface& s, const std::vector<glm::dvec3>& n, double eps,
                               std::span<const uint64_t> overlapping) {
  const auto fp = s.float_positions();
  TriangleBvh bvh(fp, s.tris);
  std::vector<double> room(s.p.size(), INFINITY);
  tbb::parallel_for(size_t(0), s.p.size(), [&](size_t v) {
    if (glm::dot(n[v], n[v]) == 0.0) return;
    std::vector<TriangleHit> hits;
    bvh.all_hits(Ray{s.p[v], n[v]}, eps, INFINITY, hits);
    for (const TriangleHit& h : hits) {
      const Tri& t = s.tris[h.triangle];
      const uint32_t i = s.piece[v], j = s.piece[t[0]];
      if (i != j && std::binary_search(overlapping.begin(), overlapping.end(),
                                       (uint64_t(std::min(i, j)) << 32) | std::max(i, j)))
        continue;
      if (glm::dot(glm::cross(s.p[t[1]] - s.p[t[0]], s.p[t[2]] - s.p[t[0]]), n[v]) < 0)
        room[v] = std::min(room[v], h.t);
    }
  });
  return room;
}

// Flips the pieces (connected through edges) that are wound inside-out: negative volume about
// their own centroid. Returns how many were flipped.
uint32_t orient_pieces(std::span<const glm::vec3> p, std::vector<Tri>& tris) {
  std::vector<uint32_t> parent(tris.size());
  for (uint32_t i = 0; i < parent.size(); ++i) parent[i] = i;
  auto find = [&](uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::unordered_map<uint64_t, uint32_t> first;
  first.reserve(tris.size() * 2);
  for (uint32_t t = 0; t < tris.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = tris[t][k], b = tris[t][(k + 1) % 3];
      auto [it, fresh] = first.try_emplace((uint64_t(std::min(a, b)) << 32) | std::max(a, b), t);
      if (!fresh) {
        const uint32_t x = find(t), y = find(it->second);
        if (x != y) parent[std::max(x, y)] = std::min(x, y);
      }
    }
  std::unordered_map<uint32_t, glm::dvec4> centroid;  // xyz sum, count
  for (uint32_t t = 0; t < tris.size(); ++t)
    for (uint32_t v : tris[t]) centroid[find(t)] += glm::dvec4(glm::dvec3(p[v]), 1.0);
  std::unordered_map<uint32_t, double> volume;
  for (uint32_t t = 0; t < tris.size(); ++t) {
    const glm::dvec4 c = centroid[find(t)];
    const glm::dvec3 o = glm::dvec3(c) / c.w;
    const glm::dvec3 a = glm::dvec3(p[tris[t][0]]) - o, b = glm::dvec3(p[tris[t][1]]) - o,
                     d = glm::dvec3(p[tris[t][2]]) - o;
    volume[find(t)] += glm::dot(a, glm::cross(b, d));
  }
  uint32_t flipped = 0;
  for (const auto& [root, vol] : volume) flipped += vol < 0 ? 1 : 0;
  for (uint32_t t = 0; t < tris.size(); ++t)
    if (volume[find(t)] < 0) std::swap(tris[t][1], tris[t][2]);
  return flipped;
}

// Moves each vertex by up to want[v] along its normal, bounded by its edges and the room ahead;
// relaxes tangentially after each step; a step that makes the surface pass through itself is taken
// back for the vertices involved, which then stay. Returns the distance each vertex moved.
std::vector<double> push_out(Surface& s, std::vector<double> want, double eps, const Stage& stage) {
  const size_t n_v = s.p.size();
  const SurfaceDistance base(s.float_positions(), s.tris);
  std::vector<double> moved(n_v, 0.0);
  std::vector<char> frozen(n_v, 0);
  // pieces of the skin that already overlap each other may keep doing so; any other crossing is
  // the step's doing
  std::vector<uint64_t> overlapping;  // piece pairs (lo << 32 | hi), sorted
  auto pair_of = [&](const SelfCrossing& x) {
    const uint32_t i = s.piece[x.a], j = s.piece[s.tris[x.triangle][0]];
    return (uint64_t(std::min(i, j)) << 32) | std::max(i, j);
  };
  for (const SelfCrossing& x : self_crossings(s.float_positions(), s.tris))
    if (s.piece[x.a] != s.piece[s.tris[x.triangle][0]]) overlapping.push_back(pair_of(x));
  std::sort(overlapping.begin(), overlapping.end());
  const std::vector<double> room0 = room_ahead(s, s.normals(), eps, overlapping);
  for (int step = 0; step < kMaxInflateSteps; ++step) {
    stage.check();
    const auto n = s.normals();
    const auto room = room_ahead(s, n, eps, overlapping);
    std::vector<double> d(n_v, 0.0);
    std::vector<glm::dvec3> next = s.p;
    bool any = false;
    for (size_t v = 0; v < n_v; ++v) {
      if (frozen[v]) continue;
      // never use more than kRoomShare of the gap seen at the start: the other side moves too
      const double cap = std::max(0.0, kRoomShare * room0[v] - moved[v]);
      d[v] = std::min({want[v], kEdgeShare * s.shortest_edge(v), kRoomShare * room[v], cap});
      if (!(d[v] > eps)) {
        d[v] = 0.0;
        continue;
      }
      next[v] += d[v] * n[v];
      any = true;
    }
    if (!any) break;
    // tangential relaxation: towards the one-ring centroid, within the tangent plane; where the
    // plane is tilted against the surface this also sinks the vertex, so the distance to the
    // surface we started from is restored along the normal
    const std::vector<glm::dvec3> prev = s.p;
    s.p = next;
    tbb::parallel_for(size_t(0), n_v, [&](size_t v) {
      if (frozen[v] || s.nbr[v].empty()) return;
      glm::dvec3 c(0.0);
      for (uint32_t u : s.nbr[v]) c += next[u];
      glm::dvec3 t = c / double(s.nbr[v].size()) - next[v];
      t -= glm::dot(t, n[v]) * n[v];
      const glm::dvec3 relaxed = next[v] + kRelax * t;
      const double lost = std::abs(base.query(next[v]).distance) - std::abs(base.query(relaxed).distance);
      s.p[v] = relaxed + std::max(lost, 0.0) * n[v];
    });
    // take the step back where the surface now passes through itself
    for (int attempt = 0; attempt < 8; ++attempt) {
      bool reverted = false;
      for (const SelfCrossing& x : self_crossings(s.float_positions(), s.tris)) {
        if (std::binary_search(overlapping.begin(), overlapping.end(), pair_of(x))) continue;
        const Tri& t = s.tris[x.triangle];
        for (uint32_t v : {x.a, x.b, t[0], t[1], t[2]}) {
          frozen[v] = 1;
          if (s.p[v] != prev[v]) {
            s.p[v] = prev[v];
            d[v] = 0.0;
            reverted = true;
          }
        }
      }
      if (!reverted) break;
    }
    for (size_t v = 0; v < n_v; ++v) {
      want[v] -= d[v];
      moved[v] += d[v];
    }
  }
  return moved;
}

// Where a skin point is against the cage: `distance` is signed (> 0 outside) against the cage as a
// solid, the union of its closed shells: the depth inside the shell that holds the point deepest,
// or the distance to the nearest shell when none holds it; `triangle` and `bary` locate the closest
// point on that shell. `nearest` is the distance to the closest cage surface of any shell.
struct SkinDepth {
  double distance = 0.0;
  uint32_t triangle = 0;
  glm::dvec3 bary{0.0};
  double nearest = 0.0;
};

// `shells` > 1: the surface is that many closed pieces (Surface::piece), signed by each piece's own
// pseudonormals. Otherwise one surface, possibly open or overlapping itself: a point the nearest
// sheet calls outside is confirmed with the winding number.
std::vector<SkinDepth> skin_depths(const Surface& s, size_t shells, std::span<const glm::vec3> skin) {
  std::vector<SkinDepth> out(skin.size());
  const auto fp = s.float_positions();
  if (shells <= 1) {
    const SurfaceDistance sd(fp, s.tris);
    tbb::parallel_for(size_t(0), skin.size(), [&](size_t i) {
      const glm::dvec3 p(skin[i]);
      const SurfacePoint q = sd.query(p);
      SkinDepth& d = out[i];
      d.distance = q.distance > 0 && sd.winding_number(p) > 0.5 ? -q.distance : q.distance;
      d.triangle = q.triangle;
      d.bary = q.bary;
      d.nearest = std::abs(q.distance);
    });
    return out;
  }
  uint32_t pieces = 0;
  for (uint32_t x : s.piece) pieces = std::max(pieces, x + 1);
  std::vector<std::vector<uint32_t>> ids(pieces);  // global triangle of each piece's triangle
  std::vector<Aabb> box(pieces);
  for (uint32_t t = 0; t < s.tris.size(); ++t) {
    const uint32_t k = s.piece[s.tris[t][0]];
    ids[k].push_back(t);
    for (uint32_t v : s.tris[t]) box[k].extend(s.p[v]);
  }
  std::vector<std::unique_ptr<SurfaceDistance>> sd(pieces);
  tbb::parallel_for(uint32_t(0), pieces, [&](uint32_t k) {
    std::vector<Tri> tris;
    for (uint32_t t : ids[k]) tris.push_back(s.tris[t]);
    sd[k] = std::make_unique<SurfaceDistance>(fp, tris);
  });
  tbb::parallel_for(size_t(0), skin.size(), [&](size_t i) {
    const glm::dvec3 p(skin[i]);
    std::vector<std::pair<double, uint32_t>> order;  // box distance, piece
    for (uint32_t k = 0; k < pieces; ++k)
      order.emplace_back(std::sqrt(ElementBvh::box_dist2(p, box[k].lo, box[k].hi)), k);
    std::sort(order.begin(), order.end());
    SkinDepth& d = out[i];
    d.distance = d.nearest = INFINITY;
    for (const auto& [gap, k] : order) {
      if (gap >= d.nearest) break;  // no closer surface, and a box not holding p holds no depth
      const SurfacePoint q = sd[k]->query(p);
      d.nearest = std::min(d.nearest, std::abs(q.distance));
      if (q.distance < d.distance) {
        d.distance = q.distance;
        d.triangle = ids[k][q.triangle];
        d.bary = q.bary;
      }
    }
  });
  return out;
}

// Concavity of each vertex: the largest bend (radians) of a concave (valley) edge around it; 0 when
// every incident edge is flat or convex.
std::vector<double> concavity(const Surface& s) {
  std::unordered_map<uint64_t, std::array<uint32_t, 2>> edge_faces;  // second = UINT32_MAX when single
  edge_faces.reserve(s.tris.size() * 2);
  for (uint32_t t = 0; t < s.tris.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = s.tris[t][k], b = s.tris[t][(k + 1) % 3];
      auto [it, fresh] = edge_faces.try_emplace((uint64_t(std::min(a, b)) << 32) | std::max(a, b),
                                                std::array<uint32_t, 2>{t, UINT32_MAX});
      if (!fresh) it->second[1] = t;
    }
  auto normal = [&](uint32_t t) {
    const Tri& f = s.tris[t];
    return glm::normalize(glm::cross(s.p[f[1]] - s.p[f[0]], s.p[f[2]] - s.p[f[0]]));
  };
  std::vector<double> c(s.p.size(), 0.0);
  for (const auto& [key, f] : edge_faces) {
    if (f[1] == UINT32_MAX) continue;
    const uint32_t a = uint32_t(key >> 32), b = uint32_t(key & 0xffffffffu);
    const Tri& t1 = s.tris[f[1]];
    const uint32_t apex = t1[0] + t1[1] + t1[2] - a - b;  // the far corner of the second face
    const glm::dvec3 n0 = normal(f[0]), n1 = normal(f[1]);
    if (!(glm::dot(s.p[apex] - s.p[a], n0) > 0)) continue;  // convex or flat
    const double bend = std::acos(std::clamp(glm::dot(n0, n1), -1.0, 1.0));
    c[a] = std::max(c[a], bend);
    c[b] = std::max(c[b], bend);
  }
  return c;
}

// ------------------------------------------------------------ pieces and shells

// Extra decimation error near the joints: 1 + joint_detail * kJointBoost * exp(-(d / r)^2) for the
// nearest joint in units of its reach r.
struct JointField {
  std::vector<glm::dvec3> joints;
  std::vector<double> radius;  // #J reach of each joint's detail
  double detail = 0.0;
  double operator()(const glm::dvec3& p) const {
    double g = 0.0;
    for (size_t j = 0; j < joints.size(); ++j) {
      const double d = glm::length(p - joints[j]) / radius[j];
      g = std::max(g, std::exp(-d * d));
    }
    return 1.0 + detail * kJointBoost * g;
  }
};

// Connected pieces of a triangle soup through shared vertices: the piece of each triangle (#T).
// Returns the number of pieces, numbered in order of their first triangle.
uint32_t label_pieces(size_t n_vertices, std::span<const Tri> tris, std::vector<uint32_t>& tri_piece) {
  std::vector<uint32_t> parent(n_vertices);
  for (uint32_t i = 0; i < parent.size(); ++i) parent[i] = i;
  auto find = [&](uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const Tri& t : tris)
    for (int k = 1; k < 3; ++k) {
      const uint32_t a = find(t[0]), b = find(t[k]);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  std::vector<uint32_t> number(n_vertices, UINT32_MAX);
  uint32_t count = 0;
  tri_piece.resize(tris.size());
  for (size_t t = 0; t < tris.size(); ++t) {
    uint32_t& n = number[find(tris[t][0])];
    if (n == UINT32_MAX) n = count++;
    tri_piece[t] = n;
  }
  return count;
}

// Some triangles of a soup with their own compact vertex array.
struct Patch {
  std::vector<glm::vec3> positions;  // #V
  std::vector<Tri> tris;             // #T
};
Patch extract(std::span<const glm::vec3> positions, std::span<const Tri> tris,
              const std::function<bool(size_t)>& keep) {
  Patch out;
  std::unordered_map<uint32_t, uint32_t> index;
  for (size_t t = 0; t < tris.size(); ++t) {
    if (!keep(t)) continue;
    Tri n;
    for (int k = 0; k < 3; ++k) {
      auto [it, fresh] = index.try_emplace(tris[t][k], uint32_t(out.positions.size()));
      if (fresh) out.positions.push_back(positions[tris[t][k]]);
      n[k] = it->second;
    }
    out.tris.push_back(n);
  }
  return out;
}

// A shell's claim on the face budget: its area, weighted where the joint detail will keep faces
// (the decimater's error is scaled by the factor f; with errors growing as edge^4 the density it
// leaves grows about as sqrt(f)).
double budget_weight(const Patch& p, const JointField& field) {
  double w = 0.0;
  for (const Tri& t : p.tris) {
    const glm::dvec3 a(p.positions[t[0]]), b(p.positions[t[1]]), c(p.positions[t[2]]);
    w += 0.5 * glm::length(glm::cross(b - a, c - a)) * std::sqrt(field((a + b + c) / 3.0));
  }
  return w;
}

// Splits `target` faces over shells in proportion to their weights, giving each at least `least`
// (when the target allows it).
std::vector<uint32_t> share_budget(std::span<const double> weight, uint32_t target, uint32_t least) {
  const size_t n = weight.size();
  std::vector<uint32_t> budget(n, 0);
  std::vector<char> fixed(n, 0);
  least = std::min<uint32_t>(least, std::max<uint32_t>(4, target / uint32_t(std::max<size_t>(n, 1))));
  for (bool changed = true; changed;) {
    changed = false;
    double free_weight = 0.0;
    uint32_t free_faces = target;
    for (size_t i = 0; i < n; ++i) {
      if (fixed[i])
        free_faces -= std::min(free_faces, least);
      else
        free_weight += weight[i];
    }
    for (size_t i = 0; i < n; ++i) {
      if (fixed[i]) {
        budget[i] = least;
        continue;
      }
      const double share = free_weight > 0 ? free_faces * weight[i] / free_weight : 0.0;
      budget[i] = static_cast<uint32_t>(std::floor(share));
      if (share < least) {
        fixed[i] = 1;
        changed = true;
      }
    }
  }
  return budget;
}

// Groups the pieces of the welded skin into shells, one closed wrap each. Every piece starts as its
// own group; then, while some group's share of the face budget is below `least` faces, the one
// with the smallest share joins the group of the piece nearest to it (a finger segment joins its
// neighbour, then the hand). Separate shells keep skin that is buried inside other pieces close to
// a cage surface of its own. Returns the group of each piece (numbered 0..#G-1).
// `piece_parts` (one list per piece, or empty) and `related`: a group joins another only when
// every part of one is related to every part of the other; a group no related piece can take keeps
// its own shell, however small.
std::vector<uint32_t> group_pieces(std::span<const glm::vec3> positions, std::span<const Tri> tris,
                                   std::span<const uint32_t> tri_piece, uint32_t pieces,
                                   std::span<const double> weight, uint32_t target, uint32_t least,
                                   std::span<const std::vector<uint32_t>> piece_parts = {},
                                   const std::function<bool(uint32_t, uint32_t)>& related = {}) {
  std::vector<uint32_t> group(pieces);
  for (uint32_t i = 0; i < pieces; ++i) group[i] = i;
  if (pieces <= 1) return group;
  double total = 0.0;
  for (double w : weight) total += w;
  std::vector<double> group_weight(weight.begin(), weight.end());
  std::vector<std::vector<uint32_t>> piece_tris(pieces), members(pieces);
  for (uint32_t t = 0; t < tris.size(); ++t) piece_tris[tri_piece[t]].push_back(t);
  std::vector<std::unique_ptr<ElementBvh>> bvh(pieces);
  std::vector<Aabb> box(pieces);
  for (uint32_t i = 0; i < pieces; ++i) {
    members[i] = {i};
    std::vector<uint32_t> ids;
    for (uint32_t t : piece_tris[i]) {
      const Tri& f = tris[t];
      for (uint32_t v : f) box[i].extend(glm::dvec3(positions[v]));
      const glm::dvec3 a(positions[f[0]]), b(positions[f[1]]), c(positions[f[2]]);
      if (glm::length(glm::cross(b - a, c - a)) > 0.0) ids.push_back(t);
    }
    bvh[i] = std::make_unique<ElementBvh>(positions, tris, ids);
  }
  auto box_gap = [](const Aabb& a, const Aabb& b) {
    const glm::dvec3 d = glm::max(glm::max(a.lo - b.hi, b.lo - a.hi), glm::dvec3(0.0));
    return glm::length(d);
  };
  const bool by_parts = piece_parts.size() == pieces && related;
  std::vector<std::vector<uint32_t>> group_parts(pieces);
  if (by_parts)
    for (uint32_t i = 0; i < pieces; ++i) group_parts[i] = piece_parts[i];
  auto may_join = [&](uint32_t a, uint32_t b) {
    if (!by_parts) return true;
    for (uint32_t x : group_parts[a])
      for (uint32_t y : group_parts[b])
        if (!related(x, y)) return false;
    return true;
  };
  std::vector<uint8_t> settled(pieces, 0);  // groups no related piece can take
  for (;;) {
    uint32_t smallest = UINT32_MAX, groups = 0;
    for (uint32_t g = 0; g < pieces; ++g) {
      if (members[g].empty()) continue;
      ++groups;
      if (settled[g]) continue;
      if (smallest == UINT32_MAX || group_weight[g] < group_weight[smallest]) smallest = g;
    }
    if (groups <= 1 || smallest == UINT32_MAX || target * group_weight[smallest] / total >= least) break;
    // the piece nearest to any vertex of the group
    Aabb gbox;
    for (uint32_t i : members[smallest]) {
      gbox.extend(box[i].lo);
      gbox.extend(box[i].hi);
    }
    double best = INFINITY;
    uint32_t nearest = UINT32_MAX;
    for (uint32_t q = 0; q < pieces; ++q) {
      if (group[q] == smallest || bvh[q]->empty() || box_gap(gbox, box[q]) >= best || !may_join(smallest, group[q]))
        continue;
      for (uint32_t i : members[smallest])
        for (uint32_t t : piece_tris[i])
          for (uint32_t v : tris[t]) {
            const double d = bvh[q]->nearest_distance(glm::dvec3(positions[v]));
            if (d < best) best = d, nearest = q;
          }
    }
    if (nearest == UINT32_MAX) {  // only zero-area or unrelated pieces left
      settled[smallest] = 1;
      continue;
    }
    const uint32_t into = group[nearest];
    if (by_parts) {
      auto& gp = group_parts[into];
      gp.insert(gp.end(), group_parts[smallest].begin(), group_parts[smallest].end());
      std::sort(gp.begin(), gp.end());
      gp.erase(std::unique(gp.begin(), gp.end()), gp.end());
      group_parts[smallest].clear();
    }
    for (uint32_t i : members[smallest]) group[i] = into;
    members[into].insert(members[into].end(), members[smallest].begin(), members[smallest].end());
    members[smallest].clear();
    group_weight[into] += group_weight[smallest];
    group_weight[smallest] = 0.0;
  }
  std::vector<uint32_t> number(pieces, UINT32_MAX);
  uint32_t count = 0;
  for (uint32_t i = 0; i < pieces; ++i) {
    if (number[group[i]] == UINT32_MAX) number[group[i]] = count++;
    group[i] = number[group[i]];
  }
  return group;
}

// Progress of several decimaters running at once, reported from the build's own thread only.
class SharedProgress {
 public:
  SharedProgress(const Stage& stage, size_t expected, double lo, double hi)
      : stage_(stage), expected_(std::max<size_t>(expected, 1)), lo_(lo), hi_(hi),
        owner_(std::this_thread::get_id()) {}
  void add(size_t steps) {
    const size_t done = done_.fetch_add(steps) + steps;
    if (std::this_thread::get_id() != owner_) return;
    const double share = lo_ + (hi_ - lo_) * std::min(1.0, double(done) / double(expected_));
    if (share > last_) {
      last_ = share;
      stage_.report("decimate", share);
    }
  }
  const Stage& stage() const { return stage_; }

 private:
  const Stage& stage_;
  size_t expected_;
  double lo_, hi_;
  std::thread::id owner_;
  std::atomic<size_t> done_{0};
  double last_ = 0.0;  // owner thread only
};

class DecimateObserver : public OpenMesh::Decimater::Observer {
 public:
  DecimateObserver(SharedProgress& progress, size_t expected)
      : Observer(std::max<size_t>(expected / 50, 1)), progress_(progress) {}
  void notify(size_t step) override {
    progress_.add(step - last_);
    last_ = step;
  }
  bool abort() const override { return progress_.stage().cancelled(); }

 private:
  SharedProgress& progress_;
  size_t last_ = 0;
};

// A decimated shell: positions and triangles, vertices no face uses dropped.
struct Decimated {
  std::vector<glm::dvec3> p;
  std::vector<Tri> tris;
  uint32_t rejected = 0;  // input triangles OpenMesh refused (they would make an edge non-manifold)
  bool too_small = false;  // fewer than 4 usable triangles
  bool started = true;     // false when the decimater could not start
};

// Quadric decimation of one shell to `target` triangles with the joint factors, the aspect and
// normal guards, then the sliver clean-up. A wrap (marching tetrahedra, full of slivers) is first
// brought to 4x the target without the aspect guard, which would refuse to touch it.
Decimated decimate_shell(std::span<const glm::vec3> positions, std::span<const Tri> tris, const JointField& field,
                         uint32_t target, bool wrapped, SharedProgress& progress) {
  Decimated out;
  OmMesh mesh;
  std::vector<OmMesh::VertexHandle> vh;
  vh.reserve(positions.size());
  for (const glm::vec3& p : positions) vh.push_back(mesh.add_vertex(OpenMesh::Vec3d(p.x, p.y, p.z)));
  for (const Tri& t : tris)  // OpenMesh's complaints are silenced by the caller
    if (!mesh.add_face(vh[t[0]], vh[t[1]], vh[t[2]]).is_valid()) ++out.rejected;
  if (mesh.n_faces() < 4) {
    out.too_small = true;
    return out;
  }
  OpenMesh::VPropHandleT<double> factor_prop;
  mesh.add_property(factor_prop);
  std::vector<double> factor(positions.size(), 1.0);
  if (field.detail > 0 && !field.joints.empty())
    tbb::parallel_for(size_t(0), positions.size(), [&](size_t v) { factor[v] = field(glm::dvec3(positions[v])); });
  for (auto v : mesh.vertices()) mesh.property(factor_prop, v) = factor[v.idx()];
  mesh.request_face_normals();  // before the normal-flipping module, which would compute them noisily
  mesh.update_face_normals();
  auto decimate = [&](size_t faces, bool aspect_guard) {
    using Decimater = OpenMesh::Decimater::DecimaterT<OmMesh>;
    Decimater dec(mesh);
    ModCageQuadricT<OmMesh>::Handle hq;
    OpenMesh::Decimater::ModAspectRatioT<OmMesh>::Handle ha;
    OpenMesh::Decimater::ModNormalFlippingT<OmMesh>::Handle hn;
    dec.add(hq);
    dec.add(hn);
    dec.module(hq).set_factors(factor_prop);
    dec.module(hn).set_max_normal_deviation(kMaxNormalDeviation);
    if (aspect_guard) {
      dec.add(ha);
      dec.module(ha).set_aspect_ratio(kMaxAspect);
    }
    const size_t expected = mesh.n_faces() > faces ? (mesh.n_faces() - faces) / 2 : 1;
    DecimateObserver observer(progress, expected);
    dec.set_observer(&observer);
    if (!dec.initialize()) return false;
    dec.decimate_to_faces(0, faces);
    mesh.garbage_collection();
    return true;
  };
  if (wrapped) out.started = decimate(4 * size_t(target), false);
  progress.stage().check();
  if (out.started) out.started = decimate(target, true);
  if (!out.started) return out;
  clean_slivers(mesh);
  progress.stage().check();
  std::vector<uint32_t> used(mesh.n_vertices(), UINT32_MAX);
  for (auto f : mesh.faces()) {
    Tri t;
    int k = 0;
    for (auto v : mesh.fv_range(f)) {
      uint32_t& u = used[v.idx()];
      if (u == UINT32_MAX) {
        u = static_cast<uint32_t>(out.p.size());
        const auto& q = mesh.point(v);
        out.p.emplace_back(q[0], q[1], q[2]);
      }
      t[k++] = u;
    }
    out.tris.push_back(t);
  }
  return out;
}

}  // namespace

Status validate(const AutoCageParams& p) {
  auto bad = [](const std::string& m) { return Status(make_error(ErrorCode::kInvalidArgument, m)); };
  if (p.target_faces < 4) return bad("target faces must be at least 4 (a tetrahedron)");
  if (!(p.joint_detail >= 0 && std::isfinite(p.joint_detail))) return bad("joint detail must be >= 0");
  if (!(p.joint_radius > 0 && std::isfinite(p.joint_radius))) return bad("joint radius must be > 0");
  if (!(p.concave_share >= 0 && p.concave_share <= 1)) return bad("concave share must be in [0, 1]");
  if (!(p.inflate >= 0 && std::isfinite(p.inflate))) return bad("inflate distance must be >= 0");
  if (!(p.wrap_cell > 0 && p.wrap_cell < 0.1))
    return bad("wrap cell must be in (0, 0.1) of the bbox diagonal");
  if (!(p.weld_tolerance >= 0 && p.weld_tolerance < 0.1)) return bad("weld tolerance must be in [0, 0.1)");
  return validate(p.bind);
}

std::vector<glm::vec3> bind_joint_positions(const Character& character) {
  std::vector<glm::vec3> out;
  std::unordered_set<uint32_t> seen;
  for (const Skin& skin : character.skins)
    for (size_t j = 0; j < skin.joints.size(); ++j) {
      if (!seen.insert(skin.joints[j]).second) continue;
      const glm::mat4 bind = glm::inverse(skin.inverse_bind[j]);
      out.emplace_back(bind[3]);
    }
  if (character.skins.empty() && character.skeleton.size() > 0) {
    for (const glm::mat4& g : character.skeleton.global_transforms(character.skeleton.rest_pose()))
      out.emplace_back(g[3]);
  }
  return out;
}

Result<AutoCageReport> build_auto_cage(const Character& character, const AutoCageParams& params,
                                       const AutoCageProgress& progress) {
  if (character.num_triangles() == 0)
    return make_error(ErrorCode::kEmpty, character.source + ": has no triangles to wrap a cage around");
  const SkinParts parts = character_skin_parts(character);
  return build_auto_cage(combined_topology(character), bind_joint_positions(character), params, progress,
                         character.skins.empty() ? nullptr : &parts);
}

SkinParts character_skin_parts(const Character& character) {
  SkinParts parts;
  if (character.skins.empty()) return parts;
  parts.vertex_part = dominant_joint_nodes(character);
  auto chained = std::make_shared<const std::vector<uint8_t>>(part_relation(character));
  const Skeleton* skeleton = &character.skeleton;
  parts.related = [skeleton, chained](uint32_t a, uint32_t b) { return related_nodes(*skeleton, *chained, a, b, 1); };
  parts.cage_labels = [&character](const Cage& cage) -> std::optional<PartLabels> {
    auto att = attach_cage(character, cage.polygons.positions, AttachmentSettings{}, cage.elements);
    if (!att) return std::nullopt;
    auto labels = skeleton_part_labels(character, *att);
    if (!labels) return std::nullopt;
    return std::move(labels).value();
  };
  return parts;
}

Result<AutoCageReport> build_auto_cage(const PolyMesh& skin, std::span<const glm::vec3> joints,
                                       const AutoCageParams& params, const AutoCageProgress& progress,
                                       const SkinParts* skin_parts) {
  if (skin_parts && !skin_parts->vertex_part.empty() && skin_parts->vertex_part.size() != skin.num_vertices())
    return make_error(ErrorCode::kTopologyMismatch, "the skin parts name " + std::to_string(skin_parts->vertex_part.size()) +
                                                        " vertices but the skin has " + std::to_string(skin.num_vertices()));
  if (auto s = validate(params); !s) return s.error();
  if (auto s = validate_mesh(skin, "skin"); !s) return s.error();
  const auto t_start = std::chrono::steady_clock::now();
  const Stage stage{progress};
  AutoCageReport r;
  try {
    // ------------------------------------------------------------ join and weld
    stage.report("weld", 0.0);
    const std::vector<Tri> input = triangulate(skin).triangles;
    if (input.empty()) return make_error(ErrorCode::kEmpty, "skin: has no faces to wrap a cage around");
    r.input_vertices = static_cast<uint32_t>(skin.num_vertices());
    r.input_triangles = static_cast<uint32_t>(input.size());
    const Aabb box = bounding_box(skin.positions);
    const double diag = box.diagonal();
    if (!(diag > 0))
      return make_error(ErrorCode::kEmpty, "skin: all vertices coincide; there is nothing to wrap");
    const Weld weld = weld_vertices(skin.positions, params.weld_tolerance * diag);
    uint32_t collapsed = 0;
    std::vector<Tri> tris = weld_triangles(input, weld.remap, &collapsed);
    r.welded_vertices = static_cast<uint32_t>(weld.positions.size());
    const MeshCheck welded = check_mesh(weld.positions, tris, false);
    // outward orientation, piece by piece: a closed piece wound inside-out has negative volume
    if (const uint32_t flipped = orient_pieces(weld.positions, tris); flipped > 0)
      r.warnings.push_back(std::to_string(flipped) +
                           " pieces of the skin were wound inside-out and were turned");
    r.inflate_distance = params.inflate_absolute ? params.inflate : params.inflate * diag;
    const bool clean = welded.closed() && welded.manifold() && welded.oriented() && welded.components == 1;
    r.wrapped = params.wrap == WrapMode::kAlways || (params.wrap == WrapMode::kAuto && !clean);

    // error factors near joints
    JointField field;
    field.detail = params.joint_detail;
    r.joints = static_cast<uint32_t>(joints.size());
    if (params.joint_detail > 0)
      for (const glm::vec3& j : joints) {
        double nearest = INFINITY;
        for (const glm::vec3& p : weld.positions) nearest = std::min(nearest, glm::length(glm::dvec3(p) - glm::dvec3(j)));
        field.joints.emplace_back(j);
        field.radius.push_back(std::max(params.joint_radius * diag, 1.5 * nearest));
      }

    // the closed surfaces the decimater starts from: the welded skin itself, or one offset wrap
    // per group of its pieces
    std::vector<Patch> shells;
    if (r.wrapped) {
      stage.report("wrap", 0.02);
      const double offset = r.inflate_distance > 0 ? r.inflate_distance : 3.0 * params.wrap_cell * diag;
      r.inflate_distance = offset;
      const double cell = params.wrap_cell * diag;
      auto wrap = [&](const std::function<bool(size_t)>& keep) {
        const Patch part = extract(weld.positions, tris, keep);
        IsoSurface w = offset_wrap(part.positions, part.tris, offset, cell);
        return Patch{std::move(w.positions), std::move(w.triangles)};
      };
      std::vector<uint32_t> tri_piece;
      const uint32_t pieces = label_pieces(weld.positions.size(), tris, tri_piece);
      std::vector<uint32_t> group(pieces, 0);
      if (params.shell_per_piece && pieces > 1) {
        std::vector<Patch> piece_wraps(pieces);
        tbb::parallel_for(uint32_t(0), pieces, [&](uint32_t i) {
          piece_wraps[i] = wrap([&](size_t t) { return tri_piece[t] == i; });
        });
        stage.check();
        std::vector<double> weight(pieces);
        for (uint32_t i = 0; i < pieces; ++i) weight[i] = budget_weight(piece_wraps[i], field);
        // the parts of each piece: those of at least a tenth of its vertices (a stray weight on a
        // few seam vertices does not make a piece a part of another limb)
        std::vector<std::vector<uint32_t>> piece_parts;
        if (skin_parts && skin_parts->related && !skin_parts->vertex_part.empty()) {
          std::vector<uint32_t> welded_part(weld.positions.size(), UINT32_MAX);
          for (size_t v = weld.remap.size(); v-- > 0;) welded_part[weld.remap[v]] = skin_parts->vertex_part[v];
          std::vector<std::unordered_map<uint32_t, uint32_t>> count(pieces);
          std::vector<std::unordered_set<uint32_t>> seen(pieces);
          for (size_t t = 0; t < tris.size(); ++t)
            for (uint32_t v : tris[t])
              if (seen[tri_piece[t]].insert(v).second && welded_part[v] != UINT32_MAX) ++count[tri_piece[t]][welded_part[v]];
          piece_parts.resize(pieces);
          for (uint32_t i = 0; i < pieces; ++i) {
            for (const auto& [part, n] : count[i])
              if (10 * n >= seen[i].size()) piece_parts[i].push_back(part);
            std::sort(piece_parts[i].begin(), piece_parts[i].end());
          }
        }
        group = group_pieces(weld.positions, tris, tri_piece, pieces, weight, params.target_faces, kMinShellFaces,
                             piece_parts, skin_parts ? skin_parts->related : std::function<bool(uint32_t, uint32_t)>());
        const uint32_t groups = *std::max_element(group.begin(), group.end()) + 1;
        shells.resize(groups);
        std::vector<uint32_t> size(groups, 0), only(groups, 0);
        for (uint32_t i = 0; i < pieces; ++i) ++size[group[i]], only[group[i]] = i;
        tbb::parallel_for(uint32_t(0), groups, [&](uint32_t g) {
          if (size[g] == 1)
            shells[g] = std::move(piece_wraps[only[g]]);
          else
            shells[g] = wrap([&](size_t t) { return group[tri_piece[t]] == g; });
        });
      } else {
        shells.push_back(wrap([](size_t) { return true; }));
      }
      for (const Patch& w : shells) r.wrap_triangles += static_cast<uint32_t>(w.tris.size());
      r.warnings.push_back(
          "the welded skin is " + std::to_string(welded.components) + " pieces with " +
          std::to_string(welded.boundary_edges) + " boundary, " + std::to_string(welded.non_manifold_edges) +
          " non-manifold and " + std::to_string(welded.misoriented_edges) + " misoriented edges; the cage wraps it " +
          (shells.size() == 1 ? std::string("as one surface ")
                              : "in " + std::to_string(shells.size()) + " closed surfaces (one per group of pieces) ") +
          std::to_string(offset) + " out");
    } else {
      if (!clean)
        r.warnings.push_back("the welded skin has " + std::to_string(welded.boundary_edges) +
                             " boundary edges in " + std::to_string(welded.components) +
                             " pieces; the cage follows them and is open too");
      shells.push_back(Patch{weld.positions, tris});
    }
    r.shells = static_cast<uint32_t>(shells.size());
    stage.check();

    // ------------------------------------------------------------ decimate
    stage.report("decimate", 0.05);
    std::vector<double> weight(shells.size(), 1.0);
    if (shells.size() > 1)
      for (size_t i = 0; i < shells.size(); ++i) weight[i] = budget_weight(shells[i], field);
    const std::vector<uint32_t> budget = share_budget(weight, params.target_faces, kMinShellFaces);
    size_t expected = 0;
    for (size_t i = 0; i < shells.size(); ++i)
      expected += shells[i].tris.size() > budget[i] ? (shells[i].tris.size() - budget[i]) / 2 : 0;
    SharedProgress decimate_progress(stage, expected, 0.05, 0.6);
    std::vector<Decimated> parts(shells.size());
    {
      // faces that would make an edge or vertex non-manifold are left out (OpenMesh refuses them,
      // and would say so on its error stream; restored on the way out, cancellation included)
      struct QuietOpenMesh {
        bool was_enabled = ::omerr().is_enabled();
        QuietOpenMesh() { ::omerr().disable(); }
        ~QuietOpenMesh() {
          if (was_enabled) ::omerr().enable();
        }
      } quiet;
      tbb::parallel_for(size_t(0), shells.size(), [&](size_t i) {
        parts[i] = decimate_shell(shells[i].positions, shells[i].tris, field, budget[i], r.wrapped, decimate_progress);
      });
    }
    uint32_t rejected = 0;
    for (const Decimated& d : parts) {
      if (d.too_small) return make_error(ErrorCode::kEmpty, "skin: fewer than 4 usable triangles after welding");
      if (!d.started) return make_error(ErrorCode::kInvalidArgument, "the decimater could not start");
      rejected += d.rejected;
    }
    r.dropped_triangles = collapsed + (r.wrapped ? 0 : rejected);
    if (rejected > 0)
      r.warnings.push_back(std::to_string(rejected) + (r.wrapped ? " wrap" : " skin") +
                           " triangles would make a non-manifold edge or vertex and were left out");
    stage.check();

    // ------------------------------------------------------------ inflate
    stage.report("inflate", 0.6);
    Surface s;
    for (const Decimated& d : parts) {
      const uint32_t base = static_cast<uint32_t>(s.p.size());
      s.p.insert(s.p.end(), d.p.begin(), d.p.end());
      for (const Tri& t : d.tris) s.tris.push_back({t[0] + base, t[1] + base, t[2] + base});
    }
    s.build_adjacency();
    const double eps = 1e-9 * diag;
    if (!r.wrapped && r.inflate_distance > 0) {  // a wrap is built at the clearance already
      // less clearance in valleys: a skin point under a concave cage edge projects inside neither
      // neighbouring element, and the blind wedge widens with the depth of the point
      const auto conc = concavity(s);
      std::vector<double> want(s.p.size());
      for (size_t v = 0; v < want.size(); ++v)
        want[v] =
            r.inflate_distance * (1.0 - (1.0 - params.concave_share) * std::min(conc[v] / kFullBend, 1.0));
      const auto moved = push_out(s, want, eps, stage);
      size_t short_of = 0;
      for (size_t v = 0; v < want.size(); ++v) short_of += moved[v] < 0.999 * want[v] ? 1 : 0;
      if (short_of > 0)
        r.warnings.push_back(std::to_string(short_of) +
                             " cage vertices moved out less than the inflate distance (no room in front)");
    }

    // ------------------------------------------------------------ fit: push out where skin points remain
    // outside
    stage.report("check", 0.75);
    const size_t n_shells = r.wrapped ? r.shells : 1;
    auto signed_distances = [&] { return skin_depths(s, n_shells, skin.positions); };
    std::vector<SkinDepth> dist = signed_distances();
    const double margin = kFitMargin * r.inflate_distance;
    for (int round = 0; params.fit_skin && round < kMaxFitRounds; ++round) {
      stage.check();
      std::vector<double> want(s.p.size(), 0.0);
      bool any = false;
      for (const SkinDepth& q : dist) {
        const double need = q.distance + margin;
        if (need <= 0) continue;
        any = true;
        const double top = std::max({q.bary.x, q.bary.y, q.bary.z});
        const Tri& t = s.tris[q.triangle];
        for (int k = 0; k < 3; ++k) want[t[k]] = std::max(want[t[k]], need * q.bary[k] / top);
      }
      if (!any) break;
      push_out(s, want, eps, stage);
      dist = signed_distances();
    }

    // ------------------------------------------------------------ report
    const auto final_positions = s.float_positions();
    if (params.quads) {
      QuadPairing paired = pair_quads(final_positions, s.tris);
      r.cage = std::move(paired.mesh);
      r.quads = paired.quads;
    } else {
      r.cage.positions = final_positions;
      for (const Tri& t : s.tris) r.cage.add_face({t[0], t[1], t[2]});
    }
    r.faces = static_cast<uint32_t>(r.cage.num_faces());
    r.triangles = static_cast<uint32_t>(s.tris.size());
    r.vertices = static_cast<uint32_t>(s.p.size());
    r.check = check_mesh(r.cage.positions, s.tris);
    if (r.check.self_intersections > 0)
      r.warnings.push_back(
          "the cage passes through itself at " + std::to_string(r.check.self_intersections) +
          " edge-triangle crossings (parts of the skin are closer than the decimation error)");
    for (const SkinDepth& q : dist) {
      r.max_distance = std::max(r.max_distance, q.nearest);
      if (q.distance > 0) {
        ++r.outside_points;
        r.max_outside = std::max(r.max_outside, q.distance);
      }
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();

    stage.report("bind", 0.8);
    const auto t_bind = std::chrono::steady_clock::now();
    auto cage = make_cage(r.cage, "auto cage");
    if (!cage) return cage.error();
    BindProgress bp;
    bp.cancel = progress.cancel;
    // the figure the rig will show: bound with the separation labels it binds with
    std::optional<PartLabels> labels;
    if (skin_parts && skin_parts->cage_labels && params.bind.separate) labels = skin_parts->cage_labels(*cage);
    auto binding = bind_skin(skin.positions, *cage, r.cage.positions, params.bind, {}, bp, labels ? &*labels : nullptr);
    if (!binding) return binding.error();
    r.quality = binding->quality();
    auto failures = quality_failures(*binding, skin.positions);
    if (!failures) return failures.error();
    r.failures = std::move(failures).value();
    r.bind_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_bind).count();
    stage.report("bind", 1.0);
  } catch (const Cancelled&) {
    return make_error(ErrorCode::kCancelled, "the cage build was cancelled");
  }
  return r;
}

}  // namespace cagewrap
