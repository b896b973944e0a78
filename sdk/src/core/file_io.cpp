// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Whole-file reads shared by the OBJ, PLY and .dsurf readers.
#include "dermis/core/file_io.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace dermis {

Status ReadFileBytes(const std::string& path, const std::string& kind, std::string* bytes) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    return Status::IoError(path + ": is a directory, not " + kind);
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) return Status::IoError(path + ": cannot open for reading: " + std::strerror(errno));
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) return Status::IoError(path + ": read error");
  *bytes = std::move(ss).str();
  return Status::Ok();
}

}  // namespace dermis
