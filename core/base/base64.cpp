#include "core/base/base64.h"

#include <array>
#include <cstdint>

namespace cagewrap {

namespace {

constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

// 0..63 for the alphabet, -1 otherwise
constexpr std::array<int8_t, 256> decode_table() {
  std::array<int8_t, 256> t{};
  for (auto& v : t) v = -1;
  for (int i = 0; i < 64; ++i) t[static_cast<uint8_t>(kAlphabet[i])] = static_cast<int8_t>(i);
  return t;
}
constexpr auto kDecode = decode_table();

}  // namespace

std::string base64_encode(std::string_view bytes) {
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 3 <= bytes.size(); i += 3) {
    const uint32_t v = static_cast<uint8_t>(bytes[i]) << 16 | static_cast<uint8_t>(bytes[i + 1]) << 8 |
                       static_cast<uint8_t>(bytes[i + 2]);
    out += kAlphabet[v >> 18];
    out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63];
    out += kAlphabet[v & 63];
  }
  const size_t rest = bytes.size() - i;
  if (rest > 0) {
    uint32_t v = static_cast<uint8_t>(bytes[i]) << 16;
    if (rest == 2) v |= static_cast<uint8_t>(bytes[i + 1]) << 8;
    out += kAlphabet[v >> 18];
    out += kAlphabet[(v >> 12) & 63];
    out += rest == 2 ? kAlphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

Result<std::string> base64_decode(std::string_view text, const std::string& what) {
  if (text.size() % 4 != 0)
    return make_error(ErrorCode::kParse, what + " is not base64: its length " + std::to_string(text.size()) +
                                             " is not a multiple of 4 (cut short?)");
  size_t padding = 0;
  if (!text.empty() && text.back() == '=') padding = text[text.size() - 2] == '=' ? 2 : 1;
  std::string out;
  out.reserve(text.size() / 4 * 3);
  for (size_t i = 0; i < text.size(); i += 4) {
    uint32_t v = 0;
    for (size_t k = 0; k < 4; ++k) {
      const size_t at = i + k;
      const bool pad = at >= text.size() - padding;
      const int8_t d = kDecode[static_cast<uint8_t>(text[at])];
      if (pad ? text[at] != '=' : d < 0)
        return make_error(ErrorCode::kParse, what + " is not base64: character " + std::to_string(at) + " is '" +
                                                 std::string(1, text[at]) + "'");
      v = v << 6 | static_cast<uint32_t>(pad ? 0 : d);
    }
    out += static_cast<char>(v >> 16);
    if (i + 4 < text.size() || padding < 2) out += static_cast<char>((v >> 8) & 255);
    if (i + 4 < text.size() || padding < 1) out += static_cast<char>(v & 255);
  }
  return out;
}

}  // namespace cagewrap
