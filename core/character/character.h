// A skinned character as imported from glTF (or generated): the node hierarchy, skins, the
// primitives of every mesh instance in the default scene with their bind-pose positions,
// triangles and cleaned-up joint weights, morph targets, animation clips, and import warnings.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "core/character/animation.h"
#include "core/geometry/mesh.h"
#include "core/character/skeleton.h"

namespace cagewrap {

struct Skin {
  std::string name;
  std::vector<uint32_t> joints;          // #J skeleton node of each joint
  std::vector<glm::mat4> inverse_bind;   // #J inverse bind matrices (mesh space -> joint space)
};

struct Primitive {
  std::string mesh_name;
  uint32_t mesh = 0;       // glTF mesh index
  uint32_t primitive = 0;  // index of the primitive within its mesh
  uint32_t node = 0;       // the skeleton node that instances the mesh
  int32_t skin = -1;       // index into Character::skins; -1 = moves rigidly with `node`
  std::vector<glm::vec3> positions;  // #V x 3 bind pose (the file's raw POSITION data)
  std::vector<Tri> triangles;        // #T x 3 (strips and fans converted; points and lines have none)
  // Joint influences in CSR form, after cleanup (no zero weights, no duplicate joints, sum 1):
  // vertex v is driven by entries influence_start[v] .. influence_start[v+1]-1.
  std::vector<uint32_t> influence_start;  // #V+1, empty when unskinned
  std::vector<uint16_t> influence_joint;  // skin joint index (into Skin::joints)
  std::vector<float> influence_weight;
  std::vector<std::vector<glm::vec3>> morph_targets;  // #M x #V x 3 position offsets
  std::vector<float> morph_weights;                   // #M default weights
  // When the vertices were reordered (an export optimised for the GPU): each vertex's index before, written
  // as the application-specific attribute _CAGEWRAP_SOURCE_INDEX (float); empty = the order is the source's.
  std::vector<uint32_t> source_index;
  // The glTF extras of the mesh, as JSON text, written from the mesh's first primitive (the writer's only;
  // an export's pose-driven correctives, docs/pose-correctives.md); empty = none.
  std::string mesh_extras;

  size_t num_vertices() const { return positions.size(); }
  size_t num_influences(size_t v) const { return influence_start[v + 1] - influence_start[v]; }
  // "mesh 0 ('body') primitive 1"
  std::string label() const;
};

struct Character {
  std::string source;  // the file it came from, or a description
  Skeleton skeleton;
  std::vector<Skin> skins;
  std::vector<Primitive> primitives;  // in file order: by instancing node, then primitive index
  std::vector<Clip> clips;
  std::vector<std::string> warnings;  // one line per kind of problem, with counts
  // A file read in its own units and up axis (CharacterLoadOptions::keep_units) that are not metres, Y up: the
  // scale and turn that bring it there. A glTF export applies it as a root node (add_root_node), so that the
  // file it writes is in metres, Y up, as glTF is.
  std::optional<Trs> to_metres;

  size_t num_vertices() const;
  size_t num_triangles() const;
  size_t num_joints() const;  // distinct joints over all skins
  // A clip by exact name, else by index ("3"); -1 when neither matches.
  int32_t find_clip(const std::string& name_or_index) const;
};

// Makes a new node named `name` with local transform `t` the parent of every root node of `c` but those that only
// hold skinned meshes (their joints move them; glTF wants them at the root), appended last: every other node keeps
// its index, so skins, primitives and clips stay as they are. Errors name `c.source`.
Status add_root_node(Character& c, const std::string& name, const Trs& t);

}  // namespace cagewrap
