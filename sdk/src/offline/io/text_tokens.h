// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Tokens and numbers of the text readers (OBJ, ASCII PLY): one tokeniser and one number
// parser, so that every text format reads the same token as the same value. Internal header.
#pragma once

#include <cstddef>
#include <string_view>
#include <vector>

namespace dermis::text {

inline bool IsSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

/// `s` without trailing whitespace.
inline std::string_view TrimRight(std::string_view s) {
  while (!s.empty() && IsSpace(s.back())) s.remove_suffix(1);
  return s;
}

/// Splits a line into whitespace-separated tokens (views into `line`).
inline void Tokenize(std::string_view line, std::vector<std::string_view>* tokens) {
  tokens->clear();
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && IsSpace(line[i])) ++i;
    std::size_t j = i;
    while (j < line.size() && !IsSpace(line[j])) ++j;
    if (j > i) tokens->push_back(line.substr(i, j - i));
    i = j;
  }
}

/// Reads the whole token as a decimal floating-point number (an optional sign, '+' included,
/// digits with an optional point and exponent; "inf" and "nan" as std::from_chars reads them),
/// locale-independently and correctly rounded. A magnitude beyond the doubles reads as the
/// IEEE result of rounding: +-infinity above DBL_MAX, +-0 below half the smallest subnormal
/// (as strtod gives, so "1e-400" is 0, not infinity). False if the token is not a number.
bool ParseDouble(std::string_view token, double* out);

/// Reads the whole token as a decimal integer (an optional sign, '+' included); false if it
/// is not one or does not fit.
bool ParseInt(std::string_view token, long long* out);

}  // namespace dermis::text
