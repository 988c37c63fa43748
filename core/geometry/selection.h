// Selections of cage vertices, cage faces (polygons), skin vertices and joints: sorted sets of
// indices, and the editing operations the editor's Select menu offers (all / none / invert,
// grow / shrink by mesh adjacency, mirror across x = 0). A selection is view state: it is never
// part of a Document and never undone.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "core/geometry/mesh.h"

namespace cagewrap {

// Sorted, unique indices.
class IndexSet {
 public:
  IndexSet() = default;
  // Sorts and removes duplicates.
  explicit IndexSet(std::vector<uint32_t> indices);
  IndexSet(std::initializer_list<uint32_t> indices) : IndexSet(std::vector<uint32_t>(indices)) {}

  std::span<const uint32_t> indices() const { return indices_; }
  size_t size() const { return indices_.size(); }
  bool empty() const { return indices_.empty(); }
  bool contains(uint32_t i) const;
  auto begin() const { return indices_.begin(); }
  auto end() const { return indices_.end(); }
  bool operator==(const IndexSet&) const = default;

  void set(std::span<const uint32_t> indices);     // replace
  void add(std::span<const uint32_t> indices);     // union (shift-click)
  void remove(std::span<const uint32_t> indices);  // difference (ctrl-click)
  void toggle(std::span<const uint32_t> indices);  // symmetric difference
  void clear() { indices_.clear(); }

 private:
  std::vector<uint32_t> indices_;
};

struct Selection {
  IndexSet cage_vertices;
  IndexSet cage_faces;  // polygons of Cage::polygons, not triangle elements
  IndexSet skin_vertices;  // in skin_character / combined_topology order
  IndexSet joints;         // skeleton node indices
};

IndexSet select_all(uint32_t count);
// Every index below `count` not in `s` (indices >= count are dropped).
IndexSet invert(const IndexSet& s, uint32_t count);

// Vertices: add every neighbour through a polygon edge (consecutive corners) / drop every selected
// vertex that has a polygon-edge neighbour outside the selection.
IndexSet grow_vertices(const IndexSet& s, const PolyMesh& mesh);
IndexSet shrink_vertices(const IndexSet& s, const PolyMesh& mesh);
// Faces: add every face sharing a vertex with a selected face / drop every selected face sharing a
// vertex with an unselected face.
IndexSet grow_faces(const IndexSet& s, const PolyMesh& mesh);
IndexSet shrink_faces(const IndexSet& s, const PolyMesh& mesh);

struct MirrorResult {
  IndexSet mirrored;               // the counterparts found
  std::vector<uint32_t> unmatched;  // selected indices with no point within tolerance of (-x, y, z)
};
// For each selected point i, the point nearest to (-x_i, y_i, z_i) within `tolerance` (> 0, same
// units as the positions); a point on the plane x = 0 is its own counterpart.
MirrorResult mirror_x(const IndexSet& s, std::span<const glm::vec3> positions, double tolerance);
// The same search as a map: for each s[n], the index of its counterpart, or -1 (none within the
// tolerance, a non-finite point, or an index out of range).
std::vector<int32_t> mirror_x_counterparts(std::span<const uint32_t> s, std::span<const glm::vec3> positions,
                                           double tolerance);

// Counterparts across x = 0 of every point, found once (for the skin, whose mirror is asked for
// at every brush dab). j is a counterpart of i when j is mirror_x's answer for i or i is mirror_x's
// answer for j, so on a nearly symmetric mesh whose sides are sampled differently a region maps to
// a region without holes (some points get two counterparts).
class MirrorMap {
 public:
  MirrorMap() = default;
  MirrorMap(std::span<const glm::vec3> positions, double tolerance);
  size_t size() const { return offsets_.empty() ? 0 : offsets_.size() - 1; }
  std::span<const uint32_t> counterparts(uint32_t i) const;  // ascending; empty out of range
  // Every counterpart of the selected points; unmatched: selected points with none.
  MirrorResult mirror(const IndexSet& s) const;

 private:
  std::vector<uint32_t> offsets_;  // #points + 1
  std::vector<uint32_t> ids_;
};

}  // namespace cagewrap
