// Importing characters from glTF 2.0 (.gltf with external or embedded buffers, .glb) through
// tinygltf: every mesh primitive of the default scene, the node hierarchy, skins, morph targets,
// sparse accessors and animations. Weights are cleaned up (renormalized, zero weights dropped,
// duplicate joints merged) with one warning per kind of problem and primitive, counting the cases.
#pragma once

#include <string>

#include "core/character/character.h"
#include "core/base/result.h"

namespace cagewrap {

// Loads a character. Unusable files (missing buffers, indices or joints out of range, cyclic node
// hierarchies, accessors past their buffer view or buffer) fail with a message naming the file,
// the object and its index; usable oddities become Character::warnings.
Result<Character> load_character(const std::string& path);
// The same from a whole file's bytes held in memory (a project's embedded character): `name` stands
// for the file in messages and in Character::source. Such a file may refer to no other file: a
// .glb, or a .gltf whose buffers are data: URIs; a buffer in a separate file is named in the error.
Result<Character> load_character_bytes(const std::string& bytes, const std::string& name);

}  // namespace cagewrap
