// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Atomic file output: write to a temporary file beside the target, then rename.
#pragma once

#include <string>
#include <string_view>

#include "dermis/core/status.h"

namespace dermis {

/// Writes `bytes` to `path` through a temporary file in the same directory and renames it into
/// place, so a reader never sees a half-written file. On failure nothing is left behind.
Status WriteFileAtomically(const std::string& path, std::string_view bytes);

}  // namespace dermis
