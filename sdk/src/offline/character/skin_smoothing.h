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
/// step moves every vertex's weight vector (over all joints, not only its four) `step` of the
/// way to the mean of its edge neighbours' (Taubin 1995's Laplacian step; a vertex without
/// neighbours keeps its own). Vertices at bitwise equal rest positions (the two sides of a
/// crease cut open) are one vertex for it, with the union of their neighbours, so they keep
/// equal weights. Afterwards each vertex keeps its 4 largest influences (ties: smaller joint
/// first), normalised to sum 1. `joints` and `weights` hold one entry per vertex of
/// `topology` (`rest` too); `step` in (0, 1]. Deterministic: the result depends only on the
/// inputs' values and order.
void SmoothSkinWeights(const MeshTopology& topology, const std::vector<Vec3>& rest, int iterations,
                       double step, std::vector<glm::u16vec4>* joints,
                       std::vector<glm::vec4>* weights);

}  // namespace dermis::character
