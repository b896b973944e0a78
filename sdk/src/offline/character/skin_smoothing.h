// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Smoothing of a character part's control-vertex skin weights over its control mesh
// (docs/characters.md, "Skin weights smoothed on the control mesh"). Internal header of
// character_fit.cpp.
#pragma once

#include <glm/vec4.hpp>
#include <vector>

#include "dermis/core/mesh_topology.h"
#include "dermis/core/types.h"

namespace dermis::character {

/// Smooths per-vertex skin weights over a control mesh by `iterations` umbrella steps: each
/// step moves every vertex's weight vector (over all joints, not only its four; normalised to
/// sum 1 first) `step` of the way to the mean of its edge neighbours' (Taubin 1995's Laplacian
/// step). A vertex without weights stays without and is left out of its neighbours' means; a
/// vertex without weighted neighbours keeps its own. Vertices at bitwise equal rest positions
/// (the two sides of a crease cut open) are one vertex for it, with the union of their
/// neighbours and the mean of their weights, so they end equal. Afterwards each vertex keeps
/// its 4 largest influences (ties: smaller joint first), normalised to sum 1. `joints` and
/// `weights` hold one entry per vertex of `topology`, as `rest` does (asserted; in a release
/// build a mismatch changes nothing); `step` in (0, 1]. Deterministic: the result depends only
/// on the inputs' values and order.
void SmoothSkinWeights(const MeshTopology& topology, const std::vector<Vec3>& rest, int iterations,
                       double step, std::vector<glm::u16vec4>* joints,
                       std::vector<glm::vec4>* weights);

}  // namespace dermis::character
