// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The one whole-file read and the one atomic write (dermis/core/file_io.h).
#include "dermis/core/file_io.h"

#include <sys/stat.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "support/temp_files.h"

using namespace dermis;
namespace fs = std::filesystem;

namespace {

int Entries(const fs::path& dir) {
  int n = 0;
  for (const auto& e : fs::directory_iterator(dir)) n += e.exists() ? 1 : 0;
  return n;
}

mode_t Permissions(const std::string& path) {
  struct stat st {};
  REQUIRE(::stat(path.c_str(), &st) == 0);
  return st.st_mode & 0777;
}

}  // namespace

TEST_CASE("file io: atomic write creates, replaces and leaves no temporary file") {
  test::TempDir dir("dermis_file_io");
  const std::string path = dir.File("out.bin");
  std::string bytes("a\0b\r\n", 5);
  REQUIRE(WriteFileAtomically(path, bytes).ok());
  CHECK(test::ReadFile(path) == bytes);
  REQUIRE(WriteFileAtomically(path, "second").ok());
  CHECK(test::ReadFile(path) == "second");
  REQUIRE(WriteFileAtomically(path, "").ok());
  CHECK(test::ReadFile(path).empty());
  CHECK(Entries(dir.path()) == 1);
}

TEST_CASE("file io: a new file gets 0666 less the umask, and the umask is left alone") {
  test::TempDir dir("dermis_file_io");
  const mode_t old = ::umask(027);
  const Status s = WriteFileAtomically(dir.File("a.txt"), "x");
  const mode_t during = ::umask(002);
  const Status t = WriteFileAtomically(dir.File("b.txt"), "y");
  ::umask(old);
  REQUIRE(s.ok());
  REQUIRE(t.ok());
  CHECK(during == 027);  // the write did not change the process umask
  CHECK(Permissions(dir.File("a.txt")) == 0640);
  CHECK(Permissions(dir.File("b.txt")) == 0664);
}

TEST_CASE("file io: a failed write names the file, keeps the old one and leaves nothing") {
  test::TempDir dir("dermis_file_io");
  Status s = WriteFileAtomically(dir.File("missing/x.obj"), "data");
  CHECK(s.code() == StatusCode::kIoError);
  CHECK_THAT(s.message(), Catch::StartsWith(dir.File("missing/x.obj") + ": "));
  CHECK_FALSE(fs::exists(dir.path() / "missing"));
  // A folder in the way of the rename: the temporary file is removed, the folder kept.
  fs::create_directories(dir.path() / "taken");
  fs::create_directories(dir.path() / "taken" / "inside");
  s = WriteFileAtomically(dir.File("taken"), "data");
  CHECK(s.code() == StatusCode::kIoError);
  CHECK_THAT(s.message(), Catch::Contains("taken"));
  CHECK(fs::is_directory(dir.path() / "taken"));
  CHECK(Entries(dir.path()) == 1);
  CHECK(WriteFileAtomically("", "data").code() == StatusCode::kIoError);
}

TEST_CASE("file io: threads writing beside each other never collide") {
  test::TempDir dir("dermis_file_io");
  constexpr int kThreads = 8, kWrites = 25;
  std::vector<std::thread> threads;
  std::vector<int> failures(kThreads, 0);
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] {
      for (int i = 0; i < kWrites; ++i) {
        // All threads replace one shared file and write one of their own.
        const std::string mine = dir.File("t" + std::to_string(t) + ".txt");
        if (!WriteFileAtomically(dir.File("shared.txt"), std::string(1000, char('a' + t))).ok())
          ++failures[static_cast<std::size_t>(t)];
        if (!WriteFileAtomically(mine, std::to_string(i)).ok())
          ++failures[static_cast<std::size_t>(t)];
      }
    });
  }
  for (std::thread& t : threads) t.join();
  for (int f : failures) CHECK(f == 0);
  CHECK(Entries(dir.path()) == kThreads + 1);
  const std::string shared = test::ReadFile(dir.File("shared.txt"));
  REQUIRE(shared.size() == 1000);
  CHECK(shared == std::string(1000, shared[0]));  // one writer's bytes, never a mix
  for (int t = 0; t < kThreads; ++t) {
    CHECK(test::ReadFile(dir.File("t" + std::to_string(t) + ".txt")) ==
          std::to_string(kWrites - 1));
  }
}

TEST_CASE("file io: whole-file read and its errors") {
  test::TempDir dir("dermis_file_io");
  const std::string bytes("\x00\xff\n\r\x1a", 5);
  test::WriteFile(dir.File("in.bin"), bytes);
  std::string read;
  REQUIRE(ReadFileBytes(dir.File("in.bin"), "a test file", &read).ok());
  CHECK(read == bytes);
  Status s = ReadFileBytes(dir.File("none.bin"), "a test file", &read);
  CHECK(s.code() == StatusCode::kIoError);
  CHECK_THAT(s.message(), Catch::StartsWith(dir.File("none.bin") + ": cannot open for reading"));
  s = ReadFileBytes(dir.path().string(), "a test file", &read);
  CHECK(s.code() == StatusCode::kIoError);
  CHECK(s.message() == dir.path().string() + ": is a directory, not a test file");
}

TEST_CASE("file io: a device or a pipe is refused, not read until memory runs out") {
  // Issue 19, finding 13: /dev/zero as an input was read without end.
  std::string read = "unchanged";
  Status s = ReadFileBytes("/dev/zero", "an OBJ file", &read);
  CHECK(s.code() == StatusCode::kIoError);
  CHECK(s.message() ==
        "/dev/zero: is not a regular file (a device, pipe or socket), not an OBJ file");
  CHECK(read == "unchanged");
  test::TempDir dir;
  const std::string fifo = dir.File("pipe.obj");
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  s = ReadFileBytes(fifo, "an OBJ file", &read);  // opening it would block: never opened
  CHECK(s.message().find("is not a regular file") != std::string::npos);
}
