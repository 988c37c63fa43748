// Reading and writing static meshes and cages: OBJ and ASCII OFF read by the strict parsers of
// core/geometry/text_mesh_readers.h, PLY, STL and binary OFF through OpenMesh (ASCII PLY and STL checked token by
// token first); OBJ and raw float32 .bin written here.
#pragma once

#include <span>
#include <string>

#include <glm/vec3.hpp>

#include "core/geometry/mesh.h"
#include "core/base/result.h"

namespace cagewrap {

// Loads every vertex and polygon exactly as stored (no welding, no manifold repair, faces kept in
// file order, repeated corners included), then validates: missing/empty file, parse failure,
// non-finite coordinates and corner indices out of range are errors naming the file and the vertex or
// face (numbered from 0 in file order), and for text formats the line.
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
