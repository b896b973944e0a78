// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Moving per-vertex attributes (skin influences, texture coordinates) from a dense
/// triangle mesh to other points through the nearest surface point: the closest point's
/// triangle and barycentric coordinates blend its three corners' values.
#pragma once

#include <cstdint>
#include <glm/vec2.hpp>
#include <glm/vec4.hpp>
#include <vector>

#include "dermis/asset/asset.h"
#include "dermis/offline/geometry/triangle_distance.h"

namespace dermis {

/// The triangles of a primitive as vertex index triples (lists, strips with alternating
/// winding fixed, fans); none for points and lines.
std::vector<std::uint32_t> PrimitiveTriangles(const AssetPrimitive& primitive);

/// One joint influence.
struct Influence {
  std::uint16_t joint = 0;
  float weight = 0.0f;
};

/// The influences of `vertex` over every JOINTS_n/WEIGHTS_n set of `primitive`, duplicates of a
/// joint merged, zero weights dropped, sorted by joint.
std::vector<Influence> VertexInfluences(const AssetPrimitive& primitive, std::size_t vertex);

/// Blends the influence lists of a triangle's corners with barycentric weights, keeps the 4
/// largest (ties: smaller joint first) and normalises them to sum 1. Unused slots are joint 0
/// with weight 0; with no influence at all every weight is 0.
void BlendInfluences(const std::vector<Influence>& a, const std::vector<Influence>& b,
                     const std::vector<Influence>& c, const Vec3& barycentric, glm::u16vec4* joints,
                     glm::vec4* weights);

}  // namespace dermis
