// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief The native `.dsurf` file: a fitted displaced surface (control mesh, chart settings,
/// patch-fit operators and multilevel displacement lattices). Layout: docs/file-format.md.
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

/// Current .dsurf format version. Readers accept versions 1 .. kDsurfVersion.
constexpr std::uint32_t kDsurfVersion = 1;

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

/// Parses .dsurf bytes. Every count is checked against the bytes present before anything is
/// allocated; errors name `name` and the part of the file at fault.
Status ParseDsurf(std::string_view bytes, const std::string& name, DisplacedSurface* out);

/// Reads a .dsurf file (kIoError naming the path if it cannot be read).
Status ReadDsurf(const std::string& path, DisplacedSurface* out);

}  // namespace dermis
