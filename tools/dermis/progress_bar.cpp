// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The terminal progress bar of the dermis tool (docs/cli.md, "Progress"). Hand-written: the
// Debian packages we may use (CLI11, the C library) have none, and it is one line of text.
#include "progress_bar.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace dermis::cli {

ProgressBar::ProgressBar(const char* command, bool quiet) : command_(command) {
  const char* force = std::getenv("DERMIS_PROGRESS");
  const bool forced = force != nullptr && std::strcmp(force, "1") == 0;
  enabled_ = !quiet && (forced || ::isatty(STDERR_FILENO) == 1);
  start_ = stage_start_ = count_start_ = std::chrono::steady_clock::now();
}

ProgressBar::~ProgressBar() { Clear(); }

void ProgressBar::Clear() {
  if (!enabled_ || !drawn_) return;
  std::fprintf(stderr, "\r\033[K");
  std::fflush(stderr);
  drawn_ = false;
}

void ProgressBar::Update(const char* stage, std::size_t done, std::size_t total) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  // The time left comes from the rate since the count began: a count is one total, counted
  // up (the stage may change along it, as a fit's stages share one count of its work).
  if (total != total_ || done < done_) count_start_ = now;
  total_ = total;
  done_ = done;
  if (stage_ != stage) {
    stage_ = stage;
    stage_start_ = now;
  } else if (done < total && now - last_ < std::chrono::milliseconds(100)) {
    return;
  }
  last_ = now;
  const double elapsed =
      std::chrono::duration<double>(now - (total == 0 ? stage_start_ : count_start_)).count();
  char line[160];
  if (total == 0) {
    std::snprintf(line, sizeof line, "dermis %s: %s (%.0f s)", command_, stage, elapsed);
  } else {
    constexpr int kWidth = 24;
    const double f = static_cast<double>(std::min(done, total)) / static_cast<double>(total);
    char bar[kWidth + 1];
    const int filled = static_cast<int>(f * kWidth);
    for (int i = 0; i < kWidth; ++i) bar[i] = i < filled ? '#' : '-';
    bar[kWidth] = '\0';
    char left[32] = "";
    if (done > 0 && done < total) {
      std::snprintf(left, sizeof left, ", %.0f s left", elapsed * (1.0 - f) / f);
    }
    std::snprintf(line, sizeof line, "dermis %s: [%s] %3.0f%% %s %zu/%zu%s", command_, bar,
                  100.0 * f, stage, done, total, left);
  }
  std::fprintf(stderr, "\r\033[K%s", line);
  std::fflush(stderr);
  drawn_ = true;
}

ProgressCallback ProgressBar::Callback() {
  if (!enabled_) return {};
  return [this](const char* stage, std::size_t done, std::size_t total) {
    Update(stage, done, total);
  };
}

}  // namespace dermis::cli
