// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Smoothing spline on one B-spline lattice: penalised least squares with the discrete
// thin-plate energy (docs/notes/fit.md section 4c; the idea of SINTEF's LSMG, penalised least
// squares started from an MBA solution), solved matrix-free by Jacobi-preconditioned conjugate
// gradients. Written here rather than with Eigen's ConjugateGradient: the operator is two
// stencils and a scatter over the points, and assembling it as a sparse matrix cost more than
// the solve (measured on the bunny: 0.28 s against 0.05 s for the displacement stage).
#include "dermis/offline/fit/bspline_smoothing.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "dermis/surface/bspline_displacement.h"

namespace dermis {
namespace {

// Weight of |phi|^2 relative to the thin-plate energy: only pins the energy's null space
// (linear functions) where the data leaves it free.
constexpr double kRidge = 1e-6;
// A node is in a gap when its data weight (sum of squared basis weights of the points over it)
// is well below kGap times the mean over the unknowns: gap = kGap mean / (kGap mean + omega).
constexpr double kGap = 0.1;
// Unknowns reach this many nodes beyond the 4 x 4 supports of the points.
constexpr int kDilate = 1;

// A x for A = B^T B + lambda (K + eps I), with B the point-evaluation rows and K = D^T D the
// thin-plate energy of second differences.
struct SmoothingOperator {
  int s = 0;  // lattice side (m + 3)
  double lambda = 0.0;
  double tension = 0.0;
  std::vector<std::size_t> base;  // per point: index of its first (lower-left) node
  std::vector<double> w;          // per point: 16 weights, row l, column k
  std::vector<double> gap;        // per node: membrane weight (gap-ness), 0..1

  void Apply(const std::vector<double>& x, std::vector<double>* y) const {
    const std::size_t n = x.size();
    y->assign(n, 0.0);
    double* out = y->data();
    const std::size_t stride = static_cast<std::size_t>(s);
    for (std::size_t c = 0; c < base.size(); ++c) {
      const double* wc = w.data() + 16 * c;
      double f = 0.0;
      for (int l = 0; l < 4; ++l) {
        const double* row = x.data() + base[c] + static_cast<std::size_t>(l) * stride;
        for (int k = 0; k < 4; ++k) f += wc[4 * l + k] * row[k];
      }
      for (int l = 0; l < 4; ++l) {
        double* row = out + base[c] + static_cast<std::size_t>(l) * stride;
        for (int k = 0; k < 4; ++k) row[k] += wc[4 * l + k] * f;
      }
    }
    const double lam = lambda;
    for (int j = 0; j < s; ++j) {
      for (int i = 0; i < s; ++i) {
        const std::size_t p = static_cast<std::size_t>(j) * stride + static_cast<std::size_t>(i);
        if (i >= 1 && i + 1 < s) {  // phi_xx
          const double d = lam * (x[p - 1] - 2.0 * x[p] + x[p + 1]);
          out[p - 1] += d, out[p] -= 2.0 * d, out[p + 1] += d;
        }
        if (j >= 1 && j + 1 < s) {  // phi_yy
          const double d = lam * (x[p - stride] - 2.0 * x[p] + x[p + stride]);
          out[p - stride] += d, out[p] -= 2.0 * d, out[p + stride] += d;
        }
        if (i + 1 < s && j + 1 < s) {  // 2 phi_xy^2
          const double d = 2.0 * lam * (x[p] - x[p + 1] - x[p + stride] + x[p + stride + 1]);
          out[p] += d, out[p + 1] -= d, out[p + stride] -= d, out[p + stride + 1] += d;
        }
        // Membrane energy in the gaps.
        if (i + 1 < s) {
          const double d = tension * lam * 0.5 * (gap[p] + gap[p + 1]) * (x[p + 1] - x[p]);
          out[p + 1] += d, out[p] -= d;
        }
        if (j + 1 < s) {
          const double d =
              tension * lam * 0.5 * (gap[p] + gap[p + stride]) * (x[p + stride] - x[p]);
          out[p + stride] += d, out[p] -= d;
        }
        out[p] += kRidge * lam * x[p];
      }
    }
  }

  void Diagonal(std::vector<double>* diag) const {
    const std::size_t stride = static_cast<std::size_t>(s);
    diag->assign(stride * stride, kRidge * lambda);
    double* d = diag->data();
    for (std::size_t c = 0; c < base.size(); ++c) {
      const double* wc = w.data() + 16 * c;
      for (int l = 0; l < 4; ++l) {
        for (int k = 0; k < 4; ++k) {
          d[base[c] + static_cast<std::size_t>(l) * stride + static_cast<std::size_t>(k)] +=
              wc[4 * l + k] * wc[4 * l + k];
        }
      }
    }
    for (int j = 0; j < s; ++j) {
      for (int i = 0; i < s; ++i) {
        const std::size_t p = static_cast<std::size_t>(j) * stride + static_cast<std::size_t>(i);
        if (i >= 1 && i + 1 < s) d[p - 1] += lambda, d[p] += 4.0 * lambda, d[p + 1] += lambda;
        if (j >= 1 && j + 1 < s) {
          d[p - stride] += lambda, d[p] += 4.0 * lambda, d[p + stride] += lambda;
        }
        if (i + 1 < s) {
          const double t = tension * lambda * 0.5 * (gap[p] + gap[p + 1]);
          d[p] += t, d[p + 1] += t;
        }
        if (j + 1 < s) {
          const double t = tension * lambda * 0.5 * (gap[p] + gap[p + stride]);
          d[p] += t, d[p + stride] += t;
        }
        if (i + 1 < s && j + 1 < s) {
          d[p] += 2.0 * lambda, d[p + 1] += 2.0 * lambda;
          d[p + stride] += 2.0 * lambda, d[p + stride + 1] += 2.0 * lambda;
        }
      }
    }
  }
};

double Dot(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) s += a[i] * b[i];
  return s;
}

}  // namespace

void SmoothBsplineFit(const Vec2* z, const double* r, std::size_t count, double half_extent, int m,
                      double smoothing, double tension, int iterations, std::vector<double>* phi) {
  const int s = m + 3;
  const std::size_t n = static_cast<std::size_t>(s) * static_cast<std::size_t>(s);
  phi->resize(n, 0.0);
  if (count == 0 || !(smoothing > 0.0) || iterations <= 0) return;
  SmoothingOperator op;
  op.s = s;
  op.lambda = smoothing * static_cast<double>(count) / static_cast<double>(n);
  op.tension = std::max(tension, 0.0);
  op.base.resize(count);
  op.w.resize(16 * count);
  std::vector<double> b(n, 0.0);
  const double scale = m / (2.0 * half_extent);
  for (std::size_t c = 0; c < count; ++c) {
    int i = 0, j = 0;
    double u = 0.0, v = 0.0, bs[4], bt[4], unused[4];
    BsplineCell((z[c].x + half_extent) * scale, m, &i, &u);
    BsplineCell((z[c].y + half_extent) * scale, m, &j, &v);
    CubicBsplineBasis(u, bs, unused);
    CubicBsplineBasis(v, bt, unused);
    op.base[c] =
        static_cast<std::size_t>(j) * static_cast<std::size_t>(s) + static_cast<std::size_t>(i);
    for (int l = 0; l < 4; ++l) {
      for (int k = 0; k < 4; ++k) {
        const double wk = bs[k] * bt[l];
        op.w[16 * c + static_cast<std::size_t>(4 * l + k)] = wk;
        b[op.base[c] + static_cast<std::size_t>(l * s + k)] += wk * r[c];
      }
    }
  }
  // Unknowns: the nodes some point touches, dilated; the others keep a zero correction (as BA
  // leaves them), so the spline never extrapolates into parts of the chart without data.
  std::vector<char> active(n, 0);
  for (std::size_t c = 0; c < count; ++c) {
    for (int l = -kDilate; l < 4 + kDilate; ++l) {
      for (int k = -kDilate; k < 4 + kDilate; ++k) {
        const int i = static_cast<int>(op.base[c] % static_cast<std::size_t>(s)) + k;
        const int j = static_cast<int>(op.base[c] / static_cast<std::size_t>(s)) + l;
        if (i >= 0 && i < s && j >= 0 && j < s) {
          active[static_cast<std::size_t>(j) * static_cast<std::size_t>(s) +
                 static_cast<std::size_t>(i)] = 1;
        }
      }
    }
  }
  auto mask = [&](std::vector<double>* v) {
    for (std::size_t k = 0; k < n; ++k) {
      if (!active[k]) (*v)[k] = 0.0;
    }
  };
  {
    std::vector<double> omega(n, 0.0);
    for (std::size_t c = 0; c < count; ++c)
      for (int l = 0; l < 4; ++l)
        for (int k = 0; k < 4; ++k) {
          const double wk = op.w[16 * c + static_cast<std::size_t>(4 * l + k)];
          omega[op.base[c] + static_cast<std::size_t>(l * s + k)] += wk * wk;
        }
    double mean = 0.0, na = 0.0;
    for (std::size_t k = 0; k < n; ++k)
      if (active[k]) mean += omega[k], na += 1.0;
    mean = na > 0 ? mean / na : 1.0;
    op.gap.assign(n, 0.0);
    for (std::size_t k = 0; k < n; ++k) op.gap[k] = kGap * mean / (kGap * mean + omega[k]);
  }
  std::vector<double> diag, x = *phi, res, p, q, zv(n);
  mask(&x);
  for (std::size_t k = 0; k < n; ++k) b[k] += kRidge * op.lambda * x[k];
  op.Diagonal(&diag);
  op.Apply(x, &res);
  for (std::size_t k = 0; k < n; ++k) res[k] = b[k] - res[k];
  mask(&res);
  const double stop = 1e-16 * Dot(b, b);
  for (std::size_t k = 0; k < n; ++k) zv[k] = res[k] / diag[k];
  p = zv;
  double rz = Dot(res, zv);
  for (int it = 0; it < iterations && Dot(res, res) > stop; ++it) {
    op.Apply(p, &q);
    mask(&q);
    const double pq = Dot(p, q);
    if (!(pq > 0.0)) break;
    const double alpha = rz / pq;
    for (std::size_t k = 0; k < n; ++k) x[k] += alpha * p[k], res[k] -= alpha * q[k];
    for (std::size_t k = 0; k < n; ++k) zv[k] = res[k] / diag[k];
    const double rz_next = Dot(res, zv);
    const double beta = rz_next / rz;
    rz = rz_next;
    for (std::size_t k = 0; k < n; ++k) p[k] = zv[k] + beta * p[k];
  }
  *phi = std::move(x);
}

}  // namespace dermis
