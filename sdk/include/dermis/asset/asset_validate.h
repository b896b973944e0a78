// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Structural checks of an Asset, run by every importer before it hands an asset out
/// and by readers of stored assets: so code that consumes an Asset may assume them.
#pragma once

#include "dermis/asset/asset.h"
#include "dermis/core/status.h"

namespace dermis {

/// Checks that:
/// - every index (node children/mesh/skin, skin joints/skeleton, primitive material, texture
///   image/sampler, channel node/sampler, scene nodes) is in range;
/// - the node graph is a forest (no node is the child of two nodes, no cycles) and
///   AssetNode::parent agrees with the children lists;
/// - every number is finite (positions, normals, matrices, TRS, keyframes, weights), rotations
///   are non-zero, inverse bind matrices have the last row (0, 0, 0, 1);
/// - attribute arrays have the vertex count, indices are < vertex count and fit the mode;
/// - joint indices are < the skin's joint count of every node that draws the mesh with a skin,
///   weights are >= 0;
/// - animation times are finite and increasing, value counts match times and components, and
///   the channel's path matches the sampler's component count.
/// The message names `asset.source` and a JSON pointer to the fault, e.g.
/// "model.glb: /nodes/3/children/0: node 1 has two parents (0 and 3)".
Status ValidateAsset(const Asset& asset);

}  // namespace dermis
