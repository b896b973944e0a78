// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// File-name helpers (dermis/core/path.h).
#include "dermis/core/path.h"

namespace dermis {

std::string AsciiLower(std::string_view text) {
  std::string out(text);
  for (char& c : out) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  return out;
}

std::string LowerExtension(std::string_view path) {
  const std::size_t slash = path.find_last_of("/\\");
  const std::size_t dot = path.find_last_of('.');
  if (dot == std::string_view::npos || (slash != std::string_view::npos && dot < slash)) return {};
  return AsciiLower(path.substr(dot));
}

}  // namespace dermis
