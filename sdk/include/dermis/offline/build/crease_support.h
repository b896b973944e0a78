// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Support rows beside closed crease loops: the control vertices next to a crease loop
/// (a cap's rim, a sole's edge) are moved towards it, so the smooth domain surface rounds the
/// crease over a narrower band and the displacement has a smaller step to carry
/// (docs/characters.md, "Support rows beside crease loops").
///
/// This is the modeller's support (holding) edge loop of subdivision modelling, placed on an
/// existing control mesh: the Ying–Zorin domain surface (Yoon, section 3) is C-infinity, so a
/// crease kept as control edges is rounded across about one control edge on each side, and a
/// closer row on each side narrows that rounding.
#pragma once

#include <functional>

#include "dermis/core/status.h"
#include "dermis/offline/build/crease_chains.h"
#include "dermis/offline/geometry/polygon_mesh.h"

namespace dermis {

/// What SupportCreaseLoops() did.
struct CreaseSupportResult {
  int loops = 0;  ///< Closed crease loops of the chains with at least one control vertex on them.
  int moved = 0;  ///< Control vertices moved towards a loop.
};

/// Moves each control vertex of `control` that shares a control edge with a vertex lying on a
/// closed chain of `chains` (a loop), and with no vertex of any other crease chain, straight
/// towards that loop: from x to c + keep (x - c), c the loop's point closest to x, then onto
/// the surface by `project` (model units in, model units out). A control vertex lies on a
/// chain when it is within `tolerance` (model units, >= 0) of it. Left where they are:
/// vertices on a crease, beside two creases, or beside an open chain (one that ends at
/// corners: there the row would end and the domain surface ripples, measured in
/// docs/characters.md); a vertex whose neighbours on the loop surround it (their mean within
/// half their mean distance, as a small cap's centre joined to its rim); one whose c is
/// further from its nearest neighbour on the loop than it is (c on another stretch of the
/// loop); and one whose projection is not finite. A loop with a sharp turn (a corner no other chain
/// meets) is still a loop. Every vertex is tested against the positions before any move, so the
/// result does not depend on the vertex order. The faces are not changed.
///
/// `keep` in (0, 1]: the fraction of its distance to the loop a moved vertex keeps (1 moves
/// nothing); InvalidInput otherwise, for a negative or non-finite tolerance, and for a face
/// naming a vertex out of range. `chains` must have been built (CreaseChains::Build) on the
/// surface `control` was made from, and its crease vertices must lie on the chains (as
/// QuadRemesh leaves them, before any move off its input's triangles).
Status SupportCreaseLoops(const CreaseChains& chains, double keep, double tolerance,
                          const std::function<Vec3(const Vec3&)>& project, PolygonMesh* control,
                          CreaseSupportResult* result = nullptr);

}  // namespace dermis
