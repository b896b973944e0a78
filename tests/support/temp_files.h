// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Test support: temporary folders and whole files (std and Catch2 only, so that every test
// binary may use it). Uses Catch2 assertions: call it from inside a TEST_CASE.
#pragma once

#include <filesystem>
#include <string>

namespace dermis::test {

/// A fresh folder under the system temp directory, removed with everything in it on scope exit.
class TempDir {
 public:
  explicit TempDir(const std::string& prefix = "dermis_test");
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  std::string File(const std::string& name) const { return (path_ / name).string(); }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

/// Whole file as bytes (REQUIREs that it opens).
std::string ReadFile(const std::string& path);
/// Writes `bytes` to `path` (REQUIREs success).
void WriteFile(const std::string& path, const std::string& bytes);

}  // namespace dermis::test
