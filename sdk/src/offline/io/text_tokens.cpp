// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The number parser of the text readers (text_tokens.h).
#include "offline/io/text_tokens.h"

#include <algorithm>
#include <charconv>
#include <limits>
#include <system_error>

namespace dermis::text {
namespace {

// Decimal exponent of the leading non-zero digit of a number std::from_chars has accepted as a
// whole ([-]digits[.digits][e[+-]digits]), e.g. 2 for "123.4", -3 for "0.00123e0"; the
// exponent field saturates, which is enough to tell an overflow (> 0) from an underflow.
long long LeadingExponent(std::string_view s) {
  std::size_t i = 0;
  if (i < s.size() && s[i] == '-') ++i;
  long long integer_digits = 0, leading_zeros = 0;
  bool point = false, nonzero = false;
  for (; i < s.size() && s[i] != 'e' && s[i] != 'E'; ++i) {
    if (s[i] == '.') {
      point = true;
    } else if (!nonzero && s[i] == '0') {
      if (point) ++leading_zeros;
    } else {
      nonzero = true;
      if (!point) ++integer_digits;
    }
  }
  long long exponent = 0;
  if (i < s.size()) {
    ++i;
    bool negative = false;
    if (i < s.size() && (s[i] == '-' || s[i] == '+')) negative = s[i++] == '-';
    for (; i < s.size(); ++i) exponent = std::min(exponent * 10 + (s[i] - '0'), 1000000000LL);
    if (negative) exponent = -exponent;
  }
  return exponent + (integer_digits > 0 ? integer_digits - 1 : -leading_zeros - 1);
}

}  // namespace

bool ParseDouble(std::string_view token, double* out) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  const char* end = token.data() + token.size();
  const auto res = std::from_chars(token.data(), end, *out);
  if (res.ptr != end) return false;
  if (res.ec == std::errc::result_out_of_range) {
    // libstdc++ rounds correctly and reports this only when the result is 0 or infinite.
    const bool negative = token.front() == '-';
    const double magnitude =
        LeadingExponent(token) > 0 ? std::numeric_limits<double>::infinity() : 0.0;
    *out = negative ? -magnitude : magnitude;
    return true;
  }
  return res.ec == std::errc();
}

bool ParseInt(std::string_view token, long long* out) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  const auto res = std::from_chars(token.data(), token.data() + token.size(), *out);
  return res.ec == std::errc() && res.ptr == token.data() + token.size();
}

}  // namespace dermis::text
