// Reading and writing static meshes and cages: OBJ, PLY, OFF, STL (read through OpenMesh),
// OBJ and raw float32 .bin (written here).
#pragma once

#include <span>
#include <string>

#include <glm/vec3.hpp>

#include "core/mesh.h"
#include "core/result.h"

namespace cagewrap {

// Loads every vertex and polygon exactly as stored (no welding, no manifold repair, faces kept in
// file order), then validates: missing/empty file, parse failure, non-finite coordinates and
// corner indices out of range are errors naming the file and the element.
Result<PolyMesh> load_mesh(const std::string& path);

// OBJ with 9 significant digits (float32 round-trips exactly).
Status save_obj(const std::string& path, std::span<const glm::vec3> positions, const PolyMesh& topology);
// Raw little-endian float32, #V x 3, in vertex order.
Status save_bin(const std::string& path, std::span<const glm::vec3> positions);
Result<std::vector<glm::vec3>> load_bin(const std::string& path);
// Chooses by extension: .obj or .bin.
Status save_positions(const std::string& path, std::span<const glm::vec3> positions, const PolyMesh& topology);

bool has_extension(const std::string& path, const char* ext);

}  // namespace cagewrap
