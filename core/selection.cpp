#include "core/selection.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <unordered_map>

#include <glm/geometric.hpp>

namespace cagewrap {

namespace {
template <class Op>
std::vector<uint32_t> combine(const std::vector<uint32_t>& a, std::span<const uint32_t> b_raw, Op op) {
  IndexSet b{std::vector<uint32_t>(b_raw.begin(), b_raw.end())};
  std::vector<uint32_t> out;
  out.reserve(a.size() + b.size());
  op(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(out));
  return out;
}

// Marks of the selected elements, sized to `count` (indices >= count are ignored).
std::vector<char> marks(const IndexSet& s, size_t count) {
  std::vector<char> m(count, 0);
  for (uint32_t i : s)
    if (i < count) m[i] = 1;
  return m;
}

IndexSet from_marks(const std::vector<char>& m) {
  std::vector<uint32_t> out;
  for (size_t i = 0; i < m.size(); ++i)
    if (m[i]) out.push_back(static_cast<uint32_t>(i));
  return IndexSet(std::move(out));
}

// Calls f(a, b) for every polygon edge, once per face side.
template <class F>
void for_each_edge(const PolyMesh& mesh, F f) {
  for (size_t face = 0; face < mesh.num_faces(); ++face) {
    auto c = mesh.face(face);
    for (size_t k = 0; k < c.size(); ++k) f(c[k], c[(k + 1) % c.size()]);
  }
}
}  // namespace

IndexSet::IndexSet(std::vector<uint32_t> indices) : indices_(std::move(indices)) {
  std::sort(indices_.begin(), indices_.end());
  indices_.erase(std::unique(indices_.begin(), indices_.end()), indices_.end());
}

bool IndexSet::contains(uint32_t i) const { return std::binary_search(indices_.begin(), indices_.end(), i); }

void IndexSet::set(std::span<const uint32_t> indices) { *this = IndexSet(std::vector<uint32_t>(indices.begin(), indices.end())); }

void IndexSet::add(std::span<const uint32_t> indices) {
  indices_ = combine(indices_, indices, [](auto... a) { return std::set_union(a...); });
}

void IndexSet::remove(std::span<const uint32_t> indices) {
  indices_ = combine(indices_, indices, [](auto... a) { return std::set_difference(a...); });
}

void IndexSet::toggle(std::span<const uint32_t> indices) {
  indices_ = combine(indices_, indices, [](auto... a) { return std::set_symmetric_difference(a...); });
}

IndexSet select_all(uint32_t count) {
  std::vector<uint32_t> all(count);
  for (uint32_t i = 0; i < count; ++i) all[i] = i;
  return IndexSet(std::move(all));
}

IndexSet invert(const IndexSet& s, uint32_t count) {
  auto m = marks(s, count);
  for (auto& x : m) x = !x;
  return from_marks(m);
}

IndexSet grow_vertices(const IndexSet& s, const PolyMesh& mesh) {
  auto in = marks(s, mesh.num_vertices());
  auto out = in;
  for_each_edge(mesh, [&](uint32_t a, uint32_t b) {
    if (a >= in.size() || b >= in.size()) return;
    if (in[a]) out[b] = 1;
    if (in[b]) out[a] = 1;
  });
  return from_marks(out);
}

IndexSet shrink_vertices(const IndexSet& s, const PolyMesh& mesh) {
  auto in = marks(s, mesh.num_vertices());
  auto out = in;
  for_each_edge(mesh, [&](uint32_t a, uint32_t b) {
    if (a >= in.size() || b >= in.size()) return;
    if (!in[b]) out[a] = 0;
    if (!in[a]) out[b] = 0;
  });
  return from_marks(out);
}

IndexSet grow_faces(const IndexSet& s, const PolyMesh& mesh) {
  auto in = marks(s, mesh.num_faces());
  std::vector<char> touched(mesh.num_vertices(), 0);  // vertices of selected faces
  for (size_t f = 0; f < in.size(); ++f)
    if (in[f])
      for (uint32_t v : mesh.face(f))
        if (v < touched.size()) touched[v] = 1;
  auto out = in;
  for (size_t f = 0; f < out.size(); ++f)
    for (uint32_t v : mesh.face(f))
      if (v < touched.size() && touched[v]) out[f] = 1;
  return from_marks(out);
}

IndexSet shrink_faces(const IndexSet& s, const PolyMesh& mesh) {
  auto in = marks(s, mesh.num_faces());
  std::vector<char> outside(mesh.num_vertices(), 0);  // vertices of unselected faces
  for (size_t f = 0; f < in.size(); ++f)
    if (!in[f])
      for (uint32_t v : mesh.face(f))
        if (v < outside.size()) outside[v] = 1;
  auto out = in;
  for (size_t f = 0; f < out.size(); ++f)
    for (uint32_t v : mesh.face(f))
      if (v < outside.size() && outside[v]) out[f] = 0;
  return from_marks(out);
}

std::vector<int32_t> mirror_x_counterparts(std::span<const uint32_t> s, std::span<const glm::vec3> positions,
                                           double tolerance) {
  // Uniform grid with cells of the tolerance: a counterpart lies in the 27 cells around the query.
  const double cell = tolerance > 0 ? tolerance : 1e-12;
  struct Key {
    int64_t x, y, z;
    bool operator==(const Key&) const = default;
  };
  struct KeyHash {
    size_t operator()(const Key& k) const {
      return static_cast<size_t>(k.x * 73856093LL ^ k.y * 19349663LL ^ k.z * 83492791LL);
    }
  };
  auto coord = [cell](double x) { return static_cast<int64_t>(std::clamp(std::floor(x / cell), -4e18, 4e18)); };
  auto key_of = [&](const glm::dvec3& p) { return Key{coord(p.x), coord(p.y), coord(p.z)}; };
  auto finite = [](const glm::dvec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); };
  std::unordered_map<Key, std::vector<uint32_t>, KeyHash> grid;
  for (size_t i = 0; i < positions.size(); ++i) {
    glm::dvec3 p(positions[i]);
    if (finite(p)) grid[key_of(p)].push_back(static_cast<uint32_t>(i));
  }
  std::vector<int32_t> result(s.size(), -1);
  for (size_t n = 0; n < s.size(); ++n) {
    const uint32_t i = s[n];
    if (i >= positions.size()) continue;
    glm::dvec3 q(-double(positions[i].x), positions[i].y, positions[i].z);
    if (!finite(q)) continue;
    Key k = key_of(q);
    double best = tolerance;
    int64_t best_index = -1;
    for (int64_t dx = -1; dx <= 1; ++dx)
      for (int64_t dy = -1; dy <= 1; ++dy)
        for (int64_t dz = -1; dz <= 1; ++dz) {
          auto it = grid.find({k.x + dx, k.y + dy, k.z + dz});
          if (it == grid.end()) continue;
          for (uint32_t j : it->second) {
            double d = glm::length(glm::dvec3(positions[j]) - q);
            if (d < best || (d == best && (best_index < 0 || j < best_index))) {  // ties: lowest index
              best = d;
              best_index = j;
            }
          }
        }
    result[n] = static_cast<int32_t>(best_index);
  }
  return result;
}

MirrorResult mirror_x(const IndexSet& s, std::span<const glm::vec3> positions, double tolerance) {
  std::vector<int32_t> counterpart = mirror_x_counterparts(s.indices(), positions, tolerance);
  MirrorResult result;
  std::vector<uint32_t> found;
  for (size_t n = 0; n < s.size(); ++n) {
    const uint32_t i = s.indices()[n];
    if (i >= positions.size()) continue;
    if (counterpart[n] < 0) result.unmatched.push_back(i);
    else found.push_back(static_cast<uint32_t>(counterpart[n]));
  }
  result.mirrored = IndexSet(std::move(found));
  return result;
}

}  // namespace cagewrap
