// Cages made elsewhere: read from any mesh format the project knows (OBJ, PLY, OFF, STL, and glTF/GLB
// where every primitive is joined at its rest positions), and their problems listed element by
// element so the artist can fix them. A cage with problems still binds: bad elements are skipped
// (registration.h), so the list is advice, not a refusal.
#pragma once

#include <string>
#include <vector>

#include "core/cage/cage.h"
#include "core/geometry/mesh.h"
#include "core/base/result.h"

namespace cagewrap {

// Errors name the file (unreadable, unsupported format, no faces, indices out of range, ...).
Result<PolyMesh> load_cage_mesh(const std::string& path);

struct CageProblems {
  uint32_t bad_elements = 0;        // degenerate, non-finite or duplicate control elements
  uint32_t open_edges = 0;          // used by one polygon
  uint32_t non_manifold_edges = 0;  // used by more than two polygons
  uint32_t misoriented_edges = 0;   // two polygons traverse it in the same direction
  uint32_t unused_vertices = 0;     // in no polygon
  std::vector<std::string> lines;   // one per problem, naming the element, face, edge or vertex (capped)
  size_t total() const { return bad_elements + open_edges + non_manifold_edges + misoriented_edges + unused_vertices; }
};

// At most `max_lines` lines; the counts are always complete.
CageProblems find_cage_problems(const Cage& cage, size_t max_lines = 50);

}  // namespace cagewrap
