// Writing a character as binary glTF 2.0 (.glb): the node hierarchy, one mesh per (mesh, node)
// group of primitives with POSITION, NORMAL (area-weighted), indices, JOINTS_n/WEIGHTS_n sets of
// four influences, morph targets, skins and animation clips. The output is deterministic: the
// same character gives the same bytes.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/character.h"
#include "core/result.h"

namespace cagewrap {

// The .glb bytes of a character; `generator` goes into asset.generator.
std::vector<uint8_t> encode_glb(const Character& character, const std::string& generator = "cagewrap");

// Atomic (core/atomic_write.h): a failed write leaves an existing file as it was.
Status write_glb(const std::string& path, const Character& character, const std::string& generator = "cagewrap");

}  // namespace cagewrap
