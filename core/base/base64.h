// Base64 (RFC 4648, standard alphabet, '=' padding), for file bytes kept inside JSON (a project's
// embedded character, docs/project-format.md).
#pragma once

#include <string>
#include <string_view>

#include "core/base/result.h"

namespace cagewrap {

std::string base64_encode(std::string_view bytes);
// Strict: only the standard alphabet, padded to a multiple of 4 characters, '=' only at the end.
// Errors (kParse) say what is wrong and at which character; `what` names the text in them.
Result<std::string> base64_decode(std::string_view text, const std::string& what);

}  // namespace cagewrap
