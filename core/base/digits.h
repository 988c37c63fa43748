// Large counts in messages, grouped by thousands: "12,000,000,000 bytes".
#pragma once

#include <cstdint>
#include <string>

namespace cagewrap {

// Decimal digits of n grouped by commas. Takes 128 bits so that a size computed from a file's claims
// (count x stride, which may not fit 64 bits) can be printed as it is.
inline std::string group_digits(unsigned __int128 n) {
  std::string digits;
  do {
    digits.insert(digits.begin(), char('0' + int(n % 10)));
    n /= 10;
  } while (n > 0);
  for (int i = int(digits.size()) - 3; i > 0; i -= 3) digits.insert(size_t(i), ",");
  return digits;
}

}  // namespace cagewrap
