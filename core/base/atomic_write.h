// Replacing a file so that readers only ever see the old bytes or the complete new ones: write
// `path.tmp` beside it, flush and fsync, rename over `path`, fsync the folder. On any failure the
// temporary file is removed and `path` is untouched.
#pragma once

#include <string>
#include <string_view>

#include "core/base/result.h"

namespace cagewrap {

// Errors (kWrite) name `path` and the system's reason.
Status write_file_atomic(const std::string& path, std::string_view bytes);

}  // namespace cagewrap
