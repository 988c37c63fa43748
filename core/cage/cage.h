// The cage (deformer object O of the paper): a polygon mesh the artist sees, triangulated internally
// into control elements (section 5: the user keeps seeing polygons).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/geometry/mesh.h"
#include "core/base/result.h"

namespace cagewrap {

enum class ElementStatus : uint8_t { kValid, kDegenerate, kNonFinite, kDuplicate };
const char* element_status_name(ElementStatus s);

struct Cage {
  PolyMesh polygons;                   // what the user sees and edits
  std::vector<Tri> elements;           // #E control elements (triangles), fixed vertex order
  std::vector<uint32_t> element_face;  // #E polygon each element came from

  size_t num_vertices() const { return polygons.num_vertices(); }
  size_t num_elements() const { return elements.size(); }
};

// Triangulates; fails only when a corner index is out of range or there are no faces.
Result<Cage> make_cage(PolyMesh polygons, const std::string& what);

// Zero-area (relative to the element's longest edge), non-finite, and duplicate elements (same three
// vertices, or the same three positions, as an earlier element). #E statuses.
std::vector<ElementStatus> classify_elements(const Cage& cage, std::span<const glm::vec3> positions);

// Relative area below which an element is degenerate: |e1 x e2| <= kDegenerateRatio * longest_edge^2.
// Positions are floats (a unit roundoff of 6e-8 of each coordinate), so the cross product of a triangle's
// edges carries an error of a few 1e-7 of longest_edge^2: at 1e-7 (the earlier threshold) a sliver's normal
// could be rounding noise. At 1e-5 the normal's direction is good to about a degree, and the eq. 2 frame's
// inverse amplifies the posed corners' rounding by at most ~1e-2 (a sliver 1 m long is 10 um high).
inline constexpr double kDegenerateRatio = 1e-5;

}  // namespace cagewrap
