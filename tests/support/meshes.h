// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Test support: polygon meshes (fans, the built-in meshes of the geometry stage) and
// (support/random.h) deterministic random numbers. Links dermis::offline_geometry.
#pragma once

#include <cstdint>
#include <string>

#include "dermis/asset/polygon_mesh.h"
#include "support/random.h"

namespace dermis::test {

/// A fan of `k` quads around a centre vertex covering `sector` radians (2 pi = closed disk,
/// otherwise the centre is a boundary vertex). Each quad is (centre, e_i, d_i, e_{i+1}).
PolygonMesh FanMesh(int k, double sector, double height = 0.0);

/// Deterministic pseudo-random displacement of every vertex by up to `amount` per coordinate.
void Perturb(PolygonMesh* mesh, double amount, std::uint32_t seed);

/// A built-in mesh, failing the test if it cannot be made.
PolygonMesh Builtin(const std::string& name);

}  // namespace dermis::test
