// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief The runtime archive builder (docs/engine-integration.md, "Runtime archives"): turns
/// a fitted character (a version-2 .dsurf, the offline "raw" object) into a compact, versioned,
/// immutable runtime archive (a version-4 .dsurf, docs/file-format.md), the way
/// ozz-animation's offline builders turn raw skeletons and animations into runtime ones: the
/// rig instead of the source asset, f32 instead of f64, 16-bit indices where counts allow, and
/// optionally 16-bit displacement coefficients; then measures what packing cost.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "dermis/core/status.h"
#include "dermis/dsurf/dsurf.h"
#include "dermis/runtime/character.h"

namespace dermis {

/// What BuildRuntimeArchive() measured.
struct RuntimeArchiveReport {
  std::uint64_t bytes = 0;  ///< Of the archive.
  /// The archive's surface against the character's, both through the same evaluator, at the
  /// rest pose: the level-8 tessellation of every part and every bound vertex, relative to the
  /// diagonal of the character's level-8 output (recorded in the archive's header).
  RuntimeArchiveError error;
  std::uint64_t level8_samples = 0;  ///< Samples compared at level 8 (all parts).
  std::uint64_t bound_vertices = 0;  ///< Bound vertices compared.
  /// Bytes per section of the archive, as its reader found them (DsurfFileInfo::sections).
  std::vector<std::pair<std::string, std::uint64_t>> sections;
};

/// Packs `character` into runtime-archive bytes (*out), reads them back with the runtime's
/// reader and measures the error against `character` (*report, may be null; also written into
/// the archive's header). Fails if the character is inconsistent, or if keep_source is asked
/// of a character that was itself read from an archive without its source. `threads` (0: all
/// cores) splits the measurement; the bytes do not depend on it.
Status BuildRuntimeArchive(const Character& character, const RuntimeArchiveOptions& options,
                           int threads, std::string* out, RuntimeArchiveReport* report);

}  // namespace dermis
