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

/// A bumpy sphere, radius 1 + a sin(3 theta) sin(2 phi) around the origin (a = 0: the unit
/// sphere), as a dense triangle mesh: a latitude-longitude grid of n_theta x (n_phi - 1)
/// vertices, the poles as fans.
PolygonMesh BumpySphereMesh(int n_theta, int n_phi, double a);

}  // namespace dermis::test
