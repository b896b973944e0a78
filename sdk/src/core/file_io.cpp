// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The one whole-file read and the one atomic write of the SDK, its plugins and its tools.
#include "dermis/core/file_io.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "dermis/core/hash.h"
#include "dermis/core/limits.h"

namespace dermis {
namespace {

// A new file beside `path`, named PATH.tmp.XXXXXXXX, created exclusively (O_EXCL) with mode
// 0666, which the kernel reduces by the process umask: the file gets the permissions any
// newly created file would get, and the umask is never read or changed (umask(2) is
// process-wide, so changing it races with every other thread). mkstemp(3) is not used because
// it creates 0600 files whose permissions would then have to be widened by hand.
int CreateTemporary(const std::string& path, std::string* name) {
  static std::atomic<std::uint64_t> counter{0};
  const auto now =
      static_cast<std::uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count());
  static const char kDigits[] = "0123456789abcdefghijklmnopqrstuvwxyz";
  for (int attempt = 0; attempt < 100; ++attempt) {
    std::uint64_t bits = SplitMix64(now ^ (static_cast<std::uint64_t>(::getpid()) << 32) ^
                                    SplitMix64(counter.fetch_add(1, std::memory_order_relaxed)));
    std::string suffix(8, '0');
    for (char& c : suffix) {
      c = kDigits[bits % 36];
      bits /= 36;
    }
    *name = path + ".tmp." + suffix;
    const int fd = ::open(name->c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0 || errno != EEXIST) return fd;
  }
  errno = EEXIST;
  return -1;
}

}  // namespace

Status ReadFileBytes(const std::string& path, const std::string& kind, std::string* bytes) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    return Status::IoError(path + ": is a directory, not " + kind);
  }
  // Only regular files: a device (/dev/zero), FIFO or socket would be read until memory ends.
  const auto st = std::filesystem::status(path, ec);
  if (!ec && std::filesystem::exists(st) && !std::filesystem::is_regular_file(st)) {
    return Status::IoError(path + ": is not a regular file (a device, pipe or socket), not " +
                           kind);
  }
  if (!ec && std::filesystem::is_regular_file(st)) {
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    if (!ec && size > limits::kMaxInputFileBytes) {
      return Status::Unsupported(path + ": " + std::to_string(size) + " bytes, larger than the " +
                                 std::to_string(limits::kMaxInputFileBytes) +
                                 "-byte limit on one input file");
    }
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) return Status::IoError(path + ": cannot open for reading: " + std::strerror(errno));
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) return Status::IoError(path + ": read error");
  *bytes = std::move(ss).str();
  return Status::Ok();
}

Status WriteFileAtomically(const std::string& path, std::string_view bytes) {
  if (path.empty()) return Status::IoError("empty output path");
  std::string tmp;
  const int fd = CreateTemporary(path, &tmp);
  if (fd < 0) {
    return Status::IoError(path +
                           ": cannot create a temporary file beside it: " + std::strerror(errno));
  }
  // Closes and removes the temporary file; the message names the target and errno's reason.
  const auto fail = [&](const char* what, bool close_fd) {
    const std::string reason = std::strerror(errno);
    if (close_fd) ::close(fd);
    std::remove(tmp.c_str());
    return Status::IoError(path + ": " + what + ": " + reason);
  };
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      return fail("cannot write", true);
    }
    done += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) return fail("cannot write", true);
  if (::close(fd) != 0) return fail("cannot write", false);
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    return fail("cannot move the output into place", false);
  }
  return Status::Ok();
}

}  // namespace dermis
