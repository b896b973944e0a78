// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Adaptive sizing for remeshing (docs/fitting.md, "Control mesh: sizing"): the edge length of
// Dunyach et al. 2013 ("Adaptive remeshing for real-time mesh deformation") bounded by a turn
// angle per edge instead of a chord error, with the curvature of the normal-cycle tensor
// (Cohen-Steiner & Morvan 2003, "Restricted Delaunay triangulations and normal cycle") over a
// ball, and the gradation of Persson 2006 ("Mesh size functions for implicit geometries and
// PDE-based gradient limiting") solved on the mesh graph.
#include "dermis/offline/build/sizing_field.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <queue>

namespace dermis {

Status SizingField::Build(const std::vector<Vec3>& positions,
                          const std::vector<std::uint32_t>& triangles,
                          const std::vector<double>& vertex_loop_length,
                          const SizingOptions& options) {
  if (triangles.empty() || triangles.size() % 3 != 0 ||
      vertex_loop_length.size() != positions.size()) {
    return Status::InvalidInput("sizing field: empty or mismatched seed mesh");
  }
  for (std::uint32_t v : triangles) {
    if (v >= positions.size()) return Status::InvalidInput("sizing field: index out of range");
  }
  options_ = options;
  positions_ = positions;
  triangles_ = triangles;
  loop_length_ = vertex_loop_length;
  const std::size_t nv = positions.size(), nt = triangles.size() / 3;
  normals_.assign(nt, Vec3(0.0));
  areas_.assign(nt, 0.0);
  std::vector<double> vertex_area(nv, 0.0);
  for (std::size_t t = 0; t < nt; ++t) {
    const Vec3& a = positions[triangles[3 * t]];
    const Vec3 n =
        glm::cross(positions[triangles[3 * t + 1]] - a, positions[triangles[3 * t + 2]] - a);
    const double l = glm::length(n);
    areas_[t] = 0.5 * l;
    normals_[t] = l > 0.0 ? n / l : Vec3(0.0);
    for (int k = 0; k < 3; ++k) {
      vertex_area[triangles[3 * t + static_cast<std::size_t>(k)]] += l / 6.0;
    }
  }
  // Edges with their signed dihedral angle (positive where convex), from the sorted
  // undirected edges (a, b, triangle): interior edges appear twice.
  std::vector<std::array<std::uint32_t, 3>> directed;
  directed.reserve(3 * nt);
  for (std::size_t t = 0; t < nt; ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = triangles[3 * t + static_cast<std::size_t>(k)];
      const std::uint32_t b = triangles[3 * t + static_cast<std::size_t>((k + 1) % 3)];
      directed.push_back({std::min(a, b), std::max(a, b), static_cast<std::uint32_t>(t)});
    }
  }
  std::sort(directed.begin(), directed.end());
  neighbors_.assign(nv, {});
  struct Edge {
    std::uint32_t a, b;
    double angle;
  };
  std::vector<Edge> edges;
  std::vector<std::vector<std::uint32_t>> edges_of(nv);
  for (std::size_t i = 0; i < directed.size(); ++i) {
    const std::uint32_t a = directed[i][0], b = directed[i][1];
    if (i > 0 && directed[i - 1][0] == a && directed[i - 1][1] == b) continue;
    neighbors_[a].push_back(static_cast<Index>(b));
    neighbors_[b].push_back(static_cast<Index>(a));
    double angle = 0.0;
    if (i + 1 < directed.size() && directed[i + 1][0] == a && directed[i + 1][1] == b) {
      const std::uint32_t t1 = directed[i][2], t2 = directed[i + 1][2];
      const Vec3& n1 = normals_[t1];
      const Vec3& n2 = normals_[t2];
      angle = std::atan2(glm::length(glm::cross(n1, n2)), glm::dot(n1, n2));
      // Convex when the far corner of the second triangle lies below the first's plane.
      std::uint32_t d = a;
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t w =
            triangles[3 * static_cast<std::size_t>(t2) + static_cast<std::size_t>(k)];
        if (w != a && w != b) d = w;
      }
      if (glm::dot(positions[d] - positions[a], n1) > 0.0) angle = -angle;
    }
    edges_of[a].push_back(static_cast<std::uint32_t>(edges.size()));
    edges_of[b].push_back(static_cast<std::uint32_t>(edges.size()));
    edges.push_back({a, b, angle});
  }
  for (std::size_t v = 0; v < nv; ++v) std::sort(neighbors_[v].begin(), neighbors_[v].end());
  // Curvature at each vertex: the largest eigenvalue (in magnitude) of the normal-cycle tensor
  // sum_e angle_e |e| (e e^T) / area over the seed vertices within `radius` (Cohen-Steiner &
  // Morvan 2003): signed angles, so the zig-zag of noise cancels while a curved part adds up.
  Vec3 lo(positions[triangles[0]]), hi(lo);
  double total_area = 0.0;
  for (std::size_t t = 0; t < nt; ++t) total_area += areas_[t];
  for (std::uint32_t v : triangles)
    lo = glm::min(lo, positions[v]), hi = glm::max(hi, positions[v]);
  const double radius =
      options.curvature_radius > 0.0 ? options.curvature_radius : 1e-3 * glm::length(hi - lo);
  curvature_.assign(nv, 0.0);
  std::vector<int> mark(nv, -1), edge_mark(edges.size(), -1);
  std::vector<std::uint32_t> ball;
  for (std::size_t v = 0; v < nv; ++v) {
    if (neighbors_[v].empty()) continue;
    ball.assign(1, static_cast<std::uint32_t>(v));
    mark[v] = static_cast<int>(v);
    for (std::size_t i = 0; i < ball.size(); ++i) {
      for (Index w : neighbors_[ball[i]]) {
        const std::size_t u = static_cast<std::size_t>(w);
        if (mark[u] == static_cast<int>(v)) continue;
        if (glm::length(positions[u] - positions[v]) > radius) continue;
        mark[u] = static_cast<int>(v);
        ball.push_back(static_cast<std::uint32_t>(u));
      }
    }
    Eigen::Matrix3d tensor = Eigen::Matrix3d::Zero();
    double area = 0.0;
    for (std::uint32_t u : ball) {
      area += vertex_area[u];
      for (std::uint32_t e : edges_of[u]) {
        if (edge_mark[e] == static_cast<int>(v)) continue;
        edge_mark[e] = static_cast<int>(v);
        const Vec3 d = positions[edges[e].b] - positions[edges[e].a];
        const double l = glm::length(d);
        if (!(l > 0.0)) continue;
        // Half an edge with only one end in the ball.
        const bool both =
            mark[edges[e].a] == static_cast<int>(v) && mark[edges[e].b] == static_cast<int>(v);
        const Eigen::Vector3d u3(d.x / l, d.y / l, d.z / l);
        tensor += (both ? 1.0 : 0.5) * edges[e].angle * l * (u3 * u3.transpose());
      }
    }
    if (!(area > 0.0)) continue;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(tensor / area, Eigen::EigenvaluesOnly);
    curvature_[v] = eig.eigenvalues().cwiseAbs().maxCoeff();
  }
  // The reference curvature: the area-weighted quantile.
  {
    std::vector<std::pair<double, double>> by_curvature;
    double total = 0.0;
    for (std::size_t v = 0; v < nv; ++v) {
      if (vertex_area[v] > 0.0) by_curvature.emplace_back(curvature_[v], vertex_area[v]);
      total += vertex_area[v];
    }
    std::sort(by_curvature.begin(), by_curvature.end());
    double acc = 0.0;
    reference_curvature_ = by_curvature.empty() ? 0.0 : by_curvature.back().first;
    for (const auto& c : by_curvature) {
      acc += c.second;
      if (acc >= options.reference_quantile * total) {
        reference_curvature_ = c.first;
        break;
      }
    }
  }
  if (!tree_.Build(positions_, triangles_)) {
    return Status::InvalidInput("sizing field: the seed mesh has non-finite positions");
  }
  h_max_ = 0.0;
  size_.assign(nv, 0.0);
  return Status::Ok();
}

void SizingField::SetScale(double h_max) {
  h_max_ = h_max;
  const std::size_t nv = positions_.size();
  const double h_min = options_.min_fraction * h_max;
  using Item = std::pair<double, Index>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  for (std::size_t v = 0; v < nv; ++v) {
    double h = h_max;
    if (curvature_[v] > reference_curvature_) {
      h *= std::pow(reference_curvature_ / curvature_[v], options_.curvature_exponent);
    }
    h = std::max(h, h_min);
    if (options_.max_turn > 0.0 && curvature_[v] > 0.0) {
      h = std::min(h, options_.max_turn / curvature_[v]);
    }
    if (loop_length_[v] > 0.0 && options_.loop_segments > 0) {
      h = std::min(h, loop_length_[v] / options_.loop_segments);
    }
    size_[v] = h;
    if (!neighbors_[v].empty()) queue.push({size_[v], static_cast<Index>(v)});
  }
  // Gradient limiting: h_i <= h_j + g |x_i - x_j|, settled in increasing order of size.
  std::vector<char> done(nv, 0);
  while (!queue.empty()) {
    const Item top = queue.top();
    queue.pop();
    const std::size_t v = static_cast<std::size_t>(top.second);
    if (done[v] || top.first > size_[v]) continue;
    done[v] = 1;
    for (Index w : neighbors_[v]) {
      const std::size_t u = static_cast<std::size_t>(w);
      const double h = size_[v] + options_.gradation * glm::length(positions_[u] - positions_[v]);
      if (!done[u] && h < size_[u]) {
        size_[u] = h;
        queue.push({h, w});
      }
    }
  }
}

double SizingField::PredictedVertices() const {
  double n = 0.0;
  const double per_vertex = std::sqrt(3.0) / 2.0;
  for (std::size_t t = 0; t < areas_.size(); ++t) {
    double inv = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double h = size_[triangles_[3 * t + static_cast<std::size_t>(k)]];
      inv += 1.0 / (3.0 * h * h);
    }
    n += areas_[t] * inv / per_vertex;
  }
  return n;
}

double SizingField::SetScaleForVertices(double vertices) {
  Vec3 lo(positions_[triangles_[0]]), hi(lo);
  for (std::uint32_t v : triangles_)
    lo = glm::min(lo, positions_[v]), hi = glm::max(hi, positions_[v]);
  // Bisection on log(h_max) to a relative width of 1e-4 (the count then within about 2e-4).
  double a = 1e-6 * glm::length(hi - lo), b = 2.0 * glm::length(hi - lo);
  while (b > a * (1.0 + 1e-4)) {
    const double m = std::sqrt(a * b);
    SetScale(m);
    if (PredictedVertices() > vertices) {
      a = m;
    } else {
      b = m;
    }
  }
  SetScale(std::sqrt(a * b));
  return h_max_;
}

double SizingField::At(const Vec3& p, const Vec3& normal) const {
  ClosestPoint q = tree_.Query(p);
  if (q.triangle == kInvalidIndex) return h_max_;
  if (glm::dot(normal, normal) > 0.0 &&
      !(glm::dot(normals_[static_cast<std::size_t>(q.triangle)], normal) > 0.0)) {
    const ClosestPoint f = tree_.QueryIf(
        p, [&](Index t) { return glm::dot(normals_[static_cast<std::size_t>(t)], normal) > 0.0; },
        q.distance + h_max_);
    if (f.triangle != kInvalidIndex) q = f;
  }
  const std::size_t t = 3 * static_cast<std::size_t>(q.triangle);
  return q.barycentric.x * size_[triangles_[t]] + q.barycentric.y * size_[triangles_[t + 1]] +
         q.barycentric.z * size_[triangles_[t + 2]];
}

}  // namespace dermis
