// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Control-vertex positions fitted to the data by linear least squares on the blended domain
// surface (Yoon Eq. 2 and 4 with d = 0; docs/fitting.md "Control-vertex fit"). The surface is
// linear in the control positions at a fixed parameter, so one step is a sparse symmetric
// solve (Eigen's SimplicialLDLT) of the normal equations, assembled face by face. Residuals are
// weighted mostly across the surface (tangent-distance minimisation, Wang, Pottmann and Liu
// 2006), which couples a vertex's three coordinates: the unknowns are 3 per vertex.
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
  // Exponents 0..2 (kPatchMonomials): products, not std::pow.
  const double xs[3] = {1.0, z.x, z.x * z.x}, ys[3] = {1.0, z.y, z.y * z.y};
  double mono[8];
  for (int m = 0; m < 8; ++m) mono[m] = xs[kPatchMonomials[m][0]] * ys[kPatchMonomials[m][1]];
  double centre = 1.0;
  for (int k = 0; k < n; ++k) {
    double c = 0.0;
    for (int m = 0; m < 8; ++m) c += mono[m] * op[m * n + k];
    centre -= c;
    out->emplace_back(ring[k], weight * c);
  }
  out->emplace_back(v, weight * centre);
}

// Appends the domain surface at (face, uv) as DomainSurfaceStencil() does, and tells where each
// active corner's terms end in *out (corner_end) and the corner's blend weight psi_a, by which
// those terms are already multiplied.
bool CornerStencils(const ManifoldDomain& domain, Index face, Vec2 uv,
                    std::vector<std::pair<Index, double>>* out, int* num_corners,
                    std::size_t corner_end[4], double corner_weight[4]) {
  *num_corners = 0;
  if (!ClampFaceCoordinates(domain, face, &uv)) return false;
  const MeshTopology& topo = domain.topology();
  const Index base = topo.face_offset(face);
  const double lb = domain.options().blend_lb;
  const double ub = 1.0 - lb;
  // The same corner weights and charts as EvaluateSurface(), including its one-chart shortcut.
  const int dominant = DominantCorner(uv);
  const Vec2 cd_dom = FaceToCorner(dominant, uv);
  const bool one_chart = cd_dom.x <= lb && cd_dom.y <= lb;
  double weights[4] = {1.0, 1.0, 1.0, 1.0};
  if (!one_chart) FaceCornerWeights(domain.options().blend_type, lb, uv, weights);
  for (int a = 0; a < 4; ++a) {
    if (one_chart && a != dominant) continue;
    const Vec2 cd = FaceToCorner(a, uv);
    if (!one_chart && (cd.x >= ub || cd.y >= ub)) continue;
    const double psi = weights[a];
    const Index h = base + a;
    const Index v = topo.halfedge_origin(h);
    Vec2 z;
    ChartMap(domain.chart(v), topo.halfedge_ring_index(h), cd, &z);
    AppendPatchStencil(domain, v, z, psi, out);
    corner_end[*num_corners] = out->size();
    corner_weight[(*num_corners)++] = psi;
  }
  return true;
}

}  // namespace

bool DomainSurfaceStencil(const ManifoldDomain& domain, Index face, Vec2 uv,
                          std::vector<std::pair<Index, double>>* out) {
  int nc = 0;
  std::size_t end[4];
  double w[4];
  return CornerStencils(domain, face, uv, out, &nc, end, w);
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

// One face's share of the normal equations: the distinct vertices of its stencils (sorted), a
// dense block over their coordinates ((3 vertices)^2, row-major, unknown 3i + c is coordinate c
// of vertex i; only the upper triangle is filled) and the right-hand sides (3 per vertex).
struct FaceBlock {
  std::vector<Index> vertices;
  std::vector<double> ata;
  std::vector<double> atb;
  std::vector<double> agree;  // (vertices)^2, upper triangle: the patch-agreement term (scalar)
};

// The blocks of every face, each accumulated over the face's points in order (parallel over
// faces), each point weighted by its robust weight. A point's residual r = Q(z) - p is
// measured as r^T M r, M = t I + (1 - t) n n^T (n the domain surface's unit normal at z, t the
// tangent weight): t = 1 is the point distance, t < 1 lets the surface slide along itself
// (in faces with a boundary vertex t = 1).
std::vector<FaceBlock> FaceBlocks(const ManifoldDomain& domain, const std::vector<Vec3>& points,
                                  const std::vector<PointFit>& fits,
                                  const std::vector<Vec3>& normals,
                                  const std::vector<std::size_t>& start,
                                  const std::vector<std::size_t>& order,
                                  const std::vector<double>& residual, double cutoff,
                                  double tangent_weight, double agreement, int threads) {
  const Index nf = domain.num_faces();
  std::vector<FaceBlock> blocks(static_cast<std::size_t>(nf));
  ParallelFor(threads, static_cast<std::size_t>(nf), [&](std::size_t b, std::size_t e) {
    std::vector<std::pair<Index, double>> st;
    std::vector<double> row;
    std::vector<std::size_t> nonzero;
    std::vector<double> scalar;
    std::vector<double> corner_rows;
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
      const std::size_t m3 = 3 * m;
      blk.ata.assign(m3 * m3, 0.0);
      blk.atb.assign(m3, 0.0);
      scalar.assign(m * m, 0.0);
      row.assign(m, 0.0);
      if (agreement > 0.0) blk.agree.assign(m * m, 0.0);
      // Beside a boundary the residual keeps its tangent part: sliding along the surface there
      // would let the boundary of the domain surface retract from the data's.
      const double tw =
          domain.topology().face_touches_boundary(static_cast<Index>(face)) ? 1.0 : tangent_weight;
      for (std::size_t k = start[face]; k < start[face + 1]; ++k) {
        const PointFit& f = fits[order[k]];
        st.clear();
        int nc = 0;
        std::size_t cend[4];
        double cw[4];
        CornerStencils(domain, f.face, f.uv, &st, &nc, cend, cw);
        std::fill(row.begin(), row.end(), 0.0);
        const bool agree = agreement > 0.0 && nc > 1;
        if (agree) corner_rows.assign(static_cast<std::size_t>(nc) * m, 0.0);
        int corner = 0;
        for (std::size_t t = 0; t < st.size(); ++t) {
          while (corner < nc && t >= cend[corner]) ++corner;
          const auto& [v, w] = st[t];
          const auto it = std::lower_bound(blk.vertices.begin(), blk.vertices.end(), v);
          const std::size_t i = static_cast<std::size_t>(it - blk.vertices.begin());
          row[i] += w;
          if (agree && cw[corner] > 0.0) {
            corner_rows[static_cast<std::size_t>(corner) * m + i] += w / cw[corner];
          }
        }
        if (agree) {
          // sum_a psi_a |P_a(z_a) - Q(z)|^2: each corner patch's distance from the blend.
          for (int a = 0; a < nc; ++a) {
            double* ca = corner_rows.data() + static_cast<std::size_t>(a) * m;
            for (std::size_t i = 0; i < m; ++i) ca[i] -= row[i];
            const double wa = agreement * cw[a];
            for (std::size_t i = 0; i < m; ++i) {
              if (ca[i] == 0.0) continue;
              double* arow = blk.agree.data() + i * m;
              for (std::size_t j = i; j < m; ++j) arow[j] += wa * ca[i] * ca[j];
            }
          }
        }
        nonzero.clear();
        for (std::size_t i = 0; i < m; ++i) {
          if (row[i] != 0.0) nonzero.push_back(i);
        }
        const double r = residual[k];
        const double weight = r > cutoff ? (cutoff / r) * (cutoff / r) : 1.0;
        const Vec3& p = points[order[k]];
        const Vec3& n = normals[k];
        // w^T M w with M = t I + (1 - t) n n^T: the scalar t part on the vertex pairs, and the
        // rank-one part (w (x) n)(w (x) n)^T on the coordinates, both on the upper triangle.
        const double wt = weight * tw;
        const double wn = weight * (1.0 - tw);
        const double np = glm::dot(n, p);
        for (std::size_t a = 0; a < nonzero.size(); ++a) {
          const std::size_t i = nonzero[a];
          double* srow = scalar.data() + i * m;
          for (std::size_t q = a; q < nonzero.size(); ++q) {
            srow[nonzero[q]] += wt * row[i] * row[nonzero[q]];
          }
          for (int c = 0; c < 3; ++c) {
            const double ui = wn * row[i] * n[c];
            blk.atb[3 * i + static_cast<std::size_t>(c)] += row[i] * (wt * p[c] + wn * n[c] * np);
            double* out = blk.ata.data() + (3 * i + static_cast<std::size_t>(c)) * m3;
            for (int d = c; d < 3; ++d)
              out[3 * i + static_cast<std::size_t>(d)] += ui * row[i] * n[d];
            for (std::size_t q = a + 1; q < nonzero.size(); ++q) {
              const std::size_t j = nonzero[q];
              const double uij = ui * row[j];
              out[3 * j] += uij * n.x, out[3 * j + 1] += uij * n.y, out[3 * j + 2] += uij * n.z;
            }
          }
        }
      }
      // The scalar part on every coordinate (upper triangle only: SolveDamped() reads that).
      for (std::size_t i = 0; i < m; ++i) {
        for (std::size_t j = i; j < m; ++j) {
          for (int c = 0; c < 3; ++c) {
            blk.ata[(3 * i + static_cast<std::size_t>(c)) * m3 + 3 * j +
                    static_cast<std::size_t>(c)] += scalar[i * m + j];
          }
        }
      }
    }
  });
  return blocks;
}

// The normal equations' lower triangle, 3 x 3 blocks per pair of vertices that share a face
// block, summed in face order (so the sums do not depend on the thread count).
class BlockLower {
 public:
  // The pattern: column vertex j holds the row vertices i >= j of every block containing both.
  BlockLower(const std::vector<FaceBlock>& blocks, Index nv)
      : start_(static_cast<std::size_t>(nv) + 1, 0) {
    std::vector<std::vector<Index>> rows(static_cast<std::size_t>(nv));
    for (Index v = 0; v < nv; ++v) rows[static_cast<std::size_t>(v)].push_back(v);
    for (const FaceBlock& blk : blocks) {
      // blk.vertices is sorted: for the column vertices[q] the rows are vertices[q..].
      for (std::size_t q = 0; q < blk.vertices.size(); ++q) {
        auto& r = rows[static_cast<std::size_t>(blk.vertices[q])];
        r.insert(r.end(), blk.vertices.begin() + static_cast<std::ptrdiff_t>(q),
                 blk.vertices.end());
      }
    }
    for (Index v = 0; v < nv; ++v) {
      auto& r = rows[static_cast<std::size_t>(v)];
      std::sort(r.begin(), r.end());
      r.erase(std::unique(r.begin(), r.end()), r.end());
      start_[static_cast<std::size_t>(v) + 1] = start_[static_cast<std::size_t>(v)] + r.size();
      row_.insert(row_.end(), r.begin(), r.end());
    }
    values_.assign(9 * row_.size(), 0.0);
  }

  // The 3 x 3 block (row vertex i, column vertex j), i >= j; column-major inside.
  double* Block(Index i, Index j) {
    const auto b = row_.begin() + static_cast<std::ptrdiff_t>(start_[static_cast<std::size_t>(j)]);
    const auto e =
        row_.begin() + static_cast<std::ptrdiff_t>(start_[static_cast<std::size_t>(j) + 1]);
    return values_.data() + 9 * static_cast<std::size_t>(std::lower_bound(b, e, i) - row_.begin());
  }

  // The lower triangle as a compressed column-major matrix, leaving out exact zeros.
  void ToSparse(Eigen::SparseMatrix<double>* out) const {
    const Index nv = static_cast<Index>(start_.size()) - 1;
    std::vector<int> outer(3 * static_cast<std::size_t>(nv) + 1, 0);
    std::vector<int> inner;
    std::vector<double> values;
    inner.reserve(9 * row_.size());
    values.reserve(9 * row_.size());
    for (Index j = 0; j < nv; ++j) {
      for (int d = 0; d < 3; ++d) {
        for (std::size_t s = start_[static_cast<std::size_t>(j)];
             s < start_[static_cast<std::size_t>(j) + 1]; ++s) {
          const Index i = row_[s];
          for (int c = i == j ? d : 0; c < 3; ++c) {
            const double a = values_[9 * s + static_cast<std::size_t>(3 * d + c)];
            if (a == 0.0) continue;
            inner.push_back(static_cast<int>(3 * i + c));
            values.push_back(a);
          }
        }
        outer[static_cast<std::size_t>(3 * j + d) + 1] = static_cast<int>(inner.size());
      }
    }
    const Eigen::Index n = 3 * static_cast<Eigen::Index>(nv);
    out->resize(n, n);
    out->resizeNonZeros(static_cast<Eigen::Index>(inner.size()));
    std::copy(outer.begin(), outer.end(), out->outerIndexPtr());
    std::copy(inner.begin(), inner.end(), out->innerIndexPtr());
    std::copy(values.begin(), values.end(), out->valuePtr());
  }

 private:
  std::vector<std::size_t> start_;  // per column vertex, into row_
  std::vector<Index> row_;          // row vertices, ascending per column
  std::vector<double> values_;      // 9 per (row, column) pair
};

// Assembles the blocks in face order, damps every vertex towards its current position in
// proportion to its data weight (more along the surface than across it, `vertex_normals` the
// unit normals, empty: the same in every direction), and solves (SimplicialLDLT over the 3 nv
// coordinates, lower triangle); writes the new positions.
Status SolveDamped(const std::vector<FaceBlock>& blocks, const ControlFitOptions& options,
                   const std::vector<Vec3>& vertex_normals, std::vector<Vec3>* positions) {
  const Index nv = static_cast<Index>(positions->size());
  BlockLower lower(blocks, nv);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(3 * static_cast<Eigen::Index>(nv));
  std::vector<double> diagonal(static_cast<std::size_t>(nv), 0.0);
  for (const FaceBlock& blk : blocks) {
    const std::size_t m = blk.vertices.size();
    const std::size_t m3 = 3 * m;
    for (std::size_t q = 0; q < m; ++q) {    // column vertex
      for (std::size_t p = q; p < m; ++p) {  // row vertex
        // Entry (row 3p + c, column 3q + d) from the block's upper triangle.
        double* out = lower.Block(blk.vertices[p], blk.vertices[q]);
        for (int d = 0; d < 3; ++d) {
          for (int c = p == q ? d : 0; c < 3; ++c) {
            out[3 * d + c] += blk.ata[(3 * q + static_cast<std::size_t>(d)) * m3 + 3 * p +
                                      static_cast<std::size_t>(c)];
          }
        }
        if (blk.agree.empty()) continue;
        // The patch-agreement term: the same scalar on each coordinate; not part of the data
        // weight the damping scales with.
        const double a = blk.agree[q * m + p];
        for (int c = 0; c < 3; ++c) out[4 * c] += a;
      }
    }
    for (std::size_t i = 0; i < m3; ++i) {
      // A vertex's data weight: the mean of its three diagonal entries.
      diagonal[static_cast<std::size_t>(blk.vertices[i / 3])] += blk.ata[i * m3 + i] / 3.0;
      rhs(3 * blk.vertices[i / 3] + static_cast<Index>(i % 3)) += blk.atb[i];
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
    const Vec3& x = (*positions)[v];
    // Along the surface (across the vertex normal n) the pull is at least tangent_damping of
    // the data weight: mt I + (mu - mt) n n^T.
    const double mt = std::max(options.tangent_damping * diagonal[static_cast<std::size_t>(v)], mu);
    const Vec3 n = vertex_normals.empty() ? Vec3(0.0) : vertex_normals[static_cast<std::size_t>(v)];
    double* out = lower.Block(v, v);
    for (int c = 0; c < 3; ++c) {
      for (int d = 0; d < 3; ++d) {
        const double a = (c == d ? mt : 0.0) + (mu - mt) * n[c] * n[d];
        out[3 * d + c] += a;
        rhs(3 * v + c) += a * x[d];
      }
    }
  }
  Eigen::SparseMatrix<double> ata;
  lower.ToSparse(&ata);
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> solver(ata);
  if (solver.info() != Eigen::Success) {
    return Status::InvalidInput("control fit: the normal equations could not be factored");
  }
  const Eigen::VectorXd x = solver.solve(rhs);
  if (solver.info() != Eigen::Success || !x.allFinite()) {
    return Status::InvalidInput("control fit: the normal equations could not be solved");
  }
  for (Index v = 0; v < nv; ++v) (*positions)[v] = Vec3(x(3 * v), x(3 * v + 1), x(3 * v + 2));
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
  // The domain surface's normal at each point's parameter and each vertex's one-ring normal
  // (needed only where the residual or the damping depends on the direction).
  std::vector<Vec3> normals(order.size(), Vec3(0.0, 0.0, 1.0));
  std::vector<Vec3> vertex_normals;
  const double tangent_weight = std::clamp(options.tangent_weight, 0.0, 1.0);
  if (tangent_weight < 1.0 || options.tangent_damping > options.damping) {
    std::vector<LocalPatch> patches(static_cast<std::size_t>(nv));
    domain.FitPatches(positions->data(), patches.data());
    for (const LocalPatch& lp : patches) vertex_normals.push_back(lp.fallback_normal);
    ParallelFor(threads, order.size(), [&](std::size_t b, std::size_t e) {
      for (std::size_t k = b; k < e; ++k) {
        const PointFit& f = fits[order[k]];
        SurfacePoint sp;
        if (EvaluateSurface(domain, patches.data(), nullptr, f.face, f.uv, &sp)) {
          normals[k] = sp.normal;
        }
      }
    });
  }
  const std::vector<FaceBlock> blocks =
      FaceBlocks(domain, points, fits, normals, start, order, residual, cutoff, tangent_weight,
                 options.patch_agreement, threads);
  return SolveDamped(blocks, options, vertex_normals, positions);
}

}  // namespace dermis
