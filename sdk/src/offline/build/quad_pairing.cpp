// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Blossom-Quad (Remacle et al. 2012, "Blossom-Quad: a non-uniform quadrilateral mesh generator
// using a minimum-cost perfect-matching algorithm", section 2): adjacent triangles are merged
// into quads along a maximum weight matching of the dual graph, weighted by the quality of the
// quad each pair forms. The matching is LEMON's (docs/fitting.md, "Control mesh").
#include "dermis/offline/build/quad_pairing.h"

#include <lemon/matching.h>
#include <lemon/smart_graph.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

namespace dermis {
namespace {

constexpr double kPi = 3.14159265358979323846;

double Angle(const Vec3& u, const Vec3& v) {
  return std::atan2(glm::length(glm::cross(u, v)), glm::dot(u, v));
}

}  // namespace

double QuadQuality(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  // Convex: both diagonals split it into two triangles facing the same way.
  const Vec3 n1 = glm::cross(b - a, c - a), n2 = glm::cross(c - a, d - a);
  const Vec3 n3 = glm::cross(b - a, d - a), n4 = glm::cross(c - b, d - b);
  if (!(glm::dot(n1, n2) > 0.0) || !(glm::dot(n3, n4) > 0.0) ||
      !(glm::dot(n1 + n2, n3 + n4) > 0.0)) {
    return 0.0;
  }
  const Vec3 x[4] = {a, b, c, d};
  double worst = 0.0;
  for (int k = 0; k < 4; ++k) {
    const double angle = Angle(x[(k + 1) % 4] - x[k], x[(k + 3) % 4] - x[k]);
    worst = std::max(worst, std::abs(0.5 * kPi - angle));
  }
  return std::max(0.0, 1.0 - 2.0 / kPi * worst);
}

Status PairTrianglesIntoQuads(const std::vector<Vec3>& positions,
                              const std::vector<std::uint32_t>& triangles,
                              const QuadPairingOptions& options, PolygonMesh* out,
                              QuadPairingStats* stats,
                              const std::vector<std::array<std::uint32_t, 2>>* keep_edges) {
  if (triangles.empty() || triangles.size() % 3 != 0) {
    return Status::InvalidInput("quad pairing: no triangles");
  }
  for (std::uint32_t v : triangles) {
    if (v >= positions.size()) return Status::InvalidInput("quad pairing: index out of range");
  }
  const std::size_t nt = triangles.size() / 3;
  // Directed edges (a, b) -> triangle, sorted, to find the triangle across each edge.
  std::vector<std::array<std::uint32_t, 3>> directed;
  directed.reserve(3 * nt);
  for (std::size_t t = 0; t < nt; ++t) {
    for (int k = 0; k < 3; ++k) {
      directed.push_back({triangles[3 * t + static_cast<std::size_t>(k)],
                          triangles[3 * t + static_cast<std::size_t>((k + 1) % 3)],
                          static_cast<std::uint32_t>(t)});
    }
  }
  std::sort(directed.begin(), directed.end());
  auto across = [&](std::uint32_t a, std::uint32_t b) -> std::int64_t {
    auto it =
        std::lower_bound(directed.begin(), directed.end(), std::array<std::uint32_t, 3>{b, a, 0});
    if (it == directed.end() || (*it)[0] != b || (*it)[1] != a) return -1;
    return (*it)[2];
  };
  // Triangles around each vertex, and which vertices are on the boundary. A pair removes its
  // diagonal, so an interior vertex must keep at least 3 faces: no pair across an edge of an
  // interior vertex with 3 triangles, and the matching is repaired below for the rest.
  std::vector<int> around(positions.size(), 0);
  std::vector<char> boundary(positions.size(), 0);
  for (const auto& d : directed) {
    ++around[d[0]];
    if (across(d[0], d[1]) < 0) boundary[d[0]] = boundary[d[1]] = 1;
  }
  auto interior3 = [&](std::uint32_t v) { return !boundary[v] && around[v] <= 3; };
  // The dual graph: one node per triangle, one edge per convex pair of acceptable quality.
  lemon::SmartGraph graph;
  graph.reserveNode(static_cast<int>(nt));
  for (std::size_t t = 0; t < nt; ++t) graph.addNode();
  struct Pair {
    std::uint32_t t1, t2;
    std::array<std::uint32_t, 4> quad;
    double quality;
  };
  std::vector<Pair> pairs;
  for (std::size_t t = 0; t < nt; ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = triangles[3 * t + static_cast<std::size_t>(k)];
      const std::uint32_t b = triangles[3 * t + static_cast<std::size_t>((k + 1) % 3)];
      const std::uint32_t c = triangles[3 * t + static_cast<std::size_t>((k + 2) % 3)];
      const std::int64_t u = across(a, b);
      if (u <= static_cast<std::int64_t>(t)) continue;  // boundary, or seen from the other side
      if (interior3(a) || interior3(b)) continue;
      if (keep_edges &&
          std::binary_search(keep_edges->begin(), keep_edges->end(),
                             std::array<std::uint32_t, 2>{std::min(a, b), std::max(a, b)})) {
        continue;  // a crease stays an edge
      }
      const std::size_t s = static_cast<std::size_t>(u);
      std::uint32_t d = 0;
      for (int j = 0; j < 3; ++j) {
        const std::uint32_t w = triangles[3 * s + static_cast<std::size_t>(j)];
        if (w != a && w != b) d = w;
      }
      // Triangles (a, b, c) and (b, a, d) make the quad (a, d, b, c).
      const double q = QuadQuality(positions[a], positions[d], positions[b], positions[c]);
      if (!(q > 0.0) || q < options.min_quality) continue;
      pairs.push_back(
          {static_cast<std::uint32_t>(t), static_cast<std::uint32_t>(s), {a, d, b, c}, q});
    }
  }
  lemon::SmartGraph::EdgeMap<long long> weight(graph);
  std::vector<lemon::SmartGraph::Edge> edges;
  edges.reserve(pairs.size());
  for (const Pair& p : pairs) {
    const lemon::SmartGraph::Edge e = graph.addEdge(graph.nodeFromId(static_cast<int>(p.t1)),
                                                    graph.nodeFromId(static_cast<int>(p.t2)));
    weight[e] = std::llround(1000.0 * (options.pair_bonus + p.quality));
    edges.push_back(e);
  }
  lemon::MaxWeightedMatching<lemon::SmartGraph, lemon::SmartGraph::EdgeMap<long long>> matching(
      graph, weight);
  matching.run();
  // Each triangle's pair (index into `pairs`), or -1.
  std::vector<std::int64_t> pair_of(nt, -1);
  std::vector<char> chosen(pairs.size(), 0);
  for (std::size_t i = 0; i < pairs.size(); ++i) chosen[i] = matching.matching(edges[i]) ? 1 : 0;
  // Faces left around each vertex: its triangles less the diagonals removed there (quad[0] and
  // quad[2] are the diagonal's ends). An interior vertex left with 2 faces (two pairs meeting
  // at a vertex of 4 triangles) loses its first pair.
  std::vector<int> faces(around);
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    if (chosen[i]) --faces[pairs[i].quad[0]], --faces[pairs[i].quad[2]];
  }
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    if (!chosen[i]) continue;
    const std::uint32_t a = pairs[i].quad[0], b = pairs[i].quad[2];
    if ((!boundary[a] && faces[a] < 3) || (!boundary[b] && faces[b] < 3)) {
      chosen[i] = 0;
      ++faces[a], ++faces[b];
    }
  }
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    if (chosen[i]) {
      pair_of[pairs[i].t1] = static_cast<std::int64_t>(i);
      pair_of[pairs[i].t2] = static_cast<std::int64_t>(i);
    }
  }
  PolygonMesh mesh;
  mesh.positions = positions;
  QuadPairingStats st;
  double quality = 0.0;
  for (std::size_t t = 0; t < nt; ++t) {
    const std::int64_t i = pair_of[t];
    if (i < 0) {
      mesh.AddFace({static_cast<Index>(triangles[3 * t]), static_cast<Index>(triangles[3 * t + 1]),
                    static_cast<Index>(triangles[3 * t + 2])});
      ++st.triangles;
      continue;
    }
    const Pair& p = pairs[static_cast<std::size_t>(i)];
    if (p.t1 != t) continue;
    mesh.AddFace({static_cast<Index>(p.quad[0]), static_cast<Index>(p.quad[1]),
                  static_cast<Index>(p.quad[2]), static_cast<Index>(p.quad[3])});
    ++st.quads;
    quality += p.quality;
  }
  st.mean_quality = st.quads > 0 ? quality / st.quads : 0.0;
  *out = std::move(mesh);
  if (stats) *stats = st;
  return Status::Ok();
}

}  // namespace dermis
