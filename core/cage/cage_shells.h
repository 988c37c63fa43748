// The shells of a cage (the connected pieces of its control elements) and which skin points each
// owns. A character modelled as separate segments gets one closed shell per segment or group of
// segments (core/rig/auto_cage.h), and the shells overlap wherever the segments are closer than twice
// the clearance (fingers side by side, a knee ball inside the thigh): a point is owned by the closed
// shell it lies deepest inside (else by the nearest shell), and a whole piece of the skin (connected
// through its triangles, coincident vertices welded) by the shell owning nearly all of its points.
// The skin-weights attachment takes a cage vertex's weights from its shell's points only, and the
// bind lets an owned piece use only its shell's elements, so one segment never follows another's
// cage. A piece split between shells (one skin wrapped in a body and a head shell) is owned by none:
// it blends the shells as before.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "core/geometry/mesh.h"

namespace cagewrap {

inline constexpr uint32_t kNoShell = UINT32_MAX;

struct ShellOwnership {
  uint32_t shells = 0;                 // connected pieces of the elements; ownership only when > 1
  std::vector<uint32_t> vertex_shell;  // #Vc (kNoShell: a vertex no element uses); empty when <= 1 shell
  std::vector<uint32_t> point_shell;   // #P the shell the point is deepest inside, else the nearest
  std::vector<uint32_t> piece_shell;   // #P the shell owning the point's whole skin piece, or kNoShell
};

// `share`: the share of a piece's points one shell must own for it to own the piece.
ShellOwnership cage_shell_ownership(std::span<const glm::vec3> cage_rest, std::span<const Tri> elements,
                                    std::span<const glm::vec3> skin, std::span<const Tri> skin_triangles,
                                    double share = 0.95);

}  // namespace cagewrap
