// Importing characters from glTF 2.0 (.gltf with external or embedded buffers, .glb) through
// tinygltf: every mesh primitive of the default scene, the node hierarchy, skins, morph targets,
// sparse accessors and animations. Weights are cleaned up (renormalized, zero weights dropped,
// duplicate joints merged) with one warning per kind of problem and primitive, counting the cases.
#pragma once

#include <string>

#include "core/character.h"
#include "core/result.h"

namespace cagewrap {

// Loads a character. Unusable files (missing buffers, indices or joints out of range, cyclic node
// hierarchies, accessors past their buffer view or buffer) fail with a message naming the file,
// the object and its index; usable oddities become Character::warnings.
Result<Character> load_character(const std::string& path);

}  // namespace cagewrap
