#include "core/geometry/triangle_bvh.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace cagewrap {

namespace {
constexpr uint32_t kLeafSize = 4;
constexpr int kStackSize = 96;

struct RayBoxTest {
  glm::dvec3 origin, inv;
  // Slab test; returns the entry t or +inf when the box is missed within [t_min, t_max].
  double enter(const glm::vec3& lo, const glm::vec3& hi, double t_min, double t_max) const {
    for (int a = 0; a < 3; ++a) {
      double t0 = (double(lo[a]) - origin[a]) * inv[a], t1 = (double(hi[a]) - origin[a]) * inv[a];
      if (t0 > t1) std::swap(t0, t1);
      // NaN (0 * inf when the origin lies on a slab of a parallel ray) keeps the interval as is
      if (t0 > t_min) t_min = t0;
      if (t1 < t_max) t_max = t1;
    }
    return t_min <= t_max ? t_min : TriangleBvh::kInfinity;
  }
};

// Moller-Trumbore, both sides. Returns t (or -1 on a miss) and the barycentric (u, v) of corners 1, 2.
double ray_triangle(const Ray& ray, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, double& u,
                    double& v) {
  const glm::dvec3 e1 = b - a, e2 = c - a;
  const glm::dvec3 p = glm::cross(ray.direction, e2);
  const double det = glm::dot(e1, p);
  const double scale = glm::dot(e1, e1) * glm::dot(e2, e2);
  if (!(det * det > 1e-24 * scale)) return -1.0;  // parallel or degenerate
  const double inv = 1.0 / det;
  const glm::dvec3 s = ray.origin - a;
  u = glm::dot(s, p) * inv;
  if (u < 0.0 || u > 1.0) return -1.0;
  const glm::dvec3 q = glm::cross(s, e1);
  v = glm::dot(ray.direction, q) * inv;
  if (v < 0.0 || u + v > 1.0) return -1.0;
  return glm::dot(e2, q) * inv;
}
}  // namespace

TriangleBvh::TriangleBvh(std::span<const glm::vec3> positions, std::span<const Tri> triangles)
    : positions_(positions.begin(), positions.end()) {
  tris_.reserve(triangles.size());
  ids_.reserve(triangles.size());
  const size_t nv = positions.size();
  std::vector<glm::vec3> centroids;
  centroids.reserve(triangles.size());
  for (size_t i = 0; i < triangles.size(); ++i) {
    const Tri& t = triangles[i];
    if (t[0] >= nv || t[1] >= nv || t[2] >= nv) continue;  // can never be hit; callers validate meshes
    tris_.push_back(t);
    ids_.push_back(static_cast<uint32_t>(i));
    centroids.push_back((positions[t[0]] + positions[t[1]] + positions[t[2]]) / 3.0f);
  }
  if (tris_.empty()) return;
  // order the slots by recursive median splits of one index array, then permute once
  std::vector<uint32_t> order(tris_.size());
  for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  nodes_.reserve(2 * tris_.size() / kLeafSize + 2);
  build(0, static_cast<uint32_t>(order.size()), order, centroids);
  std::vector<Tri> tris(order.size());
  std::vector<uint32_t> ids(order.size());
  for (size_t i = 0; i < order.size(); ++i) {
    tris[i] = tris_[order[i]];
    ids[i] = ids_[order[i]];
  }
  tris_ = std::move(tris);
  ids_ = std::move(ids);
  refit(positions_);  // leaf boxes from the final slots
}

void TriangleBvh::leaf_bounds(Node& node) const {
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (uint32_t i = node.first; i < node.first + node.count; ++i)
    for (uint32_t c : tris_[i]) {
      lo = glm::min(lo, positions_[c]);
      hi = glm::max(hi, positions_[c]);
    }
  node.lo = lo;
  node.hi = hi;
}

uint32_t TriangleBvh::build(uint32_t begin, uint32_t end, std::vector<uint32_t>& order,
                            const std::vector<glm::vec3>& centroids) {
  const uint32_t index = static_cast<uint32_t>(nodes_.size());
  nodes_.push_back({});
  if (end - begin <= kLeafSize) {
    nodes_[index].first = begin;
    nodes_[index].count = end - begin;
    return index;
  }
  glm::vec3 clo(INFINITY), chi(-INFINITY);
  for (uint32_t i = begin; i < end; ++i) {
    clo = glm::min(clo, centroids[order[i]]);
    chi = glm::max(chi, centroids[order[i]]);
  }
  const glm::vec3 extent = chi - clo;
  const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
  const uint32_t mid = begin + (end - begin) / 2;
  std::nth_element(order.begin() + begin, order.begin() + mid, order.begin() + end,
                   [&](uint32_t x, uint32_t y) { return centroids[x][axis] < centroids[y][axis]; });
  build(begin, mid, order, centroids);  // left child = index + 1
  const uint32_t right = build(mid, end, order, centroids);
  nodes_[index].count = 0;
  nodes_[index].right = right;
  return index;
}

void TriangleBvh::refit(std::span<const glm::vec3> positions) {
  const size_t n = std::min(positions.size(), positions_.size());
  std::copy(positions.begin(), positions.begin() + n, positions_.begin());
  // children always follow their parent, so a reverse sweep sees children first
  for (size_t i = nodes_.size(); i-- > 0;) {
    Node& node = nodes_[i];
    if (node.count > 0) {
      leaf_bounds(node);
    } else {
      node.lo = glm::min(nodes_[i + 1].lo, nodes_[node.right].lo);
      node.hi = glm::max(nodes_[i + 1].hi, nodes_[node.right].hi);
    }
  }
}

Aabb TriangleBvh::bounds() const {
  Aabb box;
  if (!nodes_.empty()) {
    box.extend(glm::dvec3(nodes_[0].lo));
    box.extend(glm::dvec3(nodes_[0].hi));
  }
  return box;
}

template <class Visit>
void TriangleBvh::traverse(const Ray& ray, double t_min, double t_max, Visit visit) const {
  if (nodes_.empty()) return;
  const RayBoxTest box{ray.origin, 1.0 / ray.direction};
  uint32_t stack[kStackSize];
  int top = 0;
  if (box.enter(nodes_[0].lo, nodes_[0].hi, t_min, t_max) == kInfinity) return;
  stack[top++] = 0;
  while (top > 0) {
    const uint32_t index = stack[--top];
    const Node& node = nodes_[index];
    if (node.count > 0) {
      for (uint32_t i = node.first; i < node.first + node.count; ++i) {
        const Tri& tri = tris_[i];
        double u, v;
        const double t = ray_triangle(ray, glm::dvec3(positions_[tri[0]]), glm::dvec3(positions_[tri[1]]),
                                      glm::dvec3(positions_[tri[2]]), u, v);
        if (t < t_min || t > t_max) continue;
        TriangleHit hit{ids_[i], {1.0 - u - v, u, v}, t, ray.at(t)};
        t_max = visit(hit);
        if (t_max < 0) return;
      }
      continue;
    }
    const uint32_t l = index + 1, r = node.right;
    const double tl = box.enter(nodes_[l].lo, nodes_[l].hi, t_min, t_max);
    const double tr = box.enter(nodes_[r].lo, nodes_[r].hi, t_min, t_max);
    // near child on top of the stack
    if (tl <= tr) {
      if (tr != kInfinity) stack[top++] = r;
      if (tl != kInfinity) stack[top++] = l;
    } else {
      if (tl != kInfinity) stack[top++] = l;
      if (tr != kInfinity) stack[top++] = r;
    }
  }
}

std::optional<TriangleHit> TriangleBvh::intersect(const Ray& ray, double t_min, double t_max) const {
  std::optional<TriangleHit> best;
  traverse(ray, t_min, t_max, [&](const TriangleHit& hit) {
    if (!best || hit.t < best->t || (hit.t == best->t && hit.triangle < best->triangle)) best = hit;
    return best->t;
  });
  return best;
}

bool TriangleBvh::any_hit(const Ray& ray, double t_min, double t_max) const {
  bool found = false;
  traverse(ray, t_min, t_max, [&](const TriangleHit&) {
    found = true;
    return -1.0;
  });
  return found;
}

void TriangleBvh::all_hits(const Ray& ray, double t_min, double t_max, std::vector<TriangleHit>& out) const {
  out.clear();
  traverse(ray, t_min, t_max, [&](const TriangleHit& hit) {
    out.push_back(hit);
    return t_max;
  });
}

uint32_t TriangleBvh::count_hits(const Ray& ray) const {
  uint32_t count = 0;
  traverse(ray, 0.0, kInfinity, [&](const TriangleHit&) {
    ++count;
    return kInfinity;
  });
  return count;
}

}  // namespace cagewrap
