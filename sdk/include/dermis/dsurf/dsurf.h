// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief The native `.dsurf` file (docs/file-format.md): versions 1 and 3 hold a fitted
/// displaced surface (control mesh, chart settings, patch-fit operators and multilevel
/// displacement lattices: merged dense lattices in version 1, sparse per-level corrections in
/// version 3), version 2 a character (the source asset and one surface per fitted part, with
/// skin weights and vertex bindings; runtime/character.h). One magic, one checksum, and one
/// reader for every version: ParseCharacter() / ReadCharacter().
///
/// Runtime code: reading needs neither Eigen nor any plugin, and never throws.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "dermis/core/status.h"
#include "dermis/surface/bspline_displacement.h"
#include "dermis/surface/manifold_domain.h"

namespace dermis {

/// Version of .dsurf files that hold one displaced surface with merged dense displacement
/// lattices (BsplineLevelForm::kMerged).
constexpr std::uint32_t kDsurfVersion = 1;
/// Version of .dsurf files that hold a character.
constexpr std::uint32_t kCharacterDsurfVersion = 2;
/// Version of .dsurf files that hold one displaced surface with sparse per-level displacement
/// corrections (BsplineLevelForm::kAdditive).
constexpr std::uint32_t kSparseDsurfVersion = 3;
/// Version of .dsurf files that hold a runtime archive: a character packed for the runtime
/// (BuildRuntimeArchive(), offline/character/runtime_archive.h): the rig, compact control
/// meshes, operators, displacement lattices (optionally 16-bit), skin influences and vertex
/// bindings, the source asset only if asked.
constexpr std::uint32_t kRuntimeArchiveVersion = 4;
/// The newest version; readers accept 1 .. kLatestDsurfVersion.
constexpr std::uint32_t kLatestDsurfVersion = 4;

/// Whether a .dsurf version holds a plain surface (1, 3) rather than a character (2).
constexpr bool IsSurfaceDsurfVersion(std::uint32_t version) {
  return version == kDsurfVersion || version == kSparseDsurfVersion;
}

struct Character;  // runtime/character.h

/// How a runtime archive (version 4) is packed.
struct RuntimeArchiveOptions {
  /// Store each displacement coefficient as 16 bits: per chart and level an f32 offset and
  /// scale, then one u16 per coefficient (error at most half a step of that range).
  bool quantize_displacements = false;
  /// Keep the whole source asset (meshes, materials, images, clips) and the fit summaries, so
  /// that offline commands (export, animate, render) can use the archive; by default only the
  /// rig (joint names, parents, inverse bind matrices) and the primitives' vertex counts and
  /// triangle indices are kept.
  bool keep_source = false;
};

/// What the header of a runtime archive records: the error of the archive against the
/// character it was built from, as the builder measured it (0 if not measured), relative to
/// the diagonal of that character's level-8 rest output.
struct RuntimeArchiveError {
  double level8_max = 0.0, level8_mean = 0.0;  ///< Level-8 output, over the diagonal.
  double bound_max = 0.0;                      ///< Bound vertices, over the diagonal.
  double diagonal = 0.0;                       ///< Model units.
};

/// The byte layout of a .dsurf file, as its reader found it (for `dermis inspect`).
struct DsurfFileInfo {
  std::uint32_t version = 0;
  /// Bytes per section, in the order first met; each byte of the file is in exactly one
  /// section ("header" holds magics, versions, flags, counts and checksums).
  std::vector<std::pair<std::string, std::uint64_t>> sections;
  /// Version 4: how it was packed and the error its header records.
  RuntimeArchiveOptions archive;
  RuntimeArchiveError archive_error;
  /// Adds `bytes` to section `name`.
  void Add(const std::string& name, std::uint64_t bytes);
};

/// A displaced surface as loaded from (or saved to) a .dsurf file.
struct DisplacedSurface {
  std::unique_ptr<ManifoldDomain> domain;
  std::vector<Vec3> rest_positions;  ///< Control vertices, model units, one per domain vertex.
  std::unique_ptr<BsplineDisplacement> displacement;  ///< Null if the file has none.
  /// Data points the displacement was fitted to, for coefficients per point (version 3
  /// stores it; 0: unknown).
  std::int64_t data_points = 0;
};

/// Serialises a surface into .dsurf bytes (little-endian, versioned, with a checksum): version 3
/// when the displacement is additive (BsplineLevelForm::kAdditive), else version 1, so a
/// version-1 file read and written again gives the same bytes. The same surface always gives
/// the same bytes. `data_points` is stored by version 3 only.
std::string SerializeDsurf(const ManifoldDomain& domain, const Vec3* rest_positions,
                           const BsplineDisplacement* displacement, std::int64_t data_points = 0);

/// Parses the bytes of a version-1 or version-3 .dsurf (a version-2 file is an error: it is a
/// character).
/// Every count is checked against the bytes present before anything is allocated; errors name
/// `name` and the part of the file at fault.
Status ParseDsurf(std::string_view bytes, const std::string& name, DisplacedSurface* out);

/// Reads a version-1 or version-3 .dsurf file (kIoError naming the path if it cannot be read).
Status ReadDsurf(const std::string& path, DisplacedSurface* out);

/// Serialises a character as a version-2 .dsurf (deterministic bytes, FNV-1a checksum).
std::string SerializeCharacter(const Character& character);

/// The reader of every version: parses .dsurf bytes as a character. A surface (version 1 or 3)
/// becomes a character of one part with no asset meshes, no skins and no bindings (its
/// asset's source is `name`). `version`, if not null, receives the file's version. Errors name
/// `name` and the part of the file at fault (kUnsupported for a version this build does not
/// know).
/// A runtime archive (version 4) reads as the character it was packed from, less what it
/// left out (Character::source_stripped). `info`, if not null, receives the byte layout.
Status ParseCharacter(std::string_view bytes, const std::string& name, Character* out,
                      std::uint32_t* version = nullptr, DsurfFileInfo* info = nullptr);

/// Serialises a character as a version-4 runtime archive (docs/file-format.md, "Runtime
/// archives"): deterministic bytes; `error` is recorded in the header as given. The offline
/// builder (BuildRuntimeArchive) measures the error and calls this.
std::string SerializeRuntimeArchive(const Character& character,
                                    const RuntimeArchiveOptions& options,
                                    const RuntimeArchiveError& error = {});

/// Reads a .dsurf file of any version once and parses it as ParseCharacter() does; `bytes`,
/// if not null, receives the file's bytes.
Status ReadCharacter(const std::string& path, Character* out, std::uint32_t* version = nullptr,
                     std::string* bytes = nullptr);

/// The version field of .dsurf bytes, without checking the rest (0 if the bytes do not start
/// with the .dsurf magic).
std::uint32_t DsurfFileVersion(std::string_view bytes);

}  // namespace dermis
