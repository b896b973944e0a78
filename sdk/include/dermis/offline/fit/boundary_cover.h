// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Moves the boundary control vertices out along the surface, one pass, towards a
/// domain surface whose boundary curve covers the data's boundary (a scan's hole rims): a
/// displacement along the normal cannot extend a surface, so a data point beyond the boundary
/// curve stays as far from the surface as it is from the curve (docs/fitting.md, "Covering the
/// data's boundary").
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "dermis/core/types.h"

namespace dermis {

class ManifoldDomain;
struct PolygonMesh;

/// The boundary edges of a polygon mesh: every directed edge (a, b) of a face that no other face
/// repeats and whose reverse (b, a) no face has, as position pairs in face order. Empty for a
/// closed mesh. Edges with an out-of-range index or equal ends are skipped. If `first` is not
/// null it receives each edge's first vertex index a (same order).
std::vector<std::pair<Vec3, Vec3>> BoundaryEdges(const PolygonMesh& mesh,
                                                 std::vector<Index>* first = nullptr);

/// Options of CoverDataBoundary().
struct BoundaryCoverOptions {
  /// A data boundary vertex counts only if its closest point on the boundary curve lies within
  /// this multiple of that boundary edge's chord (farther: another hole, or data the control
  /// mesh does not follow).
  double max_distance_edges = 1.0;
  /// A vertex moves at most this multiple of the mean length of its two boundary edges.
  double max_move_edges = 0.5;
  /// Excesses at or below this (model units) are ignored.
  double tolerance = 0.0;
  int threads = 0;  ///< 0: hardware concurrency. Results do not depend on it.
};

/// What CoverDataBoundary() did. The excesses are measured before the move.
struct BoundaryCoverReport {
  /// Data boundary edges whose first end lies beyond the curve (a vertex where the data's
  /// boundary touches itself counts once per edge leaving it).
  std::int64_t data_vertices_beyond = 0;
  double largest_excess = 0.0;      ///< Farthest of them beyond the curve (model units).
  std::int64_t vertices_moved = 0;  ///< Boundary control vertices moved.
};

/// One pass over the data boundary `edges` (BoundaryEdges(); each edge's first end is a data
/// boundary vertex) against the boundary curve of the domain surface with control positions
/// `positions` (no displacement, Yoon Eq. 4 with d = 0): each data vertex's closest point on the
/// curve (16 samples per boundary edge, then golden sections) and its excess, the distance it
/// lies beyond the curve along the surface's tangent plane, across the curve. A point at
/// parameter t on the boundary edge from a to b asks a to move out by its excess times
/// min(1, 2 (1 - t)) and b by its excess times min(1, 2 t); each boundary control vertex moves
/// by the largest it is asked (at most max_move_edges of its boundary edges' mean length),
/// along the surface, across the boundary: normalize((next - previous boundary vertex) x its
/// patch's normal). One pass: moving a vertex refits its neighbours' patches as well, so some
/// data vertices may still lie beyond the moved curve (docs/fitting.md has the measurements);
/// at a convex corner of the boundary the corner vertex moves along the bisector, by the excess
/// measured across one of its edges, so a corner is covered less.
/// `positions` is updated in place. Deterministic whatever the thread count.
/// Does nothing where the domain has no boundary, `edges` is empty or sizes disagree.
BoundaryCoverReport CoverDataBoundary(const ManifoldDomain& domain,
                                      const std::vector<std::pair<Vec3, Vec3>>& edges,
                                      const BoundaryCoverOptions& options,
                                      std::vector<Vec3>* positions);

}  // namespace dermis
