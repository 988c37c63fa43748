// Topology edits of the cage polygons (paper section 5, step 1: "polygonize and weld"): merging
// vertices, welding by distance, flipping faces, triangulating. Each returns the new cage and the
// CageTopologyChange that carries offsets, set edits and attachments across (core/document/topology_change.h).
// Selections are spans of ids (Selection::cage_vertices / cage_faces); duplicates are allowed.
#pragma once

#include <cstdint>
#include <span>

#include "core/cage/cage.h"
#include "core/base/result.h"
#include "core/document/topology_change.h"

namespace cagewrap {

// Merges the given vertices into one vertex at their centroid (it takes the lowest id's place; the
// other ids close up). Faces are re-indexed; repeated corners in a row collapse into one; a face left
// with fewer than 3 distinct corners, one that passes through a vertex twice (pinched), and one with
// the same corners as an earlier face are dropped and named in the warnings and in
// change.dropped_faces. Vertices stay even when no face uses them any more.
// Errors: no vertex given, an id out of range, a cage that is not valid (validate_mesh), no face left.
Result<CageEdit> merge_vertices(const Cage& cage, std::span<const uint32_t> vertices);

// Merges every cluster of vertices closer than `distance` (transitively, core/geometry/weld.h) into one vertex
// at the cluster's centroid; faces as in merge_vertices. Errors: distance not positive and finite,
// an invalid cage, no face left.
Result<CageEdit> weld_cage_vertices(const Cage& cage, double distance);

// Reverses the winding of the given faces (corner 0 stays first: a b c d -> a d c b), turning their
// normals around. Errors: no face given, an id out of range, an invalid cage.
Result<CageEdit> flip_faces(const Cage& cage, std::span<const uint32_t> faces);
Result<CageEdit> flip_all_faces(const Cage& cage);

// Every polygon replaced by its control elements (the triangles make_cage made), in element order,
// so element k of the result is element k of the input. Errors: an invalid cage.
Result<CageEdit> triangulate_cage(const Cage& cage);

}  // namespace cagewrap
