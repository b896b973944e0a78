// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Procedural meshes and helpers shared by the tests.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "dermis/asset/asset.h"
#include "dermis/offline/build/domain_builder.h"
#include "dermis/offline/geometry/polygon_mesh.h"
#include "dermis/runtime/character.h"
#include "dermis/surface/displacement.h"

namespace dermis::test {

/// A fan of `k` quads around a centre vertex covering `sector` radians (2 pi = closed disk,
/// otherwise the centre is a boundary vertex). Each quad is (centre, e_i, d_i, e_{i+1}).
PolygonMesh FanMesh(int k, double sector, double height = 0.0);

/// Deterministic pseudo-random displacement of every vertex by up to `amount` per coordinate.
void Perturb(PolygonMesh* mesh, double amount, std::uint32_t seed);

/// A built-in mesh, failing the test if it cannot be made.
PolygonMesh Builtin(const std::string& name);

/// Builds the control surface, failing the test on error.
ControlSurface Build(const PolygonMesh& mesh, const DomainOptions& options = DomainOptions{});

/// Appends a closed capsule to `prim` (which must have one JOINTS/WEIGHTS set and one TEXCOORD
/// set): a cylinder along y in [0, 2] with hemispherical caps, radius 0.5, whose side and caps
/// have their own vertices (split at the junctions, as UV seams do), skinned to joints 0 and 1
/// with smoothstep weights over y in [0.7, 1.3]. Placed at x0 along x.
void AddCylinder(double x0, AssetPrimitive* prim);

/// Two capsules (two components) and a lone triangle (too small to fit) in one mesh drawn by a
/// skinned node; skeleton root -> j0 (at the origin) -> j1 (at y = 1), both joints of the skin.
Asset TwoCylinders();

/// TwoCylinders() fitted once with the default character options (2 threads), shared by the
/// tests of one executable.
const Character& FittedCylinders();

/// Deterministic uniform numbers in [0, 1).
class Lcg {
 public:
  explicit Lcg(std::uint64_t seed) : state_(seed * 2862933555777941757ULL + 3037000493ULL) {}
  double Next() {
    state_ = state_ * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state_ >> 11) * (1.0 / 9007199254740992.0);
  }
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Next(); }

 private:
  std::uint64_t state_;
};

/// d_v(x, y) = amplitude * sin(x + 0.3 v) * cos(1.3 y - 0.1 v): a different smooth function per
/// chart, to exercise the blending of displaced patches.
class WavyDisplacement final : public Displacement {
 public:
  explicit WavyDisplacement(double amplitude) : amplitude_(amplitude) {}
  void Evaluate(Index v, Vec2 z, double* value, Vec2* gradient) const override {
    const double a = z.x + 0.3 * v, b = 1.3 * z.y - 0.1 * v;
    *value = amplitude_ * std::sin(a) * std::cos(b);
    *gradient =
        Vec2(amplitude_ * std::cos(a) * std::cos(b), -1.3 * amplitude_ * std::sin(a) * std::sin(b));
  }

 private:
  double amplitude_;
};

}  // namespace dermis::test
