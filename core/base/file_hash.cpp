#include "core/base/file_hash.h"

#include <cstdio>
#include <filesystem>
#include <fstream>

namespace cagewrap {

uint64_t fnv1a64(std::string_view bytes, uint64_t h) {
  for (char c : bytes) {
    h ^= static_cast<unsigned char>(c);
    h *= kFnv1a64Prime;
  }
  return h;
}

std::string format_hash(uint64_t h) {
  char text[32];
  std::snprintf(text, sizeof text, "fnv1a64:%016llx", static_cast<unsigned long long>(h));
  return text;
}

Result<std::string> hash_file(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return make_error(ErrorCode::kFileNotFound, path + ": no such file");
  std::ifstream in(path, std::ios::binary);
  if (!in) return make_error(ErrorCode::kFileUnreadable, path + ": cannot be opened for reading");
  uint64_t h = kFnv1a64Offset;
  std::string chunk(1 << 16, '\0');
  while (in) {
    in.read(chunk.data(), static_cast<std::streamsize>(chunk.size()));
    h = fnv1a64(std::string_view(chunk.data(), static_cast<size_t>(in.gcount())), h);
  }
  if (in.bad()) return make_error(ErrorCode::kFileUnreadable, path + ": read failed");
  return format_hash(h);
}

}  // namespace cagewrap
