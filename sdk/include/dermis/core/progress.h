// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief The progress callback of the library's long operations (offline only: fit, bake,
/// export, render); the command-line tool draws it as a bar on a terminal (docs/cli.md).
#pragma once

#include <cstddef>
#include <functional>

namespace dermis {

/// Reports that `done` of `total` units of the stage `stage` (a short phrase, e.g. "baking
/// frames"; valid during the call only) are finished; total 0 means unknown. Called on the
/// thread that called the operation, at most once per unit, never from per-frame runtime code.
/// An empty function is never called.
using ProgressCallback =
    std::function<void(const char* stage, std::size_t done, std::size_t total)>;

/// Calls `progress` if it is set.
inline void ReportProgress(const ProgressCallback& progress, const char* stage, std::size_t done,
                           std::size_t total) {
  if (progress) progress(stage, done, total);
}

}  // namespace dermis
