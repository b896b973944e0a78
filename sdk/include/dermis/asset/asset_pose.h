// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Poses of an Asset: animation sampling (LINEAR, STEP, CUBICSPLINE; glTF 2.0 appendix C),
/// node world matrices, joint matrices and linear blend skinning as glTF viewers compute them.
/// The asset must have passed ValidateAsset().
#pragma once

#include <vector>

#include "dermis/asset/asset.h"

namespace dermis {

/// The local transform of one node in a pose.
struct NodeTransform {
  glm::dvec3 translation{0.0};
  glm::dquat rotation{1.0, 0.0, 0.0, 0.0};
  glm::dvec3 scale{1.0};
  bool has_matrix = false;  ///< True: matrix is the transform (never animated).
  glm::dmat4 matrix{1.0};

  glm::dmat4 Matrix() const;  ///< T * R * S, or `matrix`.
};

/// A pose of the whole asset.
struct AssetPose {
  std::vector<NodeTransform> local;                ///< One per node.
  std::vector<std::vector<double>> morph_weights;  ///< One per node (empty: mesh default).
};

/// The rest pose: every node's own transform as stored in the asset.
void RestPose(const Asset& asset, AssetPose* pose);

/// Starts from the rest pose and applies every channel of clip `animation` sampled at `time`
/// seconds (clamped to the clip's keyframe range per sampler, as glTF viewers do). Rotations
/// are slerped (LINEAR) or Hermite-interpolated and renormalised (CUBICSPLINE).
void SamplePose(const Asset& asset, int animation, double time, AssetPose* pose);

/// World matrices (parent * local) of every node, in node order.
void ComputeWorldMatrices(const Asset& asset, const AssetPose& pose,
                          std::vector<glm::dmat4>* world);

/// Joint matrices world[joint] * inverse_bind of one skin.
void ComputeJointMatrices(const AssetSkin& skin, const std::vector<glm::dmat4>& world,
                          std::vector<glm::dmat4>* joint_matrices);

/// Positions (and normals if `normals` is non-null and the primitive has them) of one
/// primitive drawn by `node` in world space, as a glTF viewer draws them: with the skin's
/// linear blend skinning if the node has a skin (the node's own transform ignored, glTF 2.0
/// 3.7.3), else with the node's world matrix. Morph targets are applied first with the pose's
/// weights (or the mesh defaults).
void PosePrimitive(const Asset& asset, const AssetPose& pose, const std::vector<glm::dmat4>& world,
                   Index node, const AssetPrimitive& primitive, std::vector<glm::dvec3>* positions,
                   std::vector<glm::dvec3>* normals);

}  // namespace dermis
