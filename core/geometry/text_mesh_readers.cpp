#include "core/geometry/text_mesh_readers.h"

#include "core/base/digits.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <system_error>
#include <vector>

namespace cagewrap {

namespace {

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

// The lines of a buffer ('\n'-terminated; a '\r' before it is whitespace), numbered from 1.
class Lines {
 public:
  explicit Lines(std::string_view text) : p_(text.data()), end_(text.data() + text.size()) {}
  bool next(std::string_view& line) {
    if (p_ == end_) return false;
    const char* nl = static_cast<const char*>(std::memchr(p_, '\n', static_cast<size_t>(end_ - p_)));
    const char* stop = nl ? nl : end_;
    line = std::string_view(p_, static_cast<size_t>(stop - p_));
    p_ = nl ? nl + 1 : end_;
    ++number_;
    return true;
  }
  size_t number() const { return number_; }                            // of the line last returned
  size_t remaining() const { return static_cast<size_t>(end_ - p_); }  // bytes after it
  const char* position() const { return p_; }

 private:
  const char* p_;
  const char* end_;
  size_t number_ = 0;
};

// The whitespace-separated tokens of one line: of a line without its '\n', or of the line starting
// at `begin` in a buffer (then line_end() is where the next line starts).
class Tokens {
 public:
  explicit Tokens(std::string_view line) : p_(line.data()), end_(line.data() + line.size()) {}
  Tokens(const char* begin, const char* end) : p_(begin), end_(end) {}
  bool next(std::string_view& token) {
    while (p_ != end_ && is_space(*p_)) ++p_;
    if (p_ == end_ || *p_ == '\n') return false;
    const char* start = p_;
    while (p_ != end_ && !is_space(*p_) && *p_ != '\n') ++p_;
    token = std::string_view(start, static_cast<size_t>(p_ - start));
    return true;
  }
  const char* line_end() const {
    const char* nl = static_cast<const char*>(std::memchr(p_, '\n', static_cast<size_t>(end_ - p_)));
    return nl ? nl + 1 : end_;
  }

 private:
  const char* p_;
  const char* end_;
};

// A token as it may appear in a message: at most 40 characters, control bytes shown as '?'.
std::string quoted(std::string_view token) {
  std::string s = "'";
  for (size_t i = 0; i < token.size() && i < 40; ++i) {
    unsigned char c = static_cast<unsigned char>(token[i]);
    s += c < 32 || c == 127 ? '?' : token[i];
  }
  if (token.size() > 40) s += "...";
  return s + "'";
}

enum class Num { kOk, kNotANumber, kNonFinite, kOutOfRange };

// A decimal number, correctly rounded to F. kNonFinite for nan, inf and values beyond F's range; an
// underflow is a number (zero or a subnormal). A leading '+' is accepted.
template <class F>
Num parse_real(std::string_view token, F& out) {
  const char* b = token.data();
  const char* e = b + token.size();
  if (b != e && *b == '+') {
    ++b;
    if (b != e && *b == '-') return Num::kNotANumber;
  }
  if (b == e) return Num::kNotANumber;
  F value{};
  auto [ptr, ec] = std::from_chars(b, e, value, std::chars_format::general);
  if (ptr != e) return Num::kNotANumber;
  if (ec == std::errc::result_out_of_range) {
    // overflow or underflow: strtod tells them apart (HUGE_VAL or a value at most the smallest normal)
    std::string copy(b, e);
    const double d = std::strtod(copy.c_str(), nullptr);
    if (!std::isfinite(d) || std::abs(d) > double(std::numeric_limits<F>::max())) return Num::kNonFinite;
    out = static_cast<F>(d);
    return Num::kOk;
  }
  if (ec != std::errc()) return Num::kNotANumber;
  if (!std::isfinite(value)) return Num::kNonFinite;
  out = value;
  return Num::kOk;
}

// A decimal integer (a leading '+' is accepted); kOutOfRange beyond int64.
Num parse_int(std::string_view token, int64_t& out) {
  const char* b = token.data();
  const char* e = b + token.size();
  if (b != e && *b == '+') {
    ++b;
    if (b != e && *b == '-') return Num::kNotANumber;
  }
  if (b == e) return Num::kNotANumber;
  auto [ptr, ec] = std::from_chars(b, e, out);
  if (ptr != e) return Num::kNotANumber;
  if (ec == std::errc::result_out_of_range) return Num::kOutOfRange;
  if (ec != std::errc()) return Num::kNotANumber;
  return Num::kOk;
}

std::string at_line(const std::string& path, size_t line) {
  return path + ": line " + std::to_string(line) + ": ";
}

// Three coordinates of vertex `v` on line `line` from `tokens`; extra tokens are the caller's.
Status read_xyz(Tokens& tokens, glm::vec3& p, size_t v, const std::string& path, size_t line) {
  for (int k = 0; k < 3; ++k) {
    std::string_view token;
    if (!tokens.next(token) || token[0] == '#')
      return make_error(ErrorCode::kParse, at_line(path, line) + "vertex " + std::to_string(v) + " has " +
                                               std::to_string(k) + " coordinates, not 3");
    switch (parse_real(token, p[k])) {
      case Num::kOk:
        break;
      case Num::kNonFinite:
        return make_error(ErrorCode::kNonFinite, at_line(path, line) + "vertex " + std::to_string(v) +
                                                     " has a non-finite coordinate (" + quoted(token) +
                                                     " is not a finite float)");
      default:
        return make_error(ErrorCode::kParse, at_line(path, line) + "vertex " + std::to_string(v) + ": " +
                                                 quoted(token) + " is not a number");
    }
  }
  return Ok{};
}

bool equals_nocase(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(a[i])) != b[i]) return false;
  return true;
}

}  // namespace

// ------------------------------------------------------------------------------------------ OBJ

Result<PolyMesh> read_obj(std::string_view text, const std::string& path) {
  PolyMesh mesh;
  // Corners naming a vertex not read yet: legal only if the file defines it later (checked at the end).
  struct Forward {
    uint32_t face;
    size_t line;
    uint32_t vertex;
  };
  std::vector<Forward> forward;
  const char* const end = text.data() + text.size();
  {
    // count the v and f statements first: on a 100 MB file growing the arrays instead costs more
    size_t nv = 0, nf = 0;
    for (const char* p = text.data(); p < end;) {
      while (p < end && is_space(*p)) ++p;
      if (end - p >= 2 && is_space(p[1])) {
        nv += p[0] == 'v';
        nf += p[0] == 'f';
      }
      const char* nl = static_cast<const char*>(std::memchr(p, '\n', static_cast<size_t>(end - p)));
      p = nl ? nl + 1 : end;
    }
    mesh.positions.reserve(nv);
    mesh.face_start.reserve(nf + 1);
    mesh.face_vertices.reserve(3 * nf);  // triangles; larger polygons grow it
  }
  // then one pass over the buffer, no line splitting first
  const char* cursor = text.data();
  size_t line = 0;
  while (cursor != end) {
    ++line;
    Tokens tokens(cursor, end);
    std::string_view keyword;
    if (!tokens.next(keyword)) {
      cursor = tokens.line_end();
      continue;
    }
    if (keyword == "v") {
      glm::vec3 p;
      if (auto s = read_xyz(tokens, p, mesh.positions.size(), path, line); !s) return s.error();
      mesh.positions.push_back(p);
    } else if (keyword == "f") {
      const size_t face = mesh.num_faces();
      const size_t first = mesh.face_vertices.size();
      std::string_view token;
      while (tokens.next(token)) {
        if (token[0] == '#') break;
        const std::string_view written = token.substr(0, token.find('/'));  // a, a/b, a//c, a/b/c
        int64_t index = 0;
        const Num n = parse_int(written, index);
        const int64_t count = static_cast<int64_t>(mesh.positions.size());
        if (n == Num::kNotANumber)
          return make_error(ErrorCode::kParse, at_line(path, line) + "face " + std::to_string(face) +
                                                   ": corner " + quoted(token) + " is not a vertex index");
        if (n == Num::kOutOfRange || index > int64_t(UINT32_MAX))
          return make_error(ErrorCode::kIndexOutOfRange, at_line(path, line) + "face " +
                                                             std::to_string(face) + " uses vertex index " +
                                                             quoted(written) + ", beyond any vertex");
        if (index == 0)
          return make_error(ErrorCode::kIndexOutOfRange, at_line(path, line) + "face " +
                                                             std::to_string(face) +
                                                             " uses vertex index 0 (OBJ indices start at 1)");
        uint32_t corner;
        if (index < 0) {
          if (-index > count)
            return make_error(ErrorCode::kIndexOutOfRange,
                              at_line(path, line) + "face " + std::to_string(face) +
                                  " uses relative vertex index " + std::string(written) + " but only " +
                                  std::to_string(count) + " vertices precede it");
          corner = static_cast<uint32_t>(count + index);
        } else {
          corner = static_cast<uint32_t>(index - 1);
          if (index > count) forward.push_back({static_cast<uint32_t>(face), line, corner});
        }
        mesh.face_vertices.push_back(corner);
      }
      const size_t corners = mesh.face_vertices.size() - first;
      if (corners < 3)
        return make_error(ErrorCode::kParse, at_line(path, line) + "face " + std::to_string(face) + " has " +
                                                 std::to_string(corners) +
                                                 " corners; a face needs at least 3");
      mesh.face_start.push_back(static_cast<uint32_t>(mesh.face_vertices.size()));
    }
    // vt, vn, vp, g, o, s, l, p, usemtl, mtllib, comments and unknown statements: ignored
    cursor = tokens.line_end();
  }
  for (const Forward& f : forward)
    if (f.vertex >= mesh.positions.size())
      return make_error(ErrorCode::kIndexOutOfRange,
                        at_line(path, f.line) + "face " + std::to_string(f.face) + " uses vertex " +
                            std::to_string(f.vertex) + " (written " + std::to_string(uint64_t(f.vertex) + 1) +
                            ": OBJ counts from 1) but there are only " +
                            std::to_string(mesh.positions.size()) + " vertices");
  return mesh;
}

// ------------------------------------------------------------------------------------------ OFF

namespace {

// The next line holding data: blank lines and comments are skipped, a trailing comment is cut off.
bool next_data_line(Lines& lines, std::string_view& line) {
  while (lines.next(line)) {
    if (size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    std::string_view token;
    if (Tokens(line).next(token)) return true;
  }
  return false;
}

}  // namespace

bool off_is_binary(std::string_view text) {
  Lines lines(text);
  std::string_view line, keyword, next;
  if (!next_data_line(lines, line)) return false;
  Tokens tokens(line);
  return tokens.next(keyword) && keyword.ends_with("OFF") && tokens.next(next) && next == "BINARY";
}

Result<PolyMesh> read_off(std::string_view text, const std::string& path) {
  Lines lines(text);
  std::string_view line;
  if (!next_data_line(lines, line))
    return make_error(ErrorCode::kParse,
                      path + ": could not be parsed as OFF (the file holds no OFF header)");
  Tokens header(line);
  std::string_view keyword;
  header.next(keyword);
  const std::string_view prefix = keyword.substr(0, keyword.size() >= 3 ? keyword.size() - 3 : 0);
  if (!keyword.ends_with("OFF") || prefix.find_first_not_of("STCN4n") != std::string_view::npos)
    return make_error(ErrorCode::kParse, at_line(path, lines.number()) +
                                             "could not be parsed as OFF (the header " + quoted(keyword) +
                                             " should be OFF, COFF, NOFF or the like)");
  if (prefix.find_first_of("4n") != std::string_view::npos)
    return make_error(ErrorCode::kUnsupportedFormat,
                      at_line(path, lines.number()) + quoted(keyword) +
                          " (homogeneous or n-dimensional OFF) is not supported");
  // the counts follow on the header line or on the next data line
  std::vector<std::string_view> counts;
  for (std::string_view token; header.next(token);) counts.push_back(token);
  if (!counts.empty() && counts[0] == "BINARY")
    return make_error(ErrorCode::kUnsupportedFormat, path + ": binary OFF is read elsewhere");
  if (counts.empty()) {
    if (!next_data_line(lines, line))
      return make_error(ErrorCode::kParse, path + ": the file ends before the vertex and face counts");
    Tokens t(line);
    for (std::string_view token; t.next(token);) counts.push_back(token);
  }
  if (counts.size() < 2)
    return make_error(ErrorCode::kParse,
                      at_line(path, lines.number()) + "expected the vertex, face and edge counts");
  int64_t nv = 0, nf = 0;
  const char* names[2] = {"vertex", "face"};
  int64_t* values[2] = {&nv, &nf};
  for (int i = 0; i < 2; ++i)
    if (parse_int(counts[i], *values[i]) != Num::kOk || *values[i] < 0 || *values[i] > int64_t(UINT32_MAX))
      return make_error(ErrorCode::kParse, at_line(path, lines.number()) + "the " + names[i] + " count " +
                                               quoted(counts[i]) + " is not a count");
  // Every vertex line holds at least "0 0 0\n", every face line at least "3 0 1 2\n" (the last line may
  // lack its newline): a header promising more than the rest of the file can hold is refused before
  // anything is reserved.
  const uint64_t needed = 6 * uint64_t(nv) + 8 * uint64_t(nf);
  if (needed > uint64_t(lines.remaining()) + 1)
    return make_error(ErrorCode::kParse, at_line(path, lines.number()) + "the header promises " +
                                             group_digits(nv) + " vertices and " + group_digits(nf) +
                                             " faces (at least " + group_digits(needed) + " bytes), more than the " +
                                             group_digits(lines.remaining()) + " bytes after it can hold");
  PolyMesh mesh;
  mesh.positions.reserve(static_cast<size_t>(nv));
  mesh.face_start.reserve(static_cast<size_t>(nf) + 1);
  mesh.face_vertices.reserve(3 * static_cast<size_t>(nf));
  for (int64_t v = 0; v < nv; ++v) {
    if (!next_data_line(lines, line))
      return make_error(ErrorCode::kParse, path + ": the header promises " + std::to_string(nv) +
                                               " vertices but the file ends after " + std::to_string(v));
    Tokens tokens(line);
    glm::vec3 p;
    if (auto s = read_xyz(tokens, p, static_cast<size_t>(v), path, lines.number()); !s) return s.error();
    mesh.positions.push_back(p);  // colours, normals, texture coordinates after x y z: ignored
  }
  for (int64_t f = 0; f < nf; ++f) {
    if (!next_data_line(lines, line))
      return make_error(ErrorCode::kParse, path + ": the header promises " + std::to_string(nf) +
                                               " faces but the file ends after " + std::to_string(f));
    auto where = [&] { return at_line(path, lines.number()) + "face " + std::to_string(f); };
    Tokens tokens(line);
    std::string_view token;
    tokens.next(token);
    int64_t n = 0;
    if (parse_int(token, n) != Num::kOk || n < 0)
      return make_error(ErrorCode::kParse, where() + ": " + quoted(token) + " is not a corner count");
    if (n < 3)
      return make_error(ErrorCode::kParse,
                        where() + " has " + std::to_string(n) + " corners; a face needs at least 3");
    for (int64_t k = 0; k < n; ++k) {
      if (!tokens.next(token))
        return make_error(ErrorCode::kParse, where() + " lists " + std::to_string(n) +
                                                 " corners but the line holds " + std::to_string(k));
      int64_t index = 0;
      const Num r = parse_int(token, index);
      if (r == Num::kNotANumber)
        return make_error(ErrorCode::kParse,
                          where() + ": corner " + quoted(token) + " is not a vertex index");
      if (r == Num::kOutOfRange || index < 0 || index >= nv)
        return make_error(ErrorCode::kIndexOutOfRange, where() + " uses vertex " + std::string(token) +
                                                           " but there are only " + std::to_string(nv) +
                                                           " vertices");
      mesh.face_vertices.push_back(static_cast<uint32_t>(index));
    }
    mesh.face_start.push_back(static_cast<uint32_t>(mesh.face_vertices.size()));  // a colour after: ignored
  }
  return mesh;
}

Status check_binary_off(std::string_view data, const std::string& path) {
  // OpenMesh reads a file as binary OFF when its first line is [ST][C][N]OFF, one character, BINARY
  // (anything else it reads as text: a header with two spaces made it parse the binary body as text
  // and size a face by a number in it, found by fuzz_mesh). Then come the counts (32-bit,
  // little-endian), each vertex (x y z as floats, a normal with N, a colour of three 32-bit integers
  // with C, u v with ST) and each face (a corner count and that many 32-bit indices; no colour).
  const size_t end_of_header = data.find('\n');
  const std::string_view line = data.substr(0, end_of_header);
  size_t at_keyword = 0, vertex_bytes = 12;
  for (const auto& [flag, bytes] : {std::pair<std::string_view, size_t>{"ST", 8}, {"C", 12}, {"N", 12}})
    if (line.substr(at_keyword).starts_with(flag)) {
      at_keyword += flag.size();
      vertex_bytes += bytes;
    }
  if (end_of_header == std::string_view::npos || line.size() < at_keyword + 10 ||
      line.substr(at_keyword, 3) != "OFF" || line.substr(at_keyword + 4, 6) != "BINARY")
    return make_error(ErrorCode::kParse, path + ": line 1: a binary OFF file must start with the line "
                                                "'[ST][C][N]OFF BINARY' (one space; no 4 or n), not " +
                                                quoted(line));
  const std::string_view body = data.substr(end_of_header + 1);
  auto u32 = [&](size_t at) {
    uint32_t v = 0;
    for (int k = 3; k >= 0; --k) v = v << 8 | static_cast<uint8_t>(body[at + size_t(k)]);
    return v;
  };
  if (body.size() < 12)
    return make_error(ErrorCode::kParse, path + ": the file ends before the vertex, face and edge counts");
  const uint32_t nv = u32(0), nf = u32(4);
  const size_t left = body.size() - 12;
  // every face holds at least a corner count and three corners
  const uint64_t least = uint64_t(nv) * vertex_bytes + uint64_t(nf) * 16;
  if (least > left)
    return make_error(ErrorCode::kParse, path + ": the header promises " + group_digits(nv) + " vertices of " +
                                             std::to_string(vertex_bytes) + " bytes and " + group_digits(nf) +
                                             " faces (at least " + group_digits(least) + " bytes), but " +
                                             group_digits(left) + " bytes follow the counts");
  size_t at = 12 + size_t(nv) * vertex_bytes;
  for (uint32_t f = 0; f < nf; ++f) {
    if (body.size() - at < 4)
      return make_error(ErrorCode::kParse, path + ": the header promises " + group_digits(nf) +
                                               " faces but the file ends at face " + std::to_string(f));
    const uint32_t corners = u32(at);
    at += 4;
    if (uint64_t(corners) * 4 > body.size() - at)
      return make_error(ErrorCode::kParse, path + ": face " + std::to_string(f) + " lists " + group_digits(corners) +
                                               " corners (" + group_digits(uint64_t(corners) * 4) + " bytes) but " +
                                               group_digits(body.size() - at) + " bytes are left in the file");
    at += size_t(corners) * 4;
  }
  return Ok{};
}

// ------------------------------------------------------------------------------------------ PLY

namespace {

enum class PlyType { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

bool ply_type(std::string_view name, PlyType& out) {
  static constexpr std::pair<std::string_view, PlyType> kTypes[] = {
      {"char", PlyType::kInt8},      {"int8", PlyType::kInt8},       {"uchar", PlyType::kUint8},
      {"uint8", PlyType::kUint8},    {"short", PlyType::kInt16},     {"int16", PlyType::kInt16},
      {"ushort", PlyType::kUint16},  {"uint16", PlyType::kUint16},   {"int", PlyType::kInt32},
      {"int32", PlyType::kInt32},    {"uint", PlyType::kUint32},     {"uint32", PlyType::kUint32},
      {"float", PlyType::kFloat32},  {"float32", PlyType::kFloat32}, {"double", PlyType::kFloat64},
      {"float64", PlyType::kFloat64}};
  for (const auto& [n, t] : kTypes)
    if (n == name) {
      out = t;
      return true;
    }
  return false;
}

const char* ply_type_name(PlyType t) {
  switch (t) {
    case PlyType::kInt8:
      return "char";
    case PlyType::kUint8:
      return "uchar";
    case PlyType::kInt16:
      return "short";
    case PlyType::kUint16:
      return "ushort";
    case PlyType::kInt32:
      return "int";
    case PlyType::kUint32:
      return "uint";
    case PlyType::kFloat32:
      return "float";
    case PlyType::kFloat64:
      return "double";
  }
  return "?";
}

void int_range(PlyType t, int64_t& lo, int64_t& hi) {
  switch (t) {
    case PlyType::kInt8:
      lo = INT8_MIN, hi = INT8_MAX;
      break;
    case PlyType::kUint8:
      lo = 0, hi = UINT8_MAX;
      break;
    case PlyType::kInt16:
      lo = INT16_MIN, hi = INT16_MAX;
      break;
    case PlyType::kUint16:
      lo = 0, hi = UINT16_MAX;
      break;
    case PlyType::kInt32:
      lo = INT32_MIN, hi = INT32_MAX;
      break;
    default:
      lo = 0, hi = UINT32_MAX;
      break;
  }
}

size_t ply_type_size(PlyType t) {
  switch (t) {
    case PlyType::kInt8:
    case PlyType::kUint8:
      return 1;
    case PlyType::kInt16:
    case PlyType::kUint16:
      return 2;
    case PlyType::kFloat64:
      return 8;
    default:
      return 4;
  }
}

struct PlyProperty {
  bool list = false;
  PlyType count_type = PlyType::kUint8;
  PlyType type = PlyType::kFloat32;
  std::string_view name;
};

struct PlyElement {
  std::string_view name;
  uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

// The whitespace-separated tokens of the body, across lines.
class Stream {
 public:
  Stream(const char* begin, const char* end, size_t line) : p_(begin), end_(end), line_(line) {}
  bool next(std::string_view& token) {
    while (p_ != end_ && (is_space(*p_) || *p_ == '\n')) {
      if (*p_ == '\n') ++line_;
      ++p_;
    }
    if (p_ == end_) return false;
    const char* start = p_;
    while (p_ != end_ && !is_space(*p_) && *p_ != '\n') ++p_;
    token = std::string_view(start, static_cast<size_t>(p_ - start));
    return true;
  }
  size_t line() const { return line_; }

 private:
  const char* p_;
  const char* end_;
  size_t line_;
};

// A binary PLY body against the header: every element's fixed-size values and every list's entries
// must lie in the bytes after the header, checked before OpenMesh reads it (it reads on past the end
// of a file, growing its arrays as it goes: a header promising 10^9 vertices or a list of 4 * 10^9
// entries asked for gigabytes). Element counts are checked first, then the lists walked one by one.
Status check_binary_ply_body(const std::vector<PlyElement>& elements, bool big_endian, std::string_view body,
                             const std::string& path) {
  unsigned __int128 least = 0;  // bytes the elements need with every list empty
  for (const PlyElement& e : elements) {
    size_t per = 0;
    for (const PlyProperty& p : e.properties) per += ply_type_size(p.list ? p.count_type : p.type);
    least += static_cast<unsigned __int128>(e.count) * per;
    if (least > body.size())
      return make_error(ErrorCode::kParse,
                        path + ": the header promises " + group_digits(e.count) + " " + std::string(e.name) +
                            " elements of at least " + std::to_string(per) + " bytes each (" + group_digits(least) +
                            " bytes with the elements before them), but " + group_digits(body.size()) +
                            " bytes follow the header");
  }
  // an unsigned count of `type` at `at`, in the file's byte order; false when it is negative
  auto read_count = [&](size_t at, PlyType type, uint64_t& out) {
    const size_t n = ply_type_size(type);
    uint64_t v = 0;
    for (size_t k = 0; k < n; ++k) {
      const uint64_t byte = static_cast<uint8_t>(body[at + (big_endian ? k : n - 1 - k)]);
      v = v << 8 | byte;
    }
    const bool is_signed = type == PlyType::kInt8 || type == PlyType::kInt16 || type == PlyType::kInt32;
    if (is_signed && (v >> (8 * n - 1)) != 0) return false;
    out = v;
    return true;
  };
  size_t at = 0;
  for (const PlyElement& e : elements) {
    // the elements before have been walked, so this one's count times its least size fits the body
    for (uint64_t i = 0; i < e.count; ++i) {
      for (const PlyProperty& p : e.properties) {
        const size_t head = ply_type_size(p.list ? p.count_type : p.type);
        if (head > body.size() - at)
          return make_error(ErrorCode::kParse, path + ": the header promises " + group_digits(e.count) + " " +
                                                   std::string(e.name) + " elements but the file ends at " +
                                                   std::string(e.name) + " " + std::to_string(i));
        if (!p.list) {
          at += head;
          continue;
        }
        uint64_t n = 0;
        if (!read_count(at, p.count_type, n))
          return make_error(ErrorCode::kParse, path + ": " + std::string(e.name) + " " + std::to_string(i) +
                                                   ": a negative list length (property '" + std::string(p.name) +
                                                   "')");
        at += head;
        const unsigned __int128 bytes = static_cast<unsigned __int128>(n) * ply_type_size(p.type);
        if (bytes > body.size() - at)
          return make_error(ErrorCode::kParse,
                            path + ": " + std::string(e.name) + " " + std::to_string(i) + ": property '" +
                                std::string(p.name) + "' lists " + group_digits(n) + " entries (" +
                                group_digits(bytes) + " bytes) but " + group_digits(body.size() - at) +
                                " bytes are left in the file");
        at += static_cast<size_t>(bytes);
      }
    }
  }
  return Ok{};
}

}  // namespace

Status check_ascii_ply(std::string_view data, const std::string& path, std::string* canonical) {
  Lines lines(data);
  std::string_view line, token;
  if (!lines.next(line) || !Tokens(line).next(token) || token != "ply")
    return make_error(ErrorCode::kParse,
                      path + ": could not be parsed as PLY (the file does not start with 'ply')");
  std::vector<PlyElement> elements;
  std::string_view format_name;
  bool ascii = false, have_format = false, ended = false;
  while (!ended && lines.next(line)) {
    Tokens tokens(line);
    std::string_view keyword;
    if (!tokens.next(keyword)) continue;
    const std::string where = at_line(path, lines.number());
    if (keyword == "format") {
      std::string_view format, version, extra;
      tokens.next(format);
      if (!tokens.next(version) || version != "1.0" || tokens.next(extra))
        return make_error(ErrorCode::kParse, where + "the format line should read 'format <type> 1.0'");
      format_name = format;
      if (format == "ascii")
        ascii = true;
      else if (format != "binary_little_endian" && format != "binary_big_endian")
        return make_error(ErrorCode::kParse, where + "unknown PLY format " + quoted(format));
      have_format = true;
    } else if (keyword == "comment" || keyword == "obj_info") {
      continue;
    } else if (keyword == "element") {
      PlyElement e;
      std::string_view count;
      int64_t n = 0;
      std::string_view extra;
      if (!tokens.next(e.name) || !tokens.next(count) || parse_int(count, n) != Num::kOk || n < 0 ||
          tokens.next(extra))
        return make_error(ErrorCode::kParse, where + "the element line should read 'element <name> <count>'");
      e.count = static_cast<uint64_t>(n);
      elements.push_back(e);
    } else if (keyword == "property") {
      if (elements.empty()) return make_error(ErrorCode::kParse, where + "a property before any element");
      PlyProperty p;
      std::string_view type;
      tokens.next(type);
      if (type == "list") {
        p.list = true;
        std::string_view count_type;
        tokens.next(count_type);
        if (!ply_type(count_type, p.count_type) || p.count_type == PlyType::kFloat32 ||
            p.count_type == PlyType::kFloat64)
          return make_error(ErrorCode::kParse,
                            where + quoted(count_type) + " is not an integer type for a list count");
        tokens.next(type);
      }
      if (!ply_type(type, p.type))
        return make_error(ErrorCode::kParse, where + "unknown property type " + quoted(type));
      if (!tokens.next(p.name)) return make_error(ErrorCode::kParse, where + "a property without a name");
      // OpenMesh reads the header word by word: words after the name would be read as the next line's
      // (a tab-joined 'element vertex 4\tproperty <junk>' made it print errors without end: fuzzing)
      if (std::string_view extra; tokens.next(extra))
        return make_error(ErrorCode::kParse, where + "unexpected " + quoted(extra) + " after property " +
                                                 quoted(p.name));
      elements.back().properties.push_back(p);
    } else if (keyword == "end_header") {
      ended = true;
    } else {
      return make_error(ErrorCode::kParse, where + "unexpected " + quoted(keyword) + " in the PLY header");
    }
  }
  if (!ended) return make_error(ErrorCode::kParse, path + ": the PLY header has no end_header line");
  if (!have_format) return make_error(ErrorCode::kParse, path + ": the PLY header has no format line");
  // an element of nothing cannot be in the file, yet reading it would take `count` steps
  for (const PlyElement& e : elements)
    if (e.properties.empty() && e.count > 0)
      return make_error(ErrorCode::kParse, path + ": element " + std::string(e.name) + " has no properties but a count of " +
                                               group_digits(e.count));
  // OpenMesh's reader assumes a vertex element (it crashed on a header without one: found by fuzzing)
  if (std::none_of(elements.begin(), elements.end(), [](const PlyElement& e) { return e.name == "vertex"; }))
    return make_error(ErrorCode::kParse, path + ": the PLY header declares no vertex element");
  if (canonical) {
    std::string& out = *canonical;
    out = "ply\nformat " + std::string(format_name) + " 1.0\n";
    for (const PlyElement& e : elements) {
      out += "element " + std::string(e.name) + " " + std::to_string(e.count) + "\n";
      for (const PlyProperty& p : e.properties)
        out += std::string("property ") + (p.list ? std::string("list ") + ply_type_name(p.count_type) + " " : "") +
               ply_type_name(p.type) + " " + std::string(p.name) + "\n";
    }
    out += "end_header\n";
    out.append(lines.position(), data.data() + data.size());
  }
  if (!ascii)
    return check_binary_ply_body(elements, format_name == "binary_big_endian",
                                 data.substr(static_cast<size_t>(lines.position() - data.data())), path);

  uint64_t num_vertices = 0;
  bool have_vertices = false;
  for (const auto& e : elements)
    if (e.name == "vertex") num_vertices = e.count, have_vertices = true;
  Stream body(lines.position(), data.data() + data.size(), lines.number() + 1);
  for (const PlyElement& e : elements) {
    const bool is_vertex = e.name == "vertex", is_face = e.name == "face";
    for (uint64_t i = 0; i < e.count; ++i) {
      auto named = [&] { return at_line(path, body.line()) + std::string(e.name) + " " + std::to_string(i); };
      auto next = [&](std::string_view& t) {
        if (body.next(t)) return Status(Ok{});
        return Status(make_error(ErrorCode::kParse, path + ": the header promises " +
                                                        group_digits(e.count) + " " + std::string(e.name) +
                                                        " elements but the file ends at " +
                                                        std::string(e.name) + " " + std::to_string(i)));
      };
      // one value of `type`; `index` marks a face's vertex index
      auto value = [&](PlyType type, const PlyProperty& p, bool index) -> Status {
        std::string_view t;
        if (auto s = next(t); !s) return s;
        if (type == PlyType::kFloat32 || type == PlyType::kFloat64) {
          float f;
          double d;
          const Num r = type == PlyType::kFloat32 ? parse_real(t, f) : parse_real(t, d);
          if (r == Num::kOk) return Ok{};
          if (r == Num::kNonFinite) {
            if (is_vertex && (p.name == "x" || p.name == "y" || p.name == "z"))
              return make_error(ErrorCode::kNonFinite,
                                named() + " has a non-finite coordinate (" + quoted(t) + " is not a finite " +
                                    (type == PlyType::kFloat32 ? "float)" : "double)"));
            return make_error(ErrorCode::kNonFinite, named() + " has a non-finite value " + quoted(t) +
                                                         " in property '" + std::string(p.name) + "'");
          }
          return make_error(ErrorCode::kParse, named() + ": " + quoted(t) + " is not a number (property '" +
                                                   std::string(p.name) + "')");
        }
        int64_t v = 0, lo = 0, hi = 0;
        int_range(type, lo, hi);
        const Num r = parse_int(t, v);
        if (index && (r == Num::kOutOfRange ||
                      (r == Num::kOk && (v < 0 || (have_vertices && uint64_t(v) >= num_vertices)))))
          return make_error(ErrorCode::kIndexOutOfRange, named() + " uses vertex " + std::string(t) +
                                                             " but there are only " +
                                                             std::to_string(num_vertices) + " vertices");
        if (r != Num::kOk || v < lo || v > hi)
          return make_error(ErrorCode::kParse, named() + ": " + quoted(t) + " is not a valid " +
                                                   ply_type_name(type) + " (property '" +
                                                   std::string(p.name) + "')");
        return Ok{};
      };
      for (const PlyProperty& p : e.properties) {
        if (!p.list) {
          if (auto s = value(p.type, p, false); !s) return s;
          continue;
        }
        std::string_view t;
        if (auto s = next(t); !s) return s;
        int64_t n = 0, lo = 0, hi = 0;
        int_range(p.count_type, lo, hi);
        if (parse_int(t, n) != Num::kOk || n < 0 || n > hi)
          return make_error(ErrorCode::kParse, named() + ": " + quoted(t) + " is not a list length of type " +
                                                   ply_type_name(p.count_type) + " (property '" +
                                                   std::string(p.name) + "')");
        const bool index = is_face && (p.name == "vertex_indices" || p.name == "vertex_index");
        for (int64_t k = 0; k < n; ++k)
          if (auto s = value(p.type, p, index); !s) return s;
      }
    }
  }
  return Ok{};
}

// ------------------------------------------------------------------------------------------ STL

Status check_ascii_stl(std::string_view data, const std::string& path) {
  if (data.size() >= 84) {  // OpenMesh's own test (in 64-bit arithmetic, as it does it)
    uint32_t triangles;
    std::memcpy(&triangles, data.data() + 80, 4);
    if (84 + uint64_t(triangles) * 50 == data.size()) return Ok{};
  }
  Lines lines(data);
  std::string_view line;
  size_t vertex = 0;
  while (lines.next(line)) {
    Tokens tokens(line);
    std::string_view keyword;
    if (!tokens.next(keyword)) continue;
    if (equals_nocase(keyword, "vertex")) {
      glm::vec3 p;
      if (auto s = read_xyz(tokens, p, vertex, path, lines.number()); !s) return s;
      ++vertex;
    } else if (equals_nocase(keyword, "facet")) {
      std::string_view word;
      if (!tokens.next(word) || !equals_nocase(word, "normal")) continue;
      for (int k = 0; k < 3; ++k) {
        std::string_view t;
        float f;
        if (!tokens.next(t) || parse_real(t, f) == Num::kNotANumber)
          return make_error(ErrorCode::kParse,
                            at_line(path, lines.number()) + "the facet normal should be three numbers");
      }
    }
  }
  return Ok{};
}

}  // namespace cagewrap
