// Reading JSON files whose errors a user can act on: every failure names the file and the JSON path
// of the value (`cage.faces[12][3] is vertex 99, but the cage has 26 vertices`), or the line and
// column of a syntax error. Shared by the project file (project_io.h) and the set edits file
// (set_edits_io.h).
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

#include "core/base/result.h"

namespace cagewrap {

using Json = nlohmann::ordered_json;  // keeps the order of fields a build does not know

// Thrown by JsonReader::fail; the loader catches it and returns its error.
struct JsonLoadFailure {
  Error error;
};

// Reads fields by JSON path; a failure throws JsonLoadFailure with a message that names the file and
// the path.
class JsonReader {
 public:
  explicit JsonReader(std::string file) : file_(std::move(file)) {}
  const std::string& file() const { return file_; }

  [[noreturn]] void fail(ErrorCode code, const std::string& what) const;
  // A value as the message shows it (cut at 40 characters).
  static std::string show(const Json& j);

  const Json& field(const Json& object, const std::string& path, const char* key) const;
  const Json& object(const Json& object, const std::string& path, const char* key) const;
  const Json& array(const Json& j, const std::string& path) const;
  std::string string(const Json& j, const std::string& path) const;
  double number(const Json& j, const std::string& path) const;  // finite
  float finite_float(const Json& j, const std::string& path) const;
  uint32_t index(const Json& j, const std::string& path) const;  // a whole number in [0, 2^32)
  bool boolean(const Json& j, const std::string& path) const;
  std::vector<uint32_t> indices(const Json& j, const std::string& path) const;

  static std::string join(const std::string& path, const char* key) {
    return path.empty() ? key : path + "." + key;
  }
  static std::string at(const std::string& path, size_t i) { return path + "[" + std::to_string(i) + "]"; }

 private:
  std::string file_;
};

// The file's text parsed as JSON. Errors: kFileNotFound, kFileUnreadable, kParse ("not a JSON file
// (at line 3, column 7: ...)"), each naming the file.
Result<Json> read_json_file(const std::string& path);

// "[1, 2, 3]"
std::string json_index_list(std::span<const uint32_t> v);

// The double nearest to the shortest decimal that reads back as `f` (so a file says 0.1, not
// 0.100000001490116); f itself in the rare case that decimal would round to another float. Either
// way the float reads back bit for bit.
double json_short_float(float f);

// JSON text laid out for people and diffs: an array or object on one line when that line is at most
// `width` characters; else an array of plain values (numbers, strings, ...) fills lines of `width`,
// and any other array or object has one member a line, indented by two spaces a level. Ends without
// a newline.
std::string json_layout(const Json& j, size_t width = 100);

}  // namespace cagewrap
