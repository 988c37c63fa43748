// The automatic cage of the paper's workflow (section 5, step 1): "polygonize and weld the
// character's pieces, decimate, with more resolution near joints", then inflate so the cage
// wraps the skin, and pair the triangles into quads where they allow it.
//
// Pipeline: join every primitive (bind pose) -> weld coincident and seam vertices (tolerance
// relative to the bounding-box diagonal) -> when the result is not one closed, clean piece (a
// character modelled as separate or open segments), replace it by closed offset surfaces at the
// clearance distance (offset_wrap.h): one per piece of the skin, small neighbouring pieces grouped
// until each group earns a minimum share of the face budget (or one around everything) ->
// quadric edge-collapse decimation of each surface to its share of the target face count (shared
// by area, weighted by the joint detail; OpenMesh Decimater) with error scaled up near joints, an
// aspect-ratio guard against needles and a normal-deviation guard against folds -> inflation along
// area-weighted vertex normals in small steps (each bounded by a share of the incident edge
// lengths and by the room in front of the vertex), with tangential relaxation between steps, then
// local pushes where skin points are still outside -> greedy pairing of nearly coplanar triangles
// into convex quads (quad_pairing.h) -> checks and the cage-quality figure (the skin bound with
// bind_skin), with the skin points that fail it.
//
// This work is based on: Singh and Kokkevis, "Skinning Characters using Surface-Oriented Free-Form
// Deformations" (GI 2000), section 5; Garland and Heckbert, "Surface Simplification Using Quadric
// Error Metrics" (SIGGRAPH 1997), as implemented by OpenMesh's ModQuadricT.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "core/deform/binding.h"
#include "core/cage/cage.h"
#include "core/character/character.h"
#include "core/geometry/mesh.h"
#include "core/cage/mesh_check.h"
#include "core/deform/registration.h"
#include "core/base/result.h"

namespace cagewrap {

// When to build the cage from an offset surface of the whole skin (offset_wrap.h) instead of the
// welded skin itself: the skin's own surface only works when it is one closed, manifold,
// consistently oriented piece.
enum class WrapMode : uint8_t { kAuto, kAlways, kNever };

struct AutoCageParams {
  uint32_t target_faces = 2000;   // triangles of the cage (the decimater stops at or just below),
                                  // before they are paired into quads
  bool quads = true;              // pair nearly coplanar triangles into convex quads (quad_pairing.h)
  double joint_detail = 1.0;      // 0 = uniform; larger keeps more faces near joints
  double joint_radius = 0.04;     // relative to the bbox diagonal: reach of a joint's extra detail
                                  // (at least 1.5x the joint's distance to the skin)
  double inflate = 0.01;          // clearance between skin and cage
  bool inflate_absolute = false;  // false: `inflate` is relative to the bbox diagonal; true: scene units
  double concave_share = 0.25;   // share of `inflate` kept at strongly concave (valley) vertices; 1 = uniform
  double weld_tolerance = 1e-5;  // relative to the bbox diagonal
  bool fit_skin = true;          // push the cage out locally where skin points remain outside
  WrapMode wrap = WrapMode::kAuto;  // kAuto: wrap unless the welded skin is one closed, clean piece
  double wrap_cell = 0.01;  // grid cell of the wrap, relative to the bbox diagonal (at most the clearance)
  bool shell_per_piece = true;  // wrap each piece of the skin (or group of small neighbouring pieces)
                                // in its own closed shell; false: one offset surface around everything
  BindParams bind;  // for the cage-quality figure
};

// Checks ranges; names the offending parameter.
Status validate(const AutoCageParams& params);

struct AutoCageProgress {
  // Called on the thread running the build (marshal to the UI yourself) with a stage name ("weld",
  // "wrap", "decimate", "inflate", "check", "bind") and the overall share done in [0, 1].
  std::function<void(const char* stage, double share)> on_progress;
  const std::atomic<bool>* cancel = nullptr;  // set to true to stop; the build returns kCancelled
};

struct AutoCageReport {
  PolyMesh cage;  // the cage at rest: quads and triangles, outward; triangulate() gives the decimated
                  // triangles back (each quad splits along the edge it was merged across)

  // input
  uint32_t input_vertices = 0, input_triangles = 0;
  uint32_t welded_vertices = 0;    // after welding
  uint32_t dropped_triangles = 0;  // collapsed or repeated by the weld, or not manifold
  uint32_t joints = 0;             // joint positions that steered the detail
  bool wrapped = false;            // built from the offset surface of the whole skin
  uint32_t wrap_triangles = 0;     // triangles of the wrap surfaces before decimation
  uint32_t shells = 0;             // closed surfaces the cage is made of (1 unless wrapped per piece)
  // cage
  uint32_t faces = 0, vertices = 0;  // polygons (quads and triangles) and their vertices
  uint32_t quads = 0;                // faces that are quads
  uint32_t triangles = 0;            // control elements: the quads' two triangles and the other faces
  double inflate_distance = 0.0;  // scene units
  MeshCheck check;                // degenerate/needle triangles, non-manifold/boundary/misoriented edges
  // skin against cage
  double max_outside = 0.0;     // largest distance of a skin vertex outside the cage (0: all inside)
  uint32_t outside_points = 0;  // skin vertices outside the cage
  double max_distance = 0.0;    // largest distance from a skin vertex to the cage surface
  double quality = 0.0;  // Binding::quality(): share of points close to and projecting inside an element
  std::vector<uint32_t> failures;  // skin vertices failing that test (quality_failures()), sorted
  // time
  double seconds = 0.0;       // building the cage (weld to checks)
  double bind_seconds = 0.0;  // binding the skin for the quality figure and listing its failures
  std::vector<std::string> warnings;
};

// What the skeleton says about the skin, for a cage that keeps unrelated parts apart: the part
// (dominant joint) of every skin vertex and which parts are one (core/deform/part_labels.h related_nodes).
// Pieces of the skin are grouped into one shell only when every part of one is related to every part
// of the other (a finger's segments with each other and the hand, never two fingers or a hand and a
// thigh), and the cage-quality figure is measured with the separation labels the rig binds with.
struct SkinParts {
  std::vector<uint32_t> vertex_part;                   // #V part of each skin vertex; UINT32_MAX: none
  std::function<bool(uint32_t, uint32_t)> related;     // whether two parts are one
  // The part labels a bind of the skin to this cage would use (null: none; the figure is then
  // measured without separation).
  std::function<std::optional<PartLabels>(const Cage& cage)> cage_labels;
};

// Builds a cage around a skin in its bind pose. skin: any triangle mesh (#V x 3 positions,
// triangles); joints: bind-pose joint positions (may be empty); parts: may be null (no skeleton).
// Errors: bad parameters, an empty or non-finite skin, nothing left after welding, cancellation.
Result<AutoCageReport> build_auto_cage(const PolyMesh& skin, std::span<const glm::vec3> joints,
                                       const AutoCageParams& params = {},
                                       const AutoCageProgress& progress = {}, const SkinParts* parts = nullptr);

// The parts of a character's skin (dominant joints; related within one hierarchy step or along a
// chain of short bones) and the labels its default attachment (AttachmentSettings{}) gives a cage.
// The result refers to `character`, which must outlive it.
SkinParts character_skin_parts(const Character& character);

// The character's primitives joined in bind pose (combined_topology) and its joints' bind
// positions (from the inverse bind matrices; the rest pose when it has no skins).
Result<AutoCageReport> build_auto_cage(const Character& character, const AutoCageParams& params = {},
                                       const AutoCageProgress& progress = {});

// Bind-pose joint positions of a character: each skin joint once, in mesh space.
std::vector<glm::vec3> bind_joint_positions(const Character& character);

}  // namespace cagewrap
