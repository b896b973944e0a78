// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Whole-file input and atomic file output, with errors that name the path.
#pragma once

#include <string>
#include <string_view>

#include "dermis/core/status.h"

namespace dermis {

/// Reads the file at `path` into *bytes (binary). On failure returns kIoError naming the path:
/// "PATH: is a directory, not KIND", "PATH: cannot open for reading: REASON" or
/// "PATH: read error". `kind` describes the expected file, e.g. "an OBJ file".
Status ReadFileBytes(const std::string& path, const std::string& kind, std::string* bytes);

/// Writes `bytes` to `path` through a temporary file in the same directory (PATH.tmp.XXXXXXXX,
/// flushed to disk) and renames it into place, so a reader never sees a half-written file and
/// an existing `path` stays untouched until the rename. The file gets the permissions of any
/// new file (0666 less the process umask; the umask is never changed). On failure returns
/// kIoError "PATH: REASON" and nothing is left behind. Safe to call from several threads.
Status WriteFileAtomically(const std::string& path, std::string_view bytes);

}  // namespace dermis
