// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Tangent frames of a bound output (docs/engine-integration.md, "Tangents"): what the kernels
// need to carry the source's bind tangents along with the surface (PlanOutputBuffers).
#pragma once

#include <cstddef>
#include <vector>

#include "dermis/core/status.h"
#include "dermis/runtime/evaluation_plan.h"

namespace dermis {

class RuntimeCharacter;

/// For each vertex of `plan` (the bound output of part `part`: vertex i is
/// character.bound_vertices(part)[i]), the coefficients (a, b, w, 0) with which the kernel
/// rebuilds its tangent from the surface's face derivatives: the bind tangent T (the source's
/// TANGENT, or else one computed from TEXCOORD_0) projected onto the rest surface's tangent
/// plane is a dS/du + b dS/dv there, and w is its handedness. Fails, naming the mesh and
/// primitive, on a bound vertex whose primitive has neither tangents nor texture coordinates
/// (or whose texture coordinates give no tangent: a primitive that is not a triangle list).
/// Allocates (output creation, not per frame).
Status BuildTangentFrames(const RuntimeCharacter& character, std::size_t part,
                          const EvaluationPlan& plan, std::vector<float>* frames);

}  // namespace dermis
