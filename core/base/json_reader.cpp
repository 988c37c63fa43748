#include "core/base/json_reader.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace cagewrap {

void JsonReader::fail(ErrorCode code, const std::string& what) const {
  throw JsonLoadFailure{make_error(code, file_ + ": " + what)};
}

std::string JsonReader::show(const Json& j) {
  std::string s = j.dump();
  return s.size() > 40 ? s.substr(0, 37) + "..." : s;
}

const Json& JsonReader::field(const Json& object, const std::string& path, const char* key) const {
  if (!object.contains(key)) fail(ErrorCode::kParse, join(path, key) + " is missing");
  return object[key];
}

const Json& JsonReader::object(const Json& object, const std::string& path, const char* key) const {
  const Json& j = field(object, path, key);
  if (!j.is_object()) fail(ErrorCode::kParse, join(path, key) + " should be an object, not " + show(j));
  return j;
}

const Json& JsonReader::array(const Json& j, const std::string& path) const {
  if (!j.is_array()) fail(ErrorCode::kParse, path + " should be an array, not " + show(j));
  return j;
}

std::string JsonReader::string(const Json& j, const std::string& path) const {
  if (!j.is_string()) fail(ErrorCode::kParse, path + " should be a string, not " + show(j));
  return j.get<std::string>();
}

double JsonReader::number(const Json& j, const std::string& path) const {
  if (j.is_null())
    fail(ErrorCode::kNonFinite, path + " is null (a NaN or infinity was saved?); it must be a finite number");
  if (!j.is_number()) fail(ErrorCode::kParse, path + " should be a number, not " + show(j));
  double x = j.get<double>();
  if (!std::isfinite(x)) fail(ErrorCode::kNonFinite, path + " is not a finite number");
  return x;
}

float JsonReader::finite_float(const Json& j, const std::string& path) const {
  // doubles from 2^128 - 2^103 on round to infinity as floats; everything below rounds to a float
  constexpr double kFloatOverflow = 0x1.ffffffp127;
  double x = number(j, path);
  if (std::fabs(x) >= kFloatOverflow)
    fail(ErrorCode::kNonFinite, path + " = " + show(j) + " is too large for a float coordinate");
  return static_cast<float>(x);
}

uint32_t JsonReader::index(const Json& j, const std::string& path) const {
  if (!j.is_number_unsigned() || j.get<uint64_t>() > UINT32_MAX)
    fail(ErrorCode::kParse, path + " should be an index (a whole number >= 0), not " + show(j));
  return j.get<uint32_t>();
}

bool JsonReader::boolean(const Json& j, const std::string& path) const {
  if (!j.is_boolean()) fail(ErrorCode::kParse, path + " should be true or false, not " + show(j));
  return j.get<bool>();
}

std::vector<uint32_t> JsonReader::indices(const Json& j, const std::string& path) const {
  array(j, path);
  std::vector<uint32_t> out;
  for (size_t i = 0; i < j.size(); ++i) out.push_back(index(j[i], at(path, i)));
  return out;
}

namespace {

// "line 3, column 7" of a 1-based byte offset.
std::string text_position(const std::string& text, size_t byte) {
  size_t line = 1, column = 1;
  for (size_t i = 0; i + 1 < byte && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

}  // namespace

Result<Json> read_json_file(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    return make_error(ErrorCode::kFileNotFound, path + ": no such file");
  std::ifstream in(path, std::ios::binary);
  if (!in) return make_error(ErrorCode::kFileUnreadable, path + ": cannot be opened for reading");
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  try {
    return Json::parse(text);
  } catch (const Json::parse_error& e) {
    std::string what = e.what();
    size_t colon = what.find(": ", what.find("column"));
    std::string reason = colon == std::string::npos ? what : what.substr(colon + 2);
    return make_error(ErrorCode::kParse,
                      path + ": not a JSON file (at " + text_position(text, e.byte) + ": " + reason + ")");
  } catch (const Json::exception& e) {  // e.g. a number literal too large for a double
    std::string what = e.what();
    return make_error(ErrorCode::kParse,
                      path + ": not a JSON file (" + what.substr(what.find(']') + 2) + ")");
  }
}

std::string json_index_list(std::span<const uint32_t> v) {
  std::string s = "[";
  for (size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + std::to_string(v[i]);
  return s + "]";
}

double json_short_float(float f) {
  char text[32];
  auto written = std::to_chars(text, text + sizeof text, f);
  double d = 0;
  std::from_chars(text, written.ptr, d);
  return std::bit_cast<uint32_t>(static_cast<float>(d)) == std::bit_cast<uint32_t>(f) ? d : double(f);
}

namespace {

// A line break and the indentation of `depth`.
void new_line(std::string& out, size_t depth) {
  out += '\n';
  out.append(2 * depth, ' ');
}

// `depth`: the indentation level of the line `j` starts on; `lead`: characters already on it after
// the indentation (a key).
void layout(const Json& j, size_t width, size_t depth, size_t lead, std::string& out) {
  if (!j.is_structured() || j.empty()) {
    out += j.dump();
    return;
  }
  const bool open_array = j.is_array();
  if (open_array && std::none_of(j.begin(), j.end(), [](const Json& e) { return e.is_structured(); })) {
    // plain values: on one line, or filling lines of `width` below the bracket when too long
    std::vector<std::string> items;
    size_t total = 2 * depth + lead + 2;
    for (const Json& e : j) total += items.emplace_back(e.dump()).size() + 2;
    const bool wrap = total > width;
    out += '[';
    if (wrap) new_line(out, depth + 1);
    size_t column = 2 * (depth + 1);
    for (size_t i = 0; i < items.size(); ++i) {
      if (i) {
        out += ',';
        if (wrap && column + items[i].size() + 2 > width) {
          new_line(out, depth + 1);
          column = 2 * (depth + 1);
        } else {
          out += ' ';
          ++column;
        }
      }
      out += items[i];
      column += items[i].size() + 1;
    }
    if (wrap) new_line(out, depth);
    out += ']';
    return;
  }
  // on one line: members separated by ", ", keys by ": " (given up once it is too long)
  std::string line(1, open_array ? '[' : '{');
  size_t n = 0;
  for (const auto& [key, value] : j.items()) {
    if (n++) line += ", ";
    if (!open_array) line += Json(key).dump() + ": ";
    layout(value, SIZE_MAX, 0, 0, line);
    if (line.size() > width) break;
  }
  line += open_array ? ']' : '}';
  if (line.size() + 2 * depth + lead <= width) {
    out += line;
    return;
  }
  out += open_array ? '[' : '{';
  size_t i = 0;
  for (const auto& [key, value] : j.items()) {
    if (i++) out += ',';
    new_line(out, depth + 1);
    const std::string name = open_array ? std::string() : Json(key).dump() + ": ";
    out += name;
    layout(value, width, depth + 1, name.size(), out);
  }
  new_line(out, depth);
  out += open_array ? ']' : '}';
}

}  // namespace

std::string json_layout(const Json& j, size_t width) {
  std::string out;
  layout(j, width, 0, 0, out);
  return out;
}

}  // namespace cagewrap
