// Importing characters from glTF 2.0 (.gltf with external or embedded buffers, .glb) through
// tinygltf: every mesh primitive of the default scene, the node hierarchy, skins, morph targets,
// sparse accessors and animations. Weights are cleaned up (renormalized, zero weights dropped,
// duplicate joints merged) with one warning per kind of problem and primitive, counting the cases.
#pragma once

#include <string>
#include <vector>

#include "core/character/character.h"
#include "core/base/result.h"

namespace cagewrap {

// How a character file is read.
struct CharacterLoadOptions {
  // FBX, Collada and the other formats read through assimp (core/io/assimp_loader.h): leave the file's units and
  // up axis as they are instead of bringing the scene to metres, Y up. glTF is metres, Y up, already.
  bool keep_units = false;
  // Those formats are read by Open Asset Import in a child process, so that a crash of the importer on a
  // malformed file is an error naming the file rather than the end of this process (core/io/assimp_loader.h).
  // In this process instead: for the fuzzers, which run this project's part of the import under the
  // sanitizers in-process once the importer has read the file in a child.
  bool in_process = false;
};

// The extensions of the character files load_character reads (lower case, with the dot): .glb .gltf, then the
// formats read through assimp.
std::vector<std::string> character_extensions();
bool is_character_file(const std::string& path);

// Loads a character: .glb and .gltf through tinygltf, the formats is_assimp_character names through assimp. Unusable files (missing buffers, indices or joints out of range, cyclic node
// hierarchies, accessors past their buffer view or buffer) fail with a message naming the file,
// the object and its index; usable oddities become Character::warnings.
Result<Character> load_character(const std::string& path, const CharacterLoadOptions& options = {});
// The same from a whole file's bytes held in memory (a project's embedded character): `name` stands
// for the file in messages and in Character::source. Such a file may refer to no other file: a
// .glb, or a .gltf whose buffers are data: URIs; a buffer in a separate file is named in the error. `file_name`
// (the file the bytes came from) picks the reader by its extension: glTF unless it names an assimp format.
Result<Character> load_character_bytes(const std::string& bytes, const std::string& name, const CharacterLoadOptions& options = {},
                                       const std::string& file_name = "");

}  // namespace cagewrap
