// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Adaptive isotropic triangle remeshing onto a reference surface (Botsch & Kobbelt
/// 2004): edge splits, collapses and flips, tangential relaxation and back-projection
/// (docs/fitting.md, "Control mesh").
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "dermis/core/status.h"
#include "dermis/core/types.h"
#include "dermis/offline/build/crease_chains.h"
#include "dermis/offline/build/reference_surface.h"
#include "dermis/offline/build/sizing_field.h"

namespace dermis {

/// A triangle mesh being remeshed: positions (model units), counter-clockwise triangles, and
/// for each vertex the reference boundary loop it lies on (-1 inside). Manifold and
/// consistently oriented. With creases (crease_chains.h): each vertex's feature tag (empty: none)
/// and the crease edges (a, b, chain), a < b.
struct RemeshTriangles {
  std::vector<Vec3> positions;
  std::vector<std::uint32_t> triangles;
  std::vector<int> loop;
  std::vector<int> feature;
  std::vector<std::array<std::uint32_t, 3>> crease_edges;
};

/// Options of RemeshIsotropic().
struct IsotropicRemeshOptions {
  int iterations = 8;  ///< Rounds of split, collapse, flip, relax.
  /// Edges longer than split_ratio x size are split, shorter than collapse_ratio x size are
  /// collapsed (Botsch & Kobbelt's 4/3 and 4/5).
  double split_ratio = 4.0 / 3.0;
  double collapse_ratio = 4.0 / 5.0;
  /// A collapse or relaxation step may turn a triangle's normal by at most this (degrees).
  double max_normal_change_deg = 60.0;
  /// A collapse must leave both old positions within this fraction of the local size from the
  /// new triangles, and a flip must keep the old edge's midpoint as close to the new pair.
  double max_collapse_error = 0.3;
  /// A relaxation step must leave the vertex's old position within this fraction of the local
  /// size from its new triangles (a tip or a ridge does not creep away).
  double max_relax_error = 0.05;
  /// A collapse may not make a triangle with a smaller angle (degrees), unless one was there.
  double min_angle_deg = 10.0;
  /// A crease edge may cut its chain by at most this fraction of the local size (chord
  /// deviation, CreaseChains::ChordDeviation()): longer ones are split, collapses that would
  /// exceed it are refused, so a curved crease (a cap's rim) keeps a polygon close to it.
  double crease_chord_error = 0.12;
};

/// What RemeshIsotropic() did.
struct IsotropicRemeshStats {
  int splits = 0, collapses = 0, flips = 0;
  int rejected_moves = 0;  ///< Relaxation steps undone because a triangle would turn over.
};

/// Remeshes `mesh` in place so that its edges follow `sizing` (split above split_ratio, collapse
/// below collapse_ratio of the local size), valences approach 6 inside and 4 on the boundary by
/// flips, and vertices spread evenly (tangential area-weighted relaxation); every moved or new
/// vertex is projected back onto `reference` (boundary vertices onto their own loop). The mesh
/// stays manifold, keeps its boundary loops (each with at least 3 vertices) and its components
/// (each closed one with at least 4 vertices). With `creases` (not owned, the chains of
/// `reference`) and a tagged mesh, crease edges are kept like boundaries: split and collapsed
/// only along their chain, their vertices relaxed along it, corners fixed, never flipped.
/// Deterministic.
Status RemeshIsotropic(const ReferenceSurface& reference, const SizingField& sizing,
                       const IsotropicRemeshOptions& options, RemeshTriangles* mesh,
                       IsotropicRemeshStats* stats = nullptr,
                       const CreaseChains* creases = nullptr);

/// Changes the vertex count of `mesh` by about `delta` (positive: split the edges longest
/// relative to their size; negative: collapse the shortest), one operation at a time with the
/// same checks and projections as RemeshIsotropic(), then relaxes twice. Returns the change
/// achieved.
int AdjustVertexCount(const ReferenceSurface& reference, const SizingField& sizing, int delta,
                      const IsotropicRemeshOptions& options, RemeshTriangles* mesh,
                      const CreaseChains* creases = nullptr);

}  // namespace dermis
