// Importing characters from the formats artists' tools write (FBX, Collada, DirectX .x, Blitz3D, MilkShape 3D,
// Valve SMD, Doom 3 MD5) through Open Asset Import (libassimp), into the Character model the glTF loader fills:
// the node hierarchy (pivots and pre-rotations applied by assimp), meshes (triangulated; points and lines
// dropped), skins (a bone's offset matrix is its inverse bind matrix), skin weights cleaned like glTF's
// (core/io/skin_weights.h), and every animation (ticks to seconds, LINEAR keys).
//
// Units and axes: the file's unit (FBX UnitScaleFactor, centimetres per unit; Collada's <unit>, which assimp
// applies itself) and up axis (FBX UpAxis; Collada's <up_axis>, applied by assimp) are reported, and the scene
// is brought to metres, Y up, as glTF is: lengths (node translations, positions, the inverse bind matrices'
// translations, translation keys) are scaled, and a Z-up or X-up scene is turned by its root nodes. With
// keep_units nothing is changed.
#pragma once

#include <string>
#include <vector>

#include "core/base/result.h"
#include "core/character/character.h"
#include "core/io/gltf_loader.h"

namespace cagewrap {

// The extensions load_character_assimp reads (lower case, with the dot): .fbx .dae .x .b3d .ms3d .smd .md5mesh.
const std::vector<std::string>& assimp_character_extensions();
// Whether `path`'s extension is one of them (any case).
bool is_assimp_character(const std::string& path);

// What the import found and did about units and axes (also written to Character::warnings as a note).
struct AssimpUnits {
  double metres_per_unit = 1.0;  // the file's unit, as read (1 when the file says nothing)
  std::string up_axis = "Y";     // "+Y", "+Z", "-Z", ...
  bool converted = false;        // brought to metres, Y up
};

// Errors name the file and pass on the importer's own message. The importer runs in a child process (fork; a
// crash, a kill or 600 s without an answer is an error naming the file and the signal) whose character comes
// back as a .glb (the project's writer and reader), unless options.in_process.
Result<Character> load_character_assimp(const std::string& path, const CharacterLoadOptions& options = {},
                                        AssimpUnits* units = nullptr);
// The same from the file's bytes in memory (a project's embedded character): `name` stands for the file in
// messages, `file_name`'s extension tells the format. A format that reads other files (.md5mesh's .md5anim)
// finds none.
Result<Character> load_character_assimp_bytes(const std::string& bytes, const std::string& name, const std::string& file_name,
                                              const CharacterLoadOptions& options = {}, AssimpUnits* units = nullptr);

}  // namespace cagewrap
