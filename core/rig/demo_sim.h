// The simulated-cage use cases on the demo character (paper section 6, Figure 6), generated so that
// `cagewrap demo-sim` can write them as projects:
//   belly: the demo cage with the belly's cage vertices soft (they jiggle during the walk), every
//          other vertex pinned;
//   cape:  the demo character with a dense cape mesh skinned to its chest, its cage extended by a
//          coarse cloth sheet (the cape's driver), pinned along the top edge, free below, colliding
//          with the skeleton's capsules; the cape starts slanted back and drapes over the back and
//          hips during a pre-roll, then swings with the walk.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "core/deform/binding.h"
#include "core/cage/cage_sim.h"
#include "core/character/character.h"
#include "core/geometry/mesh.h"
#include "core/base/result.h"

namespace cagewrap {

// A rectangular sheet of cols x rows quads from `origin`, spanned by `right` and `down` (the whole
// width and length). Vertex (i, j), column i in 0..cols and row j in 0..rows, is j * (cols + 1) + i.
PolyMesh grid_sheet(const glm::dvec3& origin, const glm::dvec3& right, const glm::dvec3& down, int cols, int rows);

// Settings for the demo cage (assets/demo_cage.obj, #Vc rest positions): the cage vertices in front
// of the belly free (stiffness and mass fading to pinned at the region's edge), every other vertex
// pinned; the walk then shakes the belly. Gravity off (the belly keeps its modelled shape at rest).
SimSettings demo_belly_sim(std::span<const glm::vec3> cage_rest);

struct DemoCape {
  Character character;      // the demo character plus a second primitive (the cape) skinned to its chest
  PolyMesh cage;            // the body cage's faces, then the cape sheet's
  uint32_t first_cape_vertex = 0;
  BindParams params;        // a distance unit small enough that the body and the cape stay apart
  SimSettings sim;          // sheet free below its top row, body pinned, skeleton capsules, pre-roll
};
// Fails when the character has no joint named "chest" (it must be the demo character).
Result<DemoCape> make_demo_cape(const Character& demo, const PolyMesh& body_cage);

}  // namespace cagewrap
