// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Leave-one-out quadric residuals over two-ring neighbourhoods (docs/fitting.md,
// "Noise-adaptive control fit"): a local polynomial predictor of a vertex from its
// neighbours, as in the moving least-squares noise estimates of point-set surfaces.
#include "dermis/offline/fit/noise_estimate.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <vector>

namespace dermis {

VertexNoise EstimateVertexNoise(const PolygonMesh& mesh, int max_samples) {
  VertexNoise out;
  const std::size_t nv = mesh.positions.size();
  if (nv == 0 || max_samples <= 0) return out;
  // One-ring adjacency from the faces' edges.
  std::vector<std::vector<Index>> ring(nv);
  for (Index f = 0; f < mesh.num_faces(); ++f) {
    const Index o = mesh.face_offsets[f], n = mesh.face_size(f);
    for (Index k = 0; k < n; ++k) {
      const Index a = mesh.face_vertices[o + k], b = mesh.face_vertices[o + (k + 1) % n];
      if (a < 0 || b < 0 || static_cast<std::size_t>(a) >= nv ||
          static_cast<std::size_t>(b) >= nv || a == b) {
        continue;
      }
      ring[static_cast<std::size_t>(a)].push_back(b);
      ring[static_cast<std::size_t>(b)].push_back(a);
    }
  }
  for (auto& r : ring) {
    std::sort(r.begin(), r.end());
    r.erase(std::unique(r.begin(), r.end()), r.end());
  }
  const std::size_t stride = std::max<std::size_t>(1, nv / static_cast<std::size_t>(max_samples));
  std::vector<double> residual, spacing;
  std::vector<Index> near;
  for (std::size_t v = 0; v < nv; v += stride) {
    near.clear();
    for (Index a : ring[v]) {
      near.push_back(a);
      for (Index b : ring[static_cast<std::size_t>(a)]) near.push_back(b);
    }
    std::sort(near.begin(), near.end());
    near.erase(std::unique(near.begin(), near.end()), near.end());
    near.erase(std::remove(near.begin(), near.end(), static_cast<Index>(v)), near.end());
    if (near.size() < 8 || ring[v].empty()) continue;
    const Vec3& p = mesh.positions[v];
    // Principal frame of the neighbours (the vertex left out).
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (Index a : near) {
      const Vec3& q = mesh.positions[static_cast<std::size_t>(a)];
      c += Eigen::Vector3d(q.x, q.y, q.z);
    }
    c /= static_cast<double>(near.size());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    double radius = 0.0;
    for (Index a : near) {
      const Vec3& q = mesh.positions[static_cast<std::size_t>(a)];
      const Eigen::Vector3d x = Eigen::Vector3d(q.x, q.y, q.z) - c;
      cov += x * x.transpose();
      radius = std::max(radius, x.norm());
    }
    if (!(radius > 0.0)) continue;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
    const Eigen::Vector3d n = es.eigenvectors().col(0), u = es.eigenvectors().col(2),
                          w = es.eigenvectors().col(1);
    // Height field h(x, y) = c0 + c1 x + c2 y + c3 x^2 + c4 xy + c5 y^2 (coordinates scaled
    // by the neighbourhood's radius, for conditioning).
    Eigen::MatrixXd m(static_cast<Eigen::Index>(near.size()), 6);
    Eigen::VectorXd h(static_cast<Eigen::Index>(near.size()));
    for (std::size_t i = 0; i < near.size(); ++i) {
      const Vec3& q = mesh.positions[static_cast<std::size_t>(near[i])];
      const Eigen::Vector3d x = Eigen::Vector3d(q.x, q.y, q.z) - c;
      const double s = x.dot(u) / radius, t = x.dot(w) / radius;
      const auto r = static_cast<Eigen::Index>(i);
      m.row(r) << 1.0, s, t, s * s, s * t, t * t;
      h(r) = x.dot(n);
    }
    const Eigen::VectorXd coef = m.colPivHouseholderQr().solve(h);
    const Eigen::Vector3d x = Eigen::Vector3d(p.x, p.y, p.z) - c;
    const double s = x.dot(u) / radius, t = x.dot(w) / radius;
    const double pred =
        coef(0) + coef(1) * s + coef(2) * t + coef(3) * s * s + coef(4) * s * t + coef(5) * t * t;
    const double r = std::abs(x.dot(n) - pred);
    double sum = 0.0;
    for (Index a : ring[v]) sum += glm::length(mesh.positions[static_cast<std::size_t>(a)] - p);
    if (!std::isfinite(r) || !std::isfinite(sum)) continue;  // a non-finite position
    residual.push_back(r);
    spacing.push_back(sum / static_cast<double>(ring[v].size()));
  }
  if (residual.empty()) return out;
  auto median = [](std::vector<double>* x) {
    const auto mid = x->begin() + static_cast<std::ptrdiff_t>(x->size() / 2);
    std::nth_element(x->begin(), mid, x->end());
    return *mid;
  };
  out.vertices_used = static_cast<int>(residual.size());
  out.median = median(&residual);
  out.spacing = median(&spacing);
  return out;
}

}  // namespace dermis
