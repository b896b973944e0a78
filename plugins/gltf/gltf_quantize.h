// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// KHR_mesh_quantization for the glTF exporter (private to the plugin): the position grid
// chosen from the model, and the integer encodings of the other attributes
// (docs/gltf-compression.md, "Quantisation").
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "dermis/asset/asset.h"

namespace dermis::gltf_quantize {

/// The grid of the quantised positions: p = origin + step * q, q in [0, 2^bits - 1].
struct PositionGrid {
  glm::dvec3 origin{0.0};
  double step = 1.0;
  int bits = 16;
  /// The error the grid was chosen for (median edge length / kEdgeFraction).
  double target_error = 0.0;
};

/// The fraction of the median edge length that a quantised position may move (worst case,
/// 3D): 1/256 of an edge is far below what shading or silhouettes show.
constexpr double kEdgeFraction = 256.0;

/// Chooses the grid of every position of `asset` (morphed positions included: base + target),
/// one grid for the whole asset so that every skin and node shares one dequantising transform.
/// Bits: the fewest in [10, 16] whose worst-case error (step * sqrt(3) / 2) is at most the
/// median triangle edge length / kEdgeFraction; at most 15 when there are morph targets (their
/// deltas, up to 2^bits - 1 steps, must fit int16).
PositionGrid ChoosePositionGrid(const Asset& asset);

/// The grid coordinate of `p` (rounded, clamped to the grid).
glm::u16vec3 Quantize(const PositionGrid& grid, const glm::vec3& p);
/// The position a grid coordinate stands for.
glm::dvec3 Dequantize(const PositionGrid& grid, const glm::ivec3& q);

/// round(v * 32767), v clamped to [-1, 1] (glTF's signed normalised short).
std::int16_t Snorm16(float v);
/// round(v * 65535), v clamped to [0, 1] (glTF's unsigned normalised short).
std::uint16_t Unorm16(float v);

/// Normalised u16 weights for `slots` (floats summing to 1, largest first): rounded, then the
/// residue added to the largest so that the integers sum to exactly 65535 (the validator's
/// rule for normalised weights).
void QuantizeWeights(const float* slots, std::size_t count, std::uint16_t* out);

}  // namespace dermis::gltf_quantize
