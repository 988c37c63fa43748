// Content hashes of files (64-bit FNV-1a over the bytes), written "fnv1a64:<16 lowercase hex digits>".
// A project remembers its character file's hash to notice when the file changed under it; this is a
// change detector, not a cryptographic digest.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "core/base/result.h"

namespace cagewrap {

inline constexpr uint64_t kFnv1a64Offset = 0xcbf29ce484222325ull;
inline constexpr uint64_t kFnv1a64Prime = 0x100000001b3ull;

// Continues the hash `h` over `bytes` (start with kFnv1a64Offset).
uint64_t fnv1a64(std::string_view bytes, uint64_t h = kFnv1a64Offset);
// "fnv1a64:00000000deadbeef"
std::string format_hash(uint64_t h);
// The formatted hash of a file's bytes; errors name the file.
Result<std::string> hash_file(const std::string& path);

}  // namespace cagewrap
