#include "core/geometry/selection.h"

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

namespace {

// A uniform grid with cells of the tolerance over the positions: the counterpart of a point, the
// one nearest to its mirror image within the tolerance, lies in the 27 cells around that image.
class MirrorGrid {
 public:
  MirrorGrid(std::span<const glm::vec3> positions, double tolerance)
      : positions_(positions), tolerance_(tolerance), cell_(tolerance > 0 ? tolerance : 1e-12) {
    for (size_t i = 0; i < positions.size(); ++i) {
      glm::dvec3 p(positions[i]);
      if (finite(p)) grid_[key_of(p)].push_back(static_cast<uint32_t>(i));
    }
  }
  // The point nearest to (-x_i, y_i, z_i) within the tolerance (ties: the lowest index), or -1.
  int64_t counterpart(uint32_t i) const {
    glm::dvec3 q(-double(positions_[i].x), positions_[i].y, positions_[i].z);
    if (!finite(q)) return -1;
    Key k = key_of(q);
    double best = tolerance_;
    int64_t best_index = -1;
    for (int64_t dx = -1; dx <= 1; ++dx)
      for (int64_t dy = -1; dy <= 1; ++dy)
        for (int64_t dz = -1; dz <= 1; ++dz) {
          auto it = grid_.find({k.x + dx, k.y + dy, k.z + dz});
          if (it == grid_.end()) continue;
          for (uint32_t j : it->second) {
            double d = glm::length(glm::dvec3(positions_[j]) - q);
            if (d < best || (d == best && (best_index < 0 || j < best_index))) {  // ties: lowest index
              best = d;
              best_index = j;
            }
          }
        }
    return best_index;
  }

 private:
  struct Key {
    int64_t x, y, z;
    bool operator==(const Key&) const = default;
  };
  struct KeyHash {
    size_t operator()(const Key& k) const {
      return static_cast<size_t>(k.x * 73856093LL ^ k.y * 19349663LL ^ k.z * 83492791LL);
    }
  };
  static bool finite(const glm::dvec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }
  int64_t coord(double x) const { return static_cast<int64_t>(std::clamp(std::floor(x / cell_), -4e18, 4e18)); }
  Key key_of(const glm::dvec3& p) const { return Key{coord(p.x), coord(p.y), coord(p.z)}; }

  std::span<const glm::vec3> positions_;
  double tolerance_, cell_;
  std::unordered_map<Key, std::vector<uint32_t>, KeyHash> grid_;
};

}  // namespace

std::vector<int32_t> mirror_x_counterparts(std::span<const uint32_t> s, std::span<const glm::vec3> positions,
                                           double tolerance) {
  MirrorGrid grid(positions, tolerance);
  std::vector<int32_t> result(s.size(), -1);
  for (size_t n = 0; n < s.size(); ++n)
    if (s[n] < positions.size()) result[n] = static_cast<int32_t>(grid.counterpart(s[n]));
  return result;
}

MirrorResult mirror_x(const IndexSet& s, std::span<const glm::vec3> positions, double tolerance) {
  MirrorGrid grid(positions, tolerance);
  MirrorResult result;
  std::vector<uint32_t> found;
  for (uint32_t i : s) {
    if (i >= positions.size()) continue;
    const int64_t j = grid.counterpart(i);
    if (j < 0) result.unmatched.push_back(i);
    else found.push_back(static_cast<uint32_t>(j));
  }
  result.mirrored = IndexSet(std::move(found));
  return result;
}

MirrorMap::MirrorMap(std::span<const glm::vec3> positions, double tolerance) {
  MirrorGrid grid(positions, tolerance);
  const size_t n = positions.size();
  std::vector<std::pair<uint32_t, uint32_t>> pairs;  // (i, counterpart), both directions
  for (uint32_t i = 0; i < n; ++i) {
    const int64_t j = grid.counterpart(i);
    if (j < 0) continue;
    pairs.emplace_back(i, static_cast<uint32_t>(j));
    pairs.emplace_back(static_cast<uint32_t>(j), i);
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  offsets_.assign(n + 1, 0);
  for (const auto& [i, j] : pairs) ++offsets_[i + 1];
  for (size_t i = 0; i < n; ++i) offsets_[i + 1] += offsets_[i];
  ids_.reserve(pairs.size());
  for (const auto& [i, j] : pairs) ids_.push_back(j);
}

std::span<const uint32_t> MirrorMap::counterparts(uint32_t i) const {
  if (size_t(i) + 1 >= offsets_.size()) return {};
  return {ids_.data() + offsets_[i], offsets_[i + 1] - offsets_[i]};
}

MirrorResult MirrorMap::mirror(const IndexSet& s) const {
  MirrorResult result;
  std::vector<uint32_t> found;
  for (uint32_t i : s) {
    auto c = counterparts(i);
    if (c.empty()) result.unmatched.push_back(i);
    found.insert(found.end(), c.begin(), c.end());
  }
  result.mirrored = IndexSet(std::move(found));
  return result;
}

}  // namespace cagewrap
