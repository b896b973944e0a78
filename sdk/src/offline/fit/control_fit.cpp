// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Control-vertex positions fitted to the data by linear least squares on the blended domain
// surface (Yoon Eq. 2 and 4 with d = 0; docs/fitting.md "Control-vertex fit"). The surface is
// linear in the control positions at a fixed parameter, so one step is a sparse symmetric
// solve (Eigen's SimplicialLDLT) of the normal equations, assembled face by face.
#include "dermis/offline/fit/control_fit.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <limits>

#include "dermis/core/parallel.h"
#include "dermis/surface/blend.h"
#include "dermis/surface/chart.h"
#include "dermis/surface/surface_evaluator.h"

namespace dermis {
namespace {

// Appends weight * P_v(z) as a combination of control positions: P_v(z) = X_v + sum_m z^m
// sum_k op[m][k] (X_ring_k - X_v) (ManifoldDomain::FitPatch).
void AppendPatchStencil(const ManifoldDomain& domain, Index v, Vec2 z, double weight,
                        std::vector<std::pair<Index, double>>* out) {
  const int n = domain.patch_ring_size(v);
  const Index* ring = domain.patch_ring(v);
  const double* op = domain.patch_operator(v);
  double mono[8];
  for (int m = 0; m < 8; ++m) {
    mono[m] = std::pow(z.x, kPatchMonomials[m][0]) * std::pow(z.y, kPatchMonomials[m][1]);
  }
  double centre = 1.0;
  for (int k = 0; k < n; ++k) {
    double c = 0.0;
    for (int m = 0; m < 8; ++m) c += mono[m] * op[m * n + k];
    centre -= c;
    out->emplace_back(ring[k], weight * c);
  }
  out->emplace_back(v, weight * centre);
}

}  // namespace

bool DomainSurfaceStencil(const ManifoldDomain& domain, Index face, Vec2 uv,
                          std::vector<std::pair<Index, double>>* out) {
  if (!ClampFaceCoordinates(domain, face, &uv)) return false;
  const MeshTopology& topo = domain.topology();
  const Index base = topo.face_offset(face);
  const double lb = domain.options().blend_lb;
  const double ub = 1.0 - lb;
  // The same corner weights and charts as EvaluateSurface(), including its one-chart shortcut.
  const int dominant = DominantCorner(uv);
  const Vec2 cd_dom = FaceToCorner(dominant, uv);
  const bool one_chart = cd_dom.x <= lb && cd_dom.y <= lb;
  for (int a = 0; a < 4; ++a) {
    if (one_chart && a != dominant) continue;
    const Vec2 cd = FaceToCorner(a, uv);
    if (!one_chart && (cd.x >= ub || cd.y >= ub)) continue;
    const double psi = one_chart ? 1.0 : CornerWeight(domain.options().blend_type, lb, cd);
    const Index h = base + a;
    const Index v = topo.halfedge_origin(h);
    Vec2 z;
    ChartMap(domain.chart(v), topo.halfedge_ring_index(h), cd, &z);
    AppendPatchStencil(domain, v, z, psi, out);
  }
  return true;
}

namespace {

// Points grouped by face (stable), so each face's block is accumulated in point order: the
// points of face f are order[start[f] .. start[f + 1]). Points outside every chart are left out.
void GroupByFace(const std::vector<PointFit>& fits, Index nf, std::vector<std::size_t>* start,
                 std::vector<std::size_t>* order) {
  start->assign(static_cast<std::size_t>(nf) + 1, 0);
  for (const PointFit& f : fits) {
    if (f.status != PointFitStatus::kOutside && f.face >= 0 && f.face < nf) ++(*start)[f.face + 1];
  }
  for (Index f = 0; f < nf; ++f) (*start)[f + 1] += (*start)[f];
  order->assign(start->back(), 0);
  std::vector<std::size_t> next(start->begin(), start->end() - 1);
  for (std::size_t i = 0; i < fits.size(); ++i) {
    const PointFit& f = fits[i];
    if (f.status != PointFitStatus::kOutside && f.face >= 0 && f.face < nf) {
      (*order)[next[f.face]++] = i;
    }
  }
}

// |D(z_k) - p_k| at the current positions, in `order`.
std::vector<double> Residuals(const ManifoldDomain& domain, const std::vector<Vec3>& points,
                              const std::vector<PointFit>& fits,
                              const std::vector<std::size_t>& order,
                              const std::vector<Vec3>& positions, int threads) {
  std::vector<double> residual(order.size(), 0.0);
  ParallelFor(threads, order.size(), [&](std::size_t b, std::size_t e) {
    std::vector<std::pair<Index, double>> st;
    for (std::size_t k = b; k < e; ++k) {
      const PointFit& f = fits[order[k]];
      st.clear();
      DomainSurfaceStencil(domain, f.face, f.uv, &st);
      Vec3 q(0.0);
      for (const auto& [v, w] : st) q += w * positions[v];
      const Vec3 r = q - points[order[k]];
      residual[k] = std::sqrt(glm::dot(r, r));
    }
  });
  return residual;
}

// The residual beyond which a point's weight falls off: robust_cutoff times the median, with a
// floor relative to the data's size (data already on the surface, median ~ 0, must not
// down-weight every other point to nothing). Infinite when there is no robust weighting.
double RobustCutoff(const std::vector<double>& residual, const std::vector<Vec3>& points,
                    double robust_cutoff) {
  if (residual.empty() || !(robust_cutoff > 0.0)) return std::numeric_limits<double>::infinity();
  std::vector<double> sorted = residual;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2),
                   sorted.end());
  Vec3 lo(std::numeric_limits<double>::infinity()), hi(-lo);
  for (const Vec3& p : points) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const Vec3 ext = hi - lo;
  const double size = std::max(ext.x, std::max(ext.y, ext.z));
  return robust_cutoff * std::max(sorted[sorted.size() / 2], 1e-9 * size);
}

// One face's share of the normal equations: the distinct vertices of its stencils, a dense
// block (vertices^2, row-major) and the right-hand sides (3 per vertex).
struct FaceBlock {
  std::vector<Index> vertices;
  std::vector<double> ata;
  std::vector<double> atb;
};

// The blocks of every face, each accumulated over the face's points in order (parallel over
// faces), each point weighted by its robust weight.
std::vector<FaceBlock> FaceBlocks(const ManifoldDomain& domain, const std::vector<Vec3>& points,
                                  const std::vector<PointFit>& fits,
                                  const std::vector<std::size_t>& start,
                                  const std::vector<std::size_t>& order,
                                  const std::vector<double>& residual, double cutoff, int threads) {
  const Index nf = domain.num_faces();
  std::vector<FaceBlock> blocks(static_cast<std::size_t>(nf));
  ParallelFor(threads, static_cast<std::size_t>(nf), [&](std::size_t b, std::size_t e) {
    std::vector<std::pair<Index, double>> st;
    std::vector<double> row;
    for (std::size_t face = b; face < e; ++face) {
      if (start[face] == start[face + 1]) continue;
      FaceBlock& blk = blocks[face];
      // The vertices any point of this face can touch: the stencil at the face centre has
      // every corner's patch ring.
      st.clear();
      for (int a = 0; a < 4; ++a) {
        const Index v = domain.topology().face_vertex(static_cast<Index>(face), a);
        blk.vertices.push_back(v);
        const Index* ring = domain.patch_ring(v);
        blk.vertices.insert(blk.vertices.end(), ring, ring + domain.patch_ring_size(v));
      }
      std::sort(blk.vertices.begin(), blk.vertices.end());
      blk.vertices.erase(std::unique(blk.vertices.begin(), blk.vertices.end()), blk.vertices.end());
      const std::size_t m = blk.vertices.size();
      blk.ata.assign(m * m, 0.0);
      blk.atb.assign(3 * m, 0.0);
      row.assign(m, 0.0);
      for (std::size_t k = start[face]; k < start[face + 1]; ++k) {
        const PointFit& f = fits[order[k]];
        st.clear();
        DomainSurfaceStencil(domain, f.face, f.uv, &st);
        std::fill(row.begin(), row.end(), 0.0);
        for (const auto& [v, w] : st) {
          const auto it = std::lower_bound(blk.vertices.begin(), blk.vertices.end(), v);
          row[static_cast<std::size_t>(it - blk.vertices.begin())] += w;
        }
        const double r = residual[k];
        const double weight = r > cutoff ? (cutoff / r) * (cutoff / r) : 1.0;
        const Vec3& p = points[order[k]];
        for (std::size_t i = 0; i < m; ++i) {
          if (row[i] == 0.0) continue;
          const double wi = weight * row[i];
          for (std::size_t j = 0; j < m; ++j) blk.ata[i * m + j] += wi * row[j];
          blk.atb[3 * i] += wi * p.x, blk.atb[3 * i + 1] += wi * p.y,
              blk.atb[3 * i + 2] += wi * p.z;
        }
      }
    }
  });
  return blocks;
}

// Assembles the blocks in face order, damps every vertex towards its current position in
// proportion to its data weight, and solves (SimplicialLDLT); writes the new positions.
Status SolveDamped(const std::vector<FaceBlock>& blocks, const ControlFitOptions& options,
                   std::vector<Vec3>* positions) {
  const Index nv = static_cast<Index>(positions->size());
  std::vector<Eigen::Triplet<double>> triplets;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(nv, 3);
  std::vector<double> diagonal(static_cast<std::size_t>(nv), 0.0);
  for (const FaceBlock& blk : blocks) {
    const std::size_t m = blk.vertices.size();
    for (std::size_t i = 0; i < m; ++i) {
      for (std::size_t j = 0; j < m; ++j) {
        const double a = blk.ata[i * m + j];
        if (a != 0.0) triplets.emplace_back(blk.vertices[i], blk.vertices[j], a);
      }
      diagonal[static_cast<std::size_t>(blk.vertices[i])] += blk.ata[i * m + i];
      for (int c = 0; c < 3; ++c) {
        rhs(blk.vertices[i], c) += blk.atb[3 * i + static_cast<std::size_t>(c)];
      }
    }
  }
  double mean_diag = 0.0;
  for (double d : diagonal) mean_diag += d;
  mean_diag = nv > 0 ? mean_diag / nv : 0.0;
  if (!(mean_diag > 0.0)) return Status::InvalidInput("control fit: no data on the surface");
  for (Index v = 0; v < nv; ++v) {
    // A floor of a hundredth of the mean keeps vertices with little data well conditioned.
    const double mu =
        std::max(options.damping * diagonal[static_cast<std::size_t>(v)], 0.01 * mean_diag);
    triplets.emplace_back(v, v, mu);
    const Vec3& x = (*positions)[v];
    rhs(v, 0) += mu * x.x, rhs(v, 1) += mu * x.y, rhs(v, 2) += mu * x.z;
  }
  Eigen::SparseMatrix<double> ata(nv, nv);
  ata.setFromTriplets(triplets.begin(), triplets.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(ata);
  if (solver.info() != Eigen::Success) {
    return Status::InvalidInput("control fit: the normal equations could not be factored");
  }
  const Eigen::MatrixXd x = solver.solve(rhs);
  if (solver.info() != Eigen::Success || !x.allFinite()) {
    return Status::InvalidInput("control fit: the normal equations could not be solved");
  }
  for (Index v = 0; v < nv; ++v) (*positions)[v] = Vec3(x(v, 0), x(v, 1), x(v, 2));
  return Status::Ok();
}

}  // namespace

Status FitControlPositions(const ManifoldDomain& domain, const std::vector<Vec3>& points,
                           const std::vector<PointFit>& fits, const ControlFitOptions& options,
                           std::vector<Vec3>* positions) {
  const Index nv = domain.num_vertices();
  const Index nf = domain.num_faces();
  if (static_cast<Index>(positions->size()) != nv || fits.size() != points.size()) {
    return Status::InvalidInput("control fit: sizes of positions, points and fits disagree");
  }
  std::vector<std::size_t> start, order;
  GroupByFace(fits, nf, &start, &order);
  const int threads = ResolveThreadCount(options.threads);
  const std::vector<double> residual = Residuals(domain, points, fits, order, *positions, threads);
  const double cutoff = RobustCutoff(residual, points, options.robust_cutoff);
  const std::vector<FaceBlock> blocks =
      FaceBlocks(domain, points, fits, start, order, residual, cutoff, threads);
  return SolveDamped(blocks, options, positions);
}

}  // namespace dermis
