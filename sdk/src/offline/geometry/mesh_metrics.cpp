// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "dermis/offline/geometry/mesh_metrics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <utility>

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

double AbsMeanCurvatureIntegral(const std::vector<Vec3>& positions,
                                const std::vector<std::uint32_t>& triangles, double weld) {
  std::map<std::array<long long, 3>, std::uint32_t> id;
  std::vector<std::uint32_t> w(positions.size());
  std::vector<Vec3> welded;
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const Vec3& p = positions[i];
    const std::array<long long, 3> key = {std::llround(p.x / weld), std::llround(p.y / weld),
                                          std::llround(p.z / weld)};
    const auto it = id.emplace(key, static_cast<std::uint32_t>(welded.size()));
    if (it.second) welded.push_back(p);
    w[i] = it.first->second;
  }
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::size_t>> edges;
  std::vector<Vec3> normal(triangles.size() / 3);
  for (std::size_t t = 0; t < normal.size(); ++t) {
    const Vec3 &a = positions[triangles[3 * t]], &b = positions[triangles[3 * t + 1]],
               &c = positions[triangles[3 * t + 2]];
    const Vec3 n = glm::cross(b - a, c - a);
    const double l = glm::length(n);
    normal[t] = l > 0.0 ? n / l : Vec3(0.0);
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint32_t x = w[triangles[3 * t + k]], y = w[triangles[3 * t + (k + 1) % 3]];
      if (x != y) edges[{std::min(x, y), std::max(x, y)}].push_back(t);
    }
  }
  double sum = 0.0;
  for (const auto& e : edges) {
    if (e.second.size() != 2) continue;
    const Vec3 &n0 = normal[e.second[0]], &n1 = normal[e.second[1]];
    if (glm::dot(n0, n0) == 0.0 || glm::dot(n1, n1) == 0.0) continue;
    // atan2 of sine and cosine: exact to rounding near 0, where acos(cos) is not (1e-8).
    const double angle = std::atan2(glm::length(glm::cross(n0, n1)), glm::dot(n0, n1));
    sum += 0.5 * angle * glm::length(welded[e.first.second] - welded[e.first.first]);
  }
  return sum;
}

}  // namespace dermis
