// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Reading a whole file into memory, with errors that name the path.
#pragma once

#include <string>

#include "dermis/core/status.h"

namespace dermis {

/// Reads the file at `path` into *bytes (binary). On failure returns kIoError naming the path:
/// "PATH: is a directory, not KIND", "PATH: cannot open for reading: REASON" or
/// "PATH: read error". `kind` describes the expected file, e.g. "an OBJ file".
Status ReadFileBytes(const std::string& path, const std::string& kind, std::string* bytes);

}  // namespace dermis
