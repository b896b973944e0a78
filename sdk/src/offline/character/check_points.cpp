// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Check points of a character part (docs/characters.md, "Levels checked between the samples"):
// uniform random points on its triangles from a fixed hash, so the result is the same on every
// machine and thread count.
#include "check_points.h"

#include <algorithm>
#include <cmath>

#include "dermis/core/hash.h"

namespace dermis::character {
namespace {

/// A uniform number in [0, 1) from the hash's state, which it advances.
double Uniform(std::uint64_t* state) {
  *state = SplitMix64(*state);
  return HashToUnit(*state);
}

/// The area of triangle f (0 for another face or a degenerate one).
double TriangleArea(const PolygonMesh& mesh, Index f) {
  if (mesh.face_offsets[f + 1] - mesh.face_offsets[f] != 3) return 0.0;
  const Index* v = &mesh.face_vertices[mesh.face_offsets[f]];
  const double area = 0.5 * glm::length(glm::cross(mesh.positions[v[1]] - mesh.positions[v[0]],
                                                   mesh.positions[v[2]] - mesh.positions[v[0]]));
  return std::isfinite(area) ? area : 0.0;
}

}  // namespace

std::vector<Vec3> CheckPoints(const PolygonMesh& mesh, const ShadingSurface& shading,
                              double spacing, double per_area, std::uint64_t seed,
                              double max_points, std::vector<Vec3>* normals) {
  std::vector<Vec3> out;
  if (normals) normals->clear();
  if (!(spacing > 0.0) || !(per_area > 0.0) || !(max_points > 0.0) || !std::isfinite(spacing) ||
      !std::isfinite(per_area) || !std::isfinite(max_points)) {
    return out;
  }
  std::vector<double> area(static_cast<std::size_t>(mesh.num_faces()));
  double total = 0.0;
  for (Index f = 0; f < mesh.num_faces(); ++f) {
    area[static_cast<std::size_t>(f)] = TriangleArea(mesh, f);
    total += area[static_cast<std::size_t>(f)];
  }
  double density = per_area / (spacing * spacing);
  if (total * density > max_points) density = max_points / total;
  for (Index f = 0; f < mesh.num_faces(); ++f) {
    const double expected = std::min(area[static_cast<std::size_t>(f)] * density, max_points);
    if (!(expected > 0.0) || !std::isfinite(expected)) continue;
    std::uint64_t state = SplitMix64(seed ^ SplitMix64(static_cast<std::uint64_t>(f)));
    const double whole = std::floor(expected);
    const auto count = static_cast<std::int64_t>(whole) + (Uniform(&state) < expected - whole);
    for (std::int64_t k = 0; k < count; ++k) {
      // Uniform over the triangle: the square root folds the unit square onto it.
      const double r = std::sqrt(Uniform(&state)), s = Uniform(&state);
      const double w[3] = {1.0 - r, r * (1.0 - s), r * s};
      out.push_back(shading.Point(f, w));
      if (normals) normals->push_back(shading.Normal(f, w));
    }
  }
  return out;
}

}  // namespace dermis::character
