// Strict readers for the text mesh formats: OBJ and ASCII OFF parsed here, and checks of ASCII PLY and
// ASCII STL made before OpenMesh reads them.
//
// OpenMesh's text readers parse numbers with operator>> and carry on after one fails: a vertex line
// with "nan" or "1e999" is skipped (shifting every later index), keeps a stale value, or (ASCII PLY)
// reads on from a failed stream without end. They also drop or rewrite OBJ faces with a repeated
// corner. These readers keep every vertex and every polygon exactly as stored, in file order, and
// stop at the first bad token with a message naming the file, the line and the vertex or face
// (vertices and faces are numbered from 0, in file order, as everywhere else in cagewrap).
// Numbers are parsed with std::from_chars (correctly rounded to float, no locale, no allocation).
#pragma once

#include <string>
#include <string_view>

#include "core/geometry/mesh.h"
#include "core/base/result.h"

namespace cagewrap {

// Wavefront OBJ: `v` lines (x y z; a w or colour after them is ignored) and `f` lines with corners
// written `a`, `a/b`, `a//c` or `a/b/c`, 1-based or negative (relative to the vertices read so far).
// Other statements (vt, vn, vp, g, o, s, l, p, usemtl, mtllib, comments, unknown keywords) are
// ignored. `text` is the whole file; `path` only names it in messages.
Result<PolyMesh> read_obj(std::string_view text, const std::string& path);

// True when `text` is an OFF file with the BINARY keyword (checked by check_binary_off, read by OpenMesh).
bool off_is_binary(std::string_view text);

// Binary OFF ('[ST][C][N]OFF BINARY' on the first line, then little-endian 32-bit numbers, as OpenMesh
// reads it): the counts against the bytes after them, then every face's corner count against the
// bytes left, before OpenMesh reads it (it reads on past the end of the file and sizes a face by its
// count: a header or a face claiming 10^9 asked for gigabytes). Errors name the file and the face.
Status check_binary_off(std::string_view data, const std::string& path);

// ASCII OFF with an OFF, COFF, NOFF, CNOFF, STOFF... header: the counts, then one vertex per line
// (the first three numbers; colours, normals and texture coordinates after them are ignored), then
// one face per line (a corner count, that many 0-based indices, an optional colour). Comments (#) and
// blank lines are skipped. Counts are checked against what the file holds before anything is
// reserved, so a header promising 10^9 vertices costs nothing.
Result<PolyMesh> read_off(std::string_view text, const std::string& path);

// PLY: when the file is ASCII, walks the header and every element the way OpenMesh will and checks
// that every token parses as its declared type (vertex values finite and within float or double
// range, integers within their type, list counts non-negative, face indices non-negative) and that
// the file holds as many elements as the header promises. A binary PLY's values are exact
// (validate_mesh catches non-finite ones), but its element counts and list lengths are checked against
// the bytes after the header, as OpenMesh would read them (it reads on past the end of the file). An
// element with a count but no properties is refused. Not starting with "ply" is a parse error.
// `canonical` (optional) receives the file with its header rewritten from what was checked (one
// element or property per line, canonical type names, comments and obj_info left out), for OpenMesh:
// its own header reader is not robust to junk (fuzzing found headers that made it print errors or add
// elements without end, until memory ran out).
Status check_ascii_ply(std::string_view data, const std::string& path, std::string* canonical = nullptr);

// STL: when the file is not binary (a binary STL is 84 + 50 * triangle-count bytes long, counted in 64
// bits as OpenMesh counts: a count whose product wraps in 32 bits is no binary STL), checks
// that every `vertex` line holds three finite float numbers and every `facet normal` three numbers.
Status check_ascii_stl(std::string_view data, const std::string& path);

}  // namespace cagewrap
