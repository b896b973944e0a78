// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief A control mesh cut open along its hard creases (docs/characters.md, "Hard edges cut
/// open"): the C-infinity domain surface (Yoon, section 3) rounds every crease kept as control
/// edges over about one control edge on each side, and a quadratic patch through a right angle
/// overshoots the flat side by an eighth of the edge (the lip). Cut along the crease, each side
/// is a surface with a boundary there, flat up to the crease; with the seam patch operators
/// (ComputeSeamPatchFitOperator) the two boundaries are one curve.
#pragma once

#include <cstdint>
#include <vector>

#include "dermis/core/status.h"
#include "dermis/core/types.h"
#include "dermis/offline/build/crease_chains.h"
#include "dermis/offline/geometry/polygon_mesh.h"

namespace dermis {

/// What CutAlongCreases() did.
struct CreaseCutResult {
  int cut_edges = 0;     ///< Control edges cut open (each now two boundary edges).
  int new_vertices = 0;  ///< Vertices added: one per extra side of a vertex on the cut.
  /// Per vertex of the cut mesh: 0 off the cut; 1 for a side of a vertex inside a crease chain
  /// (two cut edges, off the mesh's boundary); 2 for a side of a junction (three or more cut
  /// edges) or of a vertex on the boundary. BuildManifoldDomain() chooses each side's chart and
  /// seam operator from it and the side's boundary (domain_builder.h).
  std::vector<std::uint8_t> seam;
};

/// Cuts `control` open along its control edges that follow a crease chain of `chains`: both
/// ends within `tolerance` (model units) of one chain, and the chain between them (the way
/// CreaseChains::Between goes) within a quarter of the edge's length of it. A chain that ends
/// inside the surface (a vertex off the boundary with one such edge: a slit's end, whose two
/// sides one chart cannot close) is left closed, edge by edge back to a junction or the
/// boundary. Each vertex on a cut edge gets one copy per fan of its faces between cut edges
/// (the first keeps its index, the others are appended in half-edge order, at the same
/// position); faces keep their order and orientation. Deterministic. InvalidInput for a mesh the
/// topology refuses (non-manifold, inconsistent orientation) or a negative or non-finite tolerance;
/// `chains` must have been built on the surface `control` lies on.
Status CutAlongCreases(const CreaseChains& chains, double tolerance, PolygonMesh* control,
                       CreaseCutResult* result);

}  // namespace dermis
