// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Triangles paired into quads by a maximum weight matching on quad quality
/// (Blossom-Quad, Remacle et al. 2012; docs/fitting.md, "Control mesh").
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "dermis/core/status.h"
#include "dermis/core/types.h"
#include "dermis/offline/geometry/polygon_mesh.h"

namespace dermis {

/// Options of PairTrianglesIntoQuads().
struct QuadPairingOptions {
  /// Weight of a pair = pair_bonus + quality (quality in [0, 1]). A positive bonus prefers more
  /// quads to better ones: two triangles are left unpaired only if that raises the others'
  /// quality by more than the bonus in total.
  double pair_bonus = 0.5;
  /// Pairs whose quad has a quality below this are never formed.
  double min_quality = 0.0;
};

/// What PairTrianglesIntoQuads() did.
struct QuadPairingStats {
  int quads = 0;            ///< Pairs formed.
  int triangles = 0;        ///< Triangles left unpaired.
  double mean_quality = 0;  ///< Mean quality of the quads formed.
};

/// Quality of the quad (a, b, c, d) (counter-clockwise): 1 - (2 / pi) max |pi/2 - corner
/// angle|, at least 0 (Remacle et al. 2012, Eq. 1); 0 when it is not convex, that is when its
/// two triangulations disagree in orientation.
double QuadQuality(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// Pairs the triangles (counter-clockwise, manifold) across their shared edges into quads by a
/// maximum weight matching of the dual graph (LEMON's MaxWeightedMatching, Edmonds' blossom
/// algorithm, integer weights so the result is exact and deterministic). `out` receives the
/// same positions, one quad per pair (in the order of its lower triangle) and every unpaired
/// triangle, with its orientation. `keep_edges` (optional; (a, b) with a < b, sorted): edges
/// that stay edges (creases), never the diagonal of a pair. Fails on malformed input.
Status PairTrianglesIntoQuads(
    const std::vector<Vec3>& positions, const std::vector<std::uint32_t>& triangles,
    const QuadPairingOptions& options, PolygonMesh* out, QuadPairingStats* stats = nullptr,
    const std::vector<std::array<std::uint32_t, 2>>* keep_edges = nullptr);

}  // namespace dermis
