// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "dermis/offline/geometry/mesh_metrics.h"

#include <algorithm>
#include <cmath>

namespace dermis {

TriangleMeshMetrics ComputeTriangleMeshMetrics(const std::vector<Vec3>& positions,
                                               const std::vector<std::uint32_t>& triangles) {
  TriangleMeshMetrics m;
  m.vertices = positions.size();
  m.triangles = triangles.size() / 3;
  std::vector<Vec3> normals(m.triangles);
  std::vector<char> used(positions.size(), 0);
  struct HalfEdge {
    std::uint32_t a, b, tri;
    bool forward;
  };
  std::vector<HalfEdge> he;
  he.reserve(triangles.size());
  for (std::size_t t = 0; t < m.triangles; ++t) {
    const std::uint32_t i[3] = {triangles[3 * t], triangles[3 * t + 1], triangles[3 * t + 2]};
    for (int k = 0; k < 3; ++k) used[i[k]] = 1;
    const Vec3 n = glm::cross(positions[i[1]] - positions[i[0]], positions[i[2]] - positions[i[0]]);
    const double len = std::sqrt(glm::dot(n, n));
    if (i[0] == i[1] || i[1] == i[2] || i[0] == i[2] || !(len > 0.0)) {
      ++m.degenerate_triangles;
      normals[t] = Vec3(0.0);
    } else {
      normals[t] = n / len;
    }
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = i[k], b = i[(k + 1) % 3];
      he.push_back({std::min(a, b), std::max(a, b), static_cast<std::uint32_t>(t), a < b});
    }
  }
  for (char u : used) m.unreferenced_vertices += u ? 0 : 1;
  std::sort(he.begin(), he.end(), [](const HalfEdge& x, const HalfEdge& y) {
    return x.a != y.a ? x.a < y.a : (x.b != y.b ? x.b < y.b : x.tri < y.tri);
  });
  for (std::size_t i = 0; i < he.size();) {
    std::size_t j = i;
    while (j < he.size() && he[j].a == he[i].a && he[j].b == he[i].b) ++j;
    ++m.edges;
    const std::size_t count = j - i;
    if (count == 1) {
      ++m.boundary_edges;
    } else if (count > 2) {
      ++m.non_manifold_edges;
    } else {
      if (he[i].forward == he[i + 1].forward) ++m.misoriented_edges;
      const double c = glm::dot(normals[he[i].tri], normals[he[i + 1].tri]);
      const double s = glm::length(glm::cross(normals[he[i].tri], normals[he[i + 1].tri]));
      m.max_dihedral = std::max(m.max_dihedral, std::atan2(s, c));
    }
    i = j;
  }
  return m;
}

}  // namespace dermis
