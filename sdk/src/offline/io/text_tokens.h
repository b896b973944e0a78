// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Whitespace tokenising shared by the text readers (OBJ, ASCII PLY). Internal header.
#pragma once

#include <cstddef>
#include <string_view>
#include <vector>

namespace dermis::text {

inline bool IsSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

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

}  // namespace dermis::text
