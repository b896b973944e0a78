// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Yoon Eq. 2 as a linear operator: constrained least squares P(0) = v over the one-ring chart
// positions (docs/notes/manifold.md section 5), made unique in rank-deficient cases by the smallest
// thin-plate energy among all least-squares minimisers (our choice; docs/math.md).
#include "dermis/offline/build/patch_fit_operator.h"

#include <Eigen/Dense>
#include <cmath>
#include <string>

#include "dermis/surface/local_patch.h"

namespace dermis {
namespace {

double Pow(double x, int k) { return k == 0 ? 1.0 : (k == 1 ? x : x * x); }

// Second derivatives of the 8 monomials at (x, y).
void MonomialHessians(double x, double y, Eigen::Matrix<double, 8, 1>* mxx,
                      Eigen::Matrix<double, 8, 1>* mxy, Eigen::Matrix<double, 8, 1>* myy) {
  for (int j = 0; j < 8; ++j) {
    const int a = kPatchMonomials[j][0], b = kPatchMonomials[j][1];
    (*mxx)(j) = a == 2 ? 2.0 * Pow(y, b) : 0.0;
    (*myy)(j) = b == 2 ? 2.0 * Pow(x, a) : 0.0;
    const double dx = a == 0 ? 0.0 : (a == 1 ? 1.0 : 2.0 * x);
    const double dy = b == 0 ? 0.0 : (b == 1 ? 1.0 : 2.0 * y);
    (*mxy)(j) = dx * dy;
  }
}

// Gram matrix of the thin-plate energy over the sector {r <= radius, 0 <= theta <= sector}.
Eigen::Matrix<double, 8, 8> ThinPlateGram(double radius, double sector) {
  // 6-point Gauss-Legendre in r (exact for the polynomial radial factors here), midpoint rule in
  // theta (exact for the trigonometric polynomials of degree < 64 on the full circle).
  static const double kNodes[6] = {-0.9324695142031521, -0.6612093864662645, -0.2386191860831969,
                                   0.2386191860831969,  0.6612093864662645,  0.9324695142031521};
  static const double kWeights[6] = {0.1713244923791704, 0.3607615730481386, 0.4679139345726910,
                                     0.4679139345726910, 0.3607615730481386, 0.1713244923791704};
  const int num_angles = 64;
  Eigen::Matrix<double, 8, 8> h = Eigen::Matrix<double, 8, 8>::Zero();
  Eigen::Matrix<double, 8, 1> mxx, mxy, myy;
  for (int i = 0; i < 6; ++i) {
    const double r = 0.5 * radius * (kNodes[i] + 1.0);
    const double wr = 0.5 * radius * kWeights[i] * r;
    for (int k = 0; k < num_angles; ++k) {
      const double theta = sector * (k + 0.5) / num_angles;
      const double w = wr * sector / num_angles;
      MonomialHessians(r * std::cos(theta), r * std::sin(theta), &mxx, &mxy, &myy);
      h += w * (mxx * mxx.transpose() + 2.0 * mxy * mxy.transpose() + myy * myy.transpose());
    }
  }
  return h;
}

}  // namespace

std::vector<Vec2> PatchRingChartPositions(const ChartParams& chart) {
  std::vector<Vec2> z;
  z.reserve(2 * chart.valence + 1);
  for (int f = 0; f < chart.valence; ++f) {
    Vec2 e, d;
    ChartMap(chart, f, Vec2(1.0, 0.0), &e);
    ChartMap(chart, f, Vec2(1.0, 1.0), &d);
    z.push_back(e);
    z.push_back(d);
  }
  if (chart.kind != VertexKind::kInterior) {
    Vec2 e;
    ChartMap(chart, chart.valence - 1, Vec2(0.0, 1.0), &e);
    z.push_back(e);
  }
  return z;
}

Status ComputePatchFitOperator(const ChartParams& chart, std::vector<double>* op, int* rank) {
  const std::vector<Vec2> z = PatchRingChartPositions(chart);
  const int n = static_cast<int>(z.size());
  Eigen::MatrixXd m(n, 8);  // monomials at the ring's chart positions
  double radius = 0.0;
  for (int r = 0; r < n; ++r) {
    for (int j = 0; j < 8; ++j) {
      m(r, j) = Pow(z[r].x, kPatchMonomials[j][0]) * Pow(z[r].y, kPatchMonomials[j][1]);
    }
    radius = std::max(radius, std::sqrt(z[r].x * z[r].x + z[r].y * z[r].y));
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(m, Eigen::ComputeFullV | Eigen::ComputeThinU);
  const Eigen::VectorXd& sigma = svd.singularValues();
  const double tol = 1e-10 * (sigma.size() > 0 ? sigma(0) : 0.0);
  int r = 0;
  while (r < sigma.size() && sigma(r) > tol) ++r;
  if (r == 0) return Status::Internal("patch fit: the ring positions are degenerate");
  // Minimum-norm least-squares solution operator M^+ (8 x n).
  Eigen::MatrixXd pinv = svd.matrixV().leftCols(r) * sigma.head(r).cwiseInverse().asDiagonal() *
                         svd.matrixU().leftCols(r).transpose();
  if (r < 8) {
    // Among all minimisers c0 + N y pick the one of least thin-plate energy:
    // y = -(N^T H N)^{-1} N^T H c0.
    const Eigen::MatrixXd null = svd.matrixV().rightCols(8 - r);
    const Eigen::Matrix<double, 8, 8> h = ThinPlateGram(radius, chart.sector);
    const Eigen::MatrixXd g = null.transpose() * h * null;
    Eigen::LDLT<Eigen::MatrixXd> ldlt(g);
    if (ldlt.info() != Eigen::Success || !ldlt.isPositive() ||
        ldlt.vectorD().minCoeff() <= 1e-12 * ldlt.vectorD().maxCoeff()) {
      return Status::Internal("patch fit: the thin-plate regulariser does not fix the null space");
    }
    const Eigen::MatrixXd correction = null * ldlt.solve(null.transpose() * h);
    pinv = (Eigen::MatrixXd::Identity(8, 8) - correction) * pinv;
  }
  op->assign(static_cast<size_t>(8 * n), 0.0);
  for (int row = 0; row < 8; ++row)
    for (int col = 0; col < n; ++col) (*op)[row * n + col] = pinv(row, col);
  if (rank) *rank = r;
  return Status::Ok();
}

Status ComputeSeamPatchFitOperator(const ChartParams& chart, SeamMode mode, std::vector<double>* op,
                                   int* rank) {
  if (mode == SeamMode::kNone) return ComputePatchFitOperator(chart, op, rank);
  if (chart.kind == VertexKind::kInterior) {
    return Status::InvalidInput("seam patch fit: an interior chart has no boundary rays");
  }
  const std::vector<Vec2> z = PatchRingChartPositions(chart);
  const int n = static_cast<int>(z.size());
  const int i1 = 0, i2 = n - 1;  // the boundary neighbours
  // Each ray's axis (0: x, 1: y) and sign; the monomials of kPatchMonomials: x, y, x^2, xy,
  // y^2, x^2 y, x y^2, x^2 y^2.
  int axis[2], sign[2];
  for (int r = 0; r < 2; ++r) {
    const Vec2 u = z[r == 0 ? i1 : i2];
    if (std::abs(std::abs(u.x) - 1.0) < 1e-9 && std::abs(u.y) < 1e-9) {
      axis[r] = 0, sign[r] = u.x > 0.0 ? 1 : -1;
    } else if (std::abs(std::abs(u.y) - 1.0) < 1e-9 && std::abs(u.x) < 1e-9) {
      axis[r] = 1, sign[r] = u.y > 0.0 ? 1 : -1;
    } else {
      return Status::Internal("seam patch fit: a boundary neighbour is off the chart's axes");
    }
  }
  if (mode == SeamMode::kCorner && axis[0] == axis[1]) {
    return Status::InvalidInput("seam patch fit: a corner needs its rays on two axes");
  }
  const int lin[2] = {0, 1}, quad[2] = {2, 4};
  // Fixed coefficients as rows over the ring deltas.
  Eigen::MatrixXd fixed = Eigen::MatrixXd::Zero(8, n);
  bool is_fixed[8] = {false, false, false, false, false, false, false, false};
  for (int r = 0; r < 2; ++r) {
    const int a = axis[r], i = r == 0 ? i1 : i2;
    Eigen::RowVectorXd line = Eigen::RowVectorXd::Zero(n), curve = Eigen::RowVectorXd::Zero(n);
    if (mode == SeamMode::kSmooth) {
      // Q(t) = v + a t + b t^2, t = +1 at the first neighbour and -1 at the second: a =
      // (d1 - d2) / 2, b = (d1 + d2) / 2; ray r runs towards t = +1 (r = 0) or -1 (r = 1).
      const double towards = r == 0 ? 1.0 : -1.0;
      line(i1) = 0.5 * towards, line(i2) = -0.5 * towards;
      curve(i1) = 0.5, curve(i2) = 0.5;
    } else {
      line(i) = 1.0;
    }
    fixed.row(lin[a]) = sign[r] * line;
    fixed.row(quad[a]) = curve;
    is_fixed[lin[a]] = is_fixed[quad[a]] = true;
  }
  std::vector<int> free;
  for (int j = 0; j < 8; ++j) {
    if (!is_fixed[j]) free.push_back(j);
  }
  const int nf = static_cast<int>(free.size());
  // The other ring positions: M_free c_free = (E - M_fixed F) delta.
  const int m = n - 2;
  Eigen::MatrixXd mf(m, nf), rhs = Eigen::MatrixXd::Zero(m, n);
  double radius = 0.0;
  for (int k = 1; k + 1 < n; ++k) {
    const int row = k - 1;
    rhs(row, k) = 1.0;
    for (int j = 0; j < 8; ++j) {
      const double mono = Pow(z[k].x, kPatchMonomials[j][0]) * Pow(z[k].y, kPatchMonomials[j][1]);
      if (is_fixed[j]) rhs.row(row) -= mono * fixed.row(j);
    }
    for (int c = 0; c < nf; ++c) {
      const int j = free[static_cast<std::size_t>(c)];
      mf(row, c) = Pow(z[k].x, kPatchMonomials[j][0]) * Pow(z[k].y, kPatchMonomials[j][1]);
    }
  }
  for (const Vec2& p : z) radius = std::max(radius, std::sqrt(p.x * p.x + p.y * p.y));
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(mf, Eigen::ComputeFullV | Eigen::ComputeThinU);
  const Eigen::VectorXd& sigma = svd.singularValues();
  const double tol = 1e-10 * (sigma.size() > 0 ? sigma(0) : 0.0);
  int r = 0;
  while (r < sigma.size() && sigma(r) > tol) ++r;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(nf, n);
  if (r > 0) {
    a = svd.matrixV().leftCols(r) * sigma.head(r).cwiseInverse().asDiagonal() *
        svd.matrixU().leftCols(r).transpose() * rhs;
  }
  // The full operator c = F + S a; where M_free has a null space N, the thin-plate energy of
  // the whole patch is least: a -= N (N^T S^T H S N)^{-1} N^T S^T H (F + S a).
  Eigen::MatrixXd s = Eigen::MatrixXd::Zero(8, nf);
  for (int c = 0; c < nf; ++c) s(free[static_cast<std::size_t>(c)], c) = 1.0;
  if (r < nf) {
    const Eigen::MatrixXd null = svd.matrixV().rightCols(nf - r);
    const Eigen::Matrix<double, 8, 8> h = ThinPlateGram(radius, chart.sector);
    const Eigen::MatrixXd g = null.transpose() * s.transpose() * h * s * null;
    Eigen::LDLT<Eigen::MatrixXd> ldlt(g);
    if (ldlt.info() != Eigen::Success || !ldlt.isPositive() ||
        ldlt.vectorD().minCoeff() <= 1e-12 * ldlt.vectorD().maxCoeff()) {
      return Status::Internal(
          "seam patch fit: the thin-plate regulariser does not fix the null space");
    }
    a -= null * ldlt.solve(null.transpose() * s.transpose() * h * (fixed + s * a));
  }
  const Eigen::MatrixXd full = fixed + s * a;
  op->assign(static_cast<std::size_t>(8 * n), 0.0);
  for (int row = 0; row < 8; ++row)
    for (int col = 0; col < n; ++col)
      (*op)[static_cast<std::size_t>(row * n + col)] = full(row, col);
  if (rank) *rank = r + static_cast<int>(8 - nf);
  return Status::Ok();
}

}  // namespace dermis
