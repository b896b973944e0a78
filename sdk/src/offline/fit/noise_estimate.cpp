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

namespace {

/// One-ring lists for the vertices marked in `want` (slot[v] >= 0), from the faces' edges;
/// indices out of range and repeated corners are skipped.
void CollectRings(const PolygonMesh& mesh, const std::vector<int>& slot,
                  std::vector<std::vector<Index>>* ring) {
  const std::size_t nv = mesh.positions.size();
  const Index nf = static_cast<Index>(mesh.face_offsets.empty() ? 0 : mesh.num_faces());
  for (Index f = 0; f < nf; ++f) {
    const Index o = mesh.face_offsets[static_cast<std::size_t>(f)], n = mesh.face_size(f);
    if (o < 0 || n < 2 || static_cast<std::size_t>(o + n) > mesh.face_vertices.size()) continue;
    for (Index k = 0; k < n; ++k) {
      const Index a = mesh.face_vertices[static_cast<std::size_t>(o + k)];
      const Index b = mesh.face_vertices[static_cast<std::size_t>(o + (k + 1) % n)];
      if (a < 0 || b < 0 || static_cast<std::size_t>(a) >= nv ||
          static_cast<std::size_t>(b) >= nv || a == b) {
        continue;
      }
      if (slot[static_cast<std::size_t>(a)] >= 0) {
        (*ring)[static_cast<std::size_t>(slot[static_cast<std::size_t>(a)])].push_back(b);
      }
      if (slot[static_cast<std::size_t>(b)] >= 0) {
        (*ring)[static_cast<std::size_t>(slot[static_cast<std::size_t>(b)])].push_back(a);
      }
    }
  }
  for (auto& r : *ring) {
    std::sort(r.begin(), r.end());
    r.erase(std::unique(r.begin(), r.end()), r.end());
  }
}

}  // namespace

VertexNoise EstimateVertexNoise(const PolygonMesh& mesh, int max_samples) {
  VertexNoise out;
  const std::size_t nv = mesh.positions.size();
  if (nv == 0 || max_samples <= 0) return out;
  // Sampled vertices, evenly over the vertex order (the stride rounded up: at most
  // max_samples), then the one-rings of those and of their neighbours only.
  const std::size_t samples = static_cast<std::size_t>(max_samples);
  const std::size_t stride = std::max<std::size_t>(1, (nv + samples - 1) / samples);
  std::vector<int> slot(nv, -1);
  std::vector<Index> sampled;
  for (std::size_t v = 0; v < nv; v += stride) {
    slot[v] = static_cast<int>(sampled.size());
    sampled.push_back(static_cast<Index>(v));
  }
  std::vector<std::vector<Index>> ring(sampled.size());
  CollectRings(mesh, slot, &ring);
  std::vector<Index> second;  // the sampled vertices' neighbours that need their own rings
  for (const auto& r : ring) {
    for (Index a : r) {
      if (slot[static_cast<std::size_t>(a)] < 0) {
        slot[static_cast<std::size_t>(a)] = static_cast<int>(sampled.size() + second.size());
        second.push_back(a);
      }
    }
  }
  std::vector<std::vector<Index>> all_rings(sampled.size() + second.size());
  CollectRings(mesh, slot, &all_rings);
  auto ring_of = [&](Index v) -> const std::vector<Index>& {
    return all_rings[static_cast<std::size_t>(slot[static_cast<std::size_t>(v)])];
  };

  std::vector<double> ratio, residual, spacing;
  std::vector<Index> near;
  for (Index v : sampled) {
    const Vec3& p = mesh.positions[static_cast<std::size_t>(v)];
    const std::vector<Index>& one = ring_of(v);
    // The vertex's spacing: its mean edge, over edges of positive length.
    double sum = 0.0;
    int edges = 0;
    for (Index a : one) {
      const double l = glm::length(mesh.positions[static_cast<std::size_t>(a)] - p);
      if (l > 0.0) sum += l, ++edges;
    }
    if (edges == 0 || !std::isfinite(sum)) continue;
    const double h = sum / edges;
    near.clear();
    for (Index a : one) {
      near.push_back(a);
      for (Index b : ring_of(a)) near.push_back(b);
    }
    std::sort(near.begin(), near.end());
    near.erase(std::unique(near.begin(), near.end()), near.end());
    // Leave the vertex out, and any neighbour at its position (a seam the weld missed), which
    // would predict it exactly.
    near.erase(std::remove_if(near.begin(), near.end(),
                              [&](Index a) {
                                return a == v ||
                                       glm::length(mesh.positions[static_cast<std::size_t>(a)] -
                                                   p) <= 1e-9 * h;
                              }),
               near.end());
    if (near.size() < 8) continue;
    // Principal frame of the neighbours.
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
    if (!(radius > 0.0) || !std::isfinite(radius)) continue;
    // Eigenvalues in increasing order: the normal is the least spread direction.
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
    const Eigen::Vector3d n = es.eigenvectors().col(0), u = es.eigenvectors().col(2),
                          w = es.eigenvectors().col(1);
    // Height field h(x, y) = c0 + c1 x + c2 y + c3 x^2 + c4 xy + c5 y^2 (coordinates scaled
    // by the neighbourhood's radius, for conditioning).
    Eigen::MatrixXd m(static_cast<Eigen::Index>(near.size()), 6);
    Eigen::VectorXd z(static_cast<Eigen::Index>(near.size()));
    for (std::size_t i = 0; i < near.size(); ++i) {
      const Vec3& q = mesh.positions[static_cast<std::size_t>(near[i])];
      const Eigen::Vector3d x = Eigen::Vector3d(q.x, q.y, q.z) - c;
      const double s = x.dot(u) / radius, t = x.dot(w) / radius;
      const auto r = static_cast<Eigen::Index>(i);
      m.row(r) << 1.0, s, t, s * s, s * t, t * t;
      z(r) = x.dot(n);
    }
    const Eigen::VectorXd coef = m.colPivHouseholderQr().solve(z);
    const Eigen::Vector3d x = Eigen::Vector3d(p.x, p.y, p.z) - c;
    const double s = x.dot(u) / radius, t = x.dot(w) / radius;
    const double pred =
        coef(0) + coef(1) * s + coef(2) * t + coef(3) * s * s + coef(4) * s * t + coef(5) * t * t;
    const double r = std::abs(x.dot(n) - pred);
    if (!std::isfinite(r)) continue;  // a non-finite position nearby
    residual.push_back(r);
    spacing.push_back(h);
    ratio.push_back(r / h);
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
  out.median_ratio = median(&ratio);
  return out;
}

}  // namespace dermis
