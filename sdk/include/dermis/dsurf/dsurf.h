// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief The native `.dsurf` file (docs/file-format.md): version 1 holds a fitted displaced
/// surface (control mesh, chart settings, patch-fit operators and multilevel displacement
/// lattices), version 2 a character (the source asset and one version-1 surface per fitted
/// part, with skin weights and vertex bindings; runtime/character.h). One magic, one
/// checksum, and one reader for every version: ParseCharacter() / ReadCharacter().
///
/// Runtime code: reading needs neither Eigen nor any plugin, and never throws.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "dermis/core/status.h"
#include "dermis/surface/bspline_displacement.h"
#include "dermis/surface/manifold_domain.h"

namespace dermis {

/// Version of .dsurf files that hold one displaced surface.
constexpr std::uint32_t kDsurfVersion = 1;
/// Version of .dsurf files that hold a character. Readers accept 1 .. kCharacterDsurfVersion.
constexpr std::uint32_t kCharacterDsurfVersion = 2;

struct Character;  // runtime/character.h

/// A displaced surface as loaded from (or saved to) a .dsurf file.
struct DisplacedSurface {
  std::unique_ptr<ManifoldDomain> domain;
  std::vector<Vec3> rest_positions;  ///< Control vertices, model units, one per domain vertex.
  std::unique_ptr<BsplineDisplacement> displacement;  ///< Null if the file has none.
};

/// Serialises a surface into .dsurf bytes (little-endian, versioned, with a checksum). The same
/// surface always gives the same bytes.
std::string SerializeDsurf(const ManifoldDomain& domain, const Vec3* rest_positions,
                           const BsplineDisplacement* displacement);

/// Parses the bytes of a version-1 .dsurf (a version-2 file is an error: it is a character).
/// Every count is checked against the bytes present before anything is allocated; errors name
/// `name` and the part of the file at fault.
Status ParseDsurf(std::string_view bytes, const std::string& name, DisplacedSurface* out);

/// Reads a version-1 .dsurf file (kIoError naming the path if it cannot be read).
Status ReadDsurf(const std::string& path, DisplacedSurface* out);

/// Serialises a character as a version-2 .dsurf (deterministic bytes, FNV-1a checksum).
std::string SerializeCharacter(const Character& character);

/// The reader of every version: parses .dsurf bytes as a character. A version-1 surface
/// becomes a character of one part with no asset meshes, no skins and no bindings (its
/// asset's source is `name`). `version`, if not null, receives the file's version. Errors name
/// `name` and the part of the file at fault (kUnsupported for a version this build does not
/// know).
Status ParseCharacter(std::string_view bytes, const std::string& name, Character* out,
                      std::uint32_t* version = nullptr);

/// Reads a .dsurf file of any version once and parses it as ParseCharacter() does; `bytes`,
/// if not null, receives the file's bytes.
Status ReadCharacter(const std::string& path, Character* out, std::uint32_t* version = nullptr,
                     std::string* bytes = nullptr);

/// The version field of .dsurf bytes, without checking the rest (0 if the bytes do not start
/// with the .dsurf magic).
std::uint32_t DsurfFileVersion(std::string_view bytes);

}  // namespace dermis
