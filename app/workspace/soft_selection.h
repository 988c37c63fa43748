// What a move of selected cage vertices moves, and by how much: soft selection (vertices near the
// selection follow with a weight that falls off with distance, Maya's Soft Select, Blender's
// Proportional Editing) and X-mirror editing (the counterparts across x = 0 move with the x component
// of the displacement negated). Headless, so the editor's gizmo and the tests share one answer.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "core/geometry/mesh.h"
#include "core/base/result.h"
#include "core/geometry/selection.h"

namespace cagewrap {

enum class Falloff : uint8_t {
  kSmooth,    // 1 - 3t^2 + 2t^3 (smoothstep from the selection to the radius)
  kLinear,    // 1 - t
  kSharp,     // (1 - t)^2
  kConstant,  // 1 inside the radius
};
const char* falloff_name(Falloff f);

// How far is "near": straight-line distance (Maya's volume mode), or distance along the mesh's
// polygon edges (surface mode: the other leg does not follow even when it is close in space).
enum class FalloffDistance : uint8_t { kVolume, kSurface };

struct SoftSelectionParams {
  bool enabled = false;
  double radius = 0.1;  // scene units, > 0 when enabled
  Falloff falloff = Falloff::kSmooth;
  FalloffDistance distance = FalloffDistance::kVolume;
};

struct MirrorParams {
  bool enabled = false;
  double tolerance = 1e-3;  // scene units: how far from (-x, y, z) a counterpart may be
};

// Weight of falloff f at normalized distance t = d / radius (0 at or beyond 1, 1 at 0).
double falloff_weight(Falloff f, double t);

// Per vertex, the share of the displacement it receives directly and mirrored (x negated).
struct MoveWeights {
  std::vector<uint32_t> vertices;  // ascending, every vertex with a non-zero weight
  std::vector<float> direct;       // #vertices, in [0, 1]
  std::vector<float> mirrored;     // #vertices, in [0, 1]; all zero without mirroring
  std::vector<uint32_t> unmatched;  // selected vertices with no counterpart within the tolerance

  // The displacement of vertices[i] for a gizmo displacement d:
  //   (direct * d + mirrored * (-d.x, d.y, d.z)) / max(1, direct + mirrored),
  // so a vertex on the mirror plane (its own counterpart) keeps x = 0 and moves by (0, d.y, d.z),
  // and a vertex pulled by both sides never moves further than the gizmo.
  glm::dvec3 displacement(size_t i, const glm::dvec3& d) const;
  // Dense weights for display (#count, max of direct and mirrored).
  std::vector<float> dense(size_t count) const;
};

// Selected vertices have weight 1; with soft selection every other vertex within the radius of a
// selected one gets falloff_weight(distance / radius) of the nearest. Mirroring repeats this for
// the counterparts of the selected vertices. Errors: a selected index out of range (names it), a
// non-positive radius or tolerance, surface mode without faces.
Result<MoveWeights> move_weights(const IndexSet& selected, std::span<const glm::vec3> positions,
                                 const PolyMesh& mesh, const SoftSelectionParams& soft,
                                 const MirrorParams& mirror);

// The vertices of the given polygons (for moving a face selection), ascending.
IndexSet face_vertices(const IndexSet& faces, const PolyMesh& mesh);

}  // namespace cagewrap
