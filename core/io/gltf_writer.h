// Writing a character as binary glTF 2.0 (.glb): the node hierarchy, one mesh per (mesh, node)
// group of primitives with POSITION, NORMAL (area-weighted), indices, JOINTS_n/WEIGHTS_n sets of
// four influences, morph targets, skins and animation clips. The output is deterministic: the
// same character gives the same bytes.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/character/character.h"
#include "core/base/result.h"
#include "core/io/gltf_quantize.h"

namespace cagewrap {

// GLB framing (glTF 2.0, section 4.4): the 12-byte header, the JSON chunk (padded with spaces) and,
// when `bin` is not empty, the BIN chunk (padded with zeros).
std::vector<uint8_t> glb_container(std::string json_text, std::vector<uint8_t> bin);
// The JSON chunk's text of a .glb file's bytes; errors name `file` (a truncated header or chunk, a
// first chunk that is not JSON).
Result<std::string> glb_json_chunk(const std::string& bytes, const std::string& file);

// The .glb bytes of a character; `generator` goes into asset.generator. With `quantization`
// (core/io/gltf_quantize.h): KHR_mesh_quantization, required by the file.
std::vector<uint8_t> encode_glb(const Character& character, const std::string& generator = "cagewrap",
                                const GlbQuantization* quantization = nullptr);

// The bytes encode_glb writes for each part of `character` (its binary chunk, before alignment padding):
// meshes (POSITION, NORMAL, indices, source indices), skins (JOINTS_n, WEIGHTS_n, inverse bind matrices),
// morph targets (their POSITION deltas), animation (key times and values). Counted by encoding it.
struct GlbPartSizes {
  uint64_t mesh = 0, skin = 0, targets = 0, animation = 0;
};
GlbPartSizes glb_part_sizes(const Character& character, const GlbQuantization* quantization = nullptr);

// Atomic (core/base/atomic_write.h): a failed write leaves an existing file as it was.
Status write_glb(const std::string& path, const Character& character, const std::string& generator = "cagewrap",
                 const GlbQuantization* quantization = nullptr);

}  // namespace cagewrap
