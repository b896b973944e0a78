// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Progress of a long subcommand on stderr (docs/cli.md, "Progress"): a bar, the stage, the
// count and the time left, redrawn in place, only when stderr is a terminal and -q is not
// given; nothing at all otherwise (logs and pipes stay clean).
#pragma once

#include <chrono>
#include <cstddef>
#include <string>

#include "dermis/core/progress.h"

namespace dermis::cli {

class ProgressBar {
 public:
  /// `command` names the subcommand in the line; `quiet`: -q was given.
  ProgressBar(const char* command, bool quiet);
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  /// True if it draws (stderr is a TTY, not quiet; DERMIS_PROGRESS=1 forces it on for tests).
  bool enabled() const { return enabled_; }
  /// Draws `done` of `total` of `stage` (total 0: the stage and the time so far), at most
  /// 10 times a second (and always when the stage changes). The time left is the rate since
  /// the count began (a new total, or a smaller done) applied to what is left, so a count
  /// that spans stages (a fit's work) gives one estimate.
  void Update(const char* stage, std::size_t done, std::size_t total);
  /// Erases the line (before other output, and at the end).
  void Clear();
  /// A ProgressCallback that calls Update (empty when not enabled, so that the library does
  /// no work for it).
  ProgressCallback Callback();

 private:
  const char* command_;
  bool enabled_ = false;
  bool drawn_ = false;
  std::string stage_;
  std::size_t total_ = 0, done_ = 0;
  std::chrono::steady_clock::time_point start_, stage_start_, count_start_, last_;
};

}  // namespace dermis::cli
