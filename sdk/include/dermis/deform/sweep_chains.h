// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief The chains of the sweep deformer (runtime; core + GLM only): how a skeleton is cut
/// into sweeps so that every joint carrying skin owns a bone (docs/deformation.md, "Chains").
/// MakeSweepDeformer() builds them; they are public so that tools and tests can show them.
#pragma once

#include <cstddef>
#include <vector>

#include "dermis/core/status.h"
#include "dermis/core/types.h"
#include "dermis/deform/deformer.h"

namespace dermis {

/// One chain J0..Jn of a skeleton, swept as one trajectory. Bone i (points[i] -> points[i + 1])
/// is owned by joints[i]. When the last joint carries skin, the chain ends in a virtual bone it
/// owns: points has one entry more than joints.
struct SweepChain {
  /// Rig joints in chain order (parent before child).
  std::vector<Index> joints;
  /// Bind-space positions (mesh units): the joints' bind positions, then the virtual end if
  /// there is one.
  std::vector<Vec3> points;
  /// True if the chain ends in a virtual bone of joints.back().
  bool virtual_end = false;
  /// How the virtual bone's direction was chosen (kNone without one).
  enum class EndDirection : unsigned char {
    kNone = 0,
    kSkin = 1,       ///< Towards the weighted centroid of the joint's vertices.
    kIncoming = 2,   ///< Along the bone before it (its vertices sit around the joint).
    kLocalFrame = 3  ///< Along the joint's bind-frame y axis (no bone before it, no skin offset).
  };
  EndDirection end_direction = EndDirection::kNone;
};

/// Cuts a rig into sweep chains (docs/deformation.md, "Chains"):
/// - a joint continues its chain into the child with a bone of positive length that is most
///   nearly straight ahead of the bone before it (the neck after the chest, not a shoulder); a
///   joint with no such bone before it (a root, or below a joint carrying no skin) continues
///   into the child whose subtree carries the most skin weight (the spine after the pelvis);
///   every other child starts a chain of its own;
/// - a chain starts at its first joint carrying skin (leading joints without skin own nothing);
/// - a chain whose last joint carries skin ends in a virtual bone: direction towards the
///   weighted centroid of the joint's vertices when that centroid lies at least a quarter of
///   their spread (RMS distance from the centroid) away from the joint, else along the bone
///   before it, else along the joint's bind-frame y axis; length the farthest reach of its
///   vertices along that direction, at least half the bone before it (or their spread);
/// - a joint whose largest blend zone (options.max_blend_fraction of the shorter of its two
///   bones) would fold its skin (radius: the 90th percentile distance from the two bones of the
///   vertices with at least half their weight on it, the joint before or the joint after) at a
///   bend below options.min_fold_angle or below its rest bend is a cut: it ends its chain
///   (owning no bone there, so no virtual bone either) and heads the next.
/// Every joint carrying skin thus owns exactly one bone (a cut joint appears as the last joint
/// of one chain and the first of the next). `influences` are validated by ValidateRig first;
/// fails naming the rig fault. Positions in mesh (bind) units; `rest_positions` has `count`
/// entries.
Status BuildSweepChains(const SkinRig& rig, const Vec3* rest_positions,
                        const VertexWeights* influences, std::size_t count,
                        const SweepOptions& options, std::vector<SweepChain>* out);

}  // namespace dermis
