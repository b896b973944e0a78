// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Multilevel B-spline approximation: the BA step, the coarse-to-fine residual loop and the
// refinement that merges levels (Lee, Wolberg and Shin 1997; docs/notes/fit.md section 1). The
// finest level may repeat its BA on its own residual and then be re-solved as a smoothing spline
// (bspline_smoothing.cpp; docs/fitting.md, "The finest level"). Written
// here rather than taken from a library: the MIT one (ddemidov/mba) is not packaged in Debian
// and keeps no per-level lattices, which the runtime level of detail needs.
#include "dermis/offline/fit/mba_fit.h"

#include <algorithm>
#include <cmath>

#include "dermis/offline/fit/bspline_smoothing.h"
#include "dermis/surface/bspline_displacement.h"

namespace dermis {

void RefineBsplineLattice(const double* coarse, int m, double* fine) {
  const int cs = m + 3;      // coarse stride, nodes -1 .. m+1
  const int fs = 2 * m + 3;  // fine stride, nodes -1 .. 2m+1
  // 1-D masks: psi_{2i} = (phi_{i-1} + 6 phi_i + phi_{i+1}) / 8, psi_{2i+1} = (phi_i + phi_{i+1})
  // / 2.
  auto taps = [](int fine_index, int* first, double w[3]) {
    if (fine_index % 2 == 0) {  // fine_index = 2i (i >= 0 here since fine_index >= 0)
      *first = fine_index / 2 - 1;
      w[0] = 0.125, w[1] = 0.75, w[2] = 0.125;
      return 3;
    }
    // fine_index = 2i + 1, also for fine_index = -1 (i = -1).
    *first = (fine_index - 1) / 2;
    if (fine_index < 0) *first = -1;
    w[0] = 0.5, w[1] = 0.5, w[2] = 0.0;
    return 2;
  };
  for (int fj = -1; fj <= 2 * m + 1; ++fj) {
    int j0 = 0;
    double wj[3];
    const int nj = taps(fj, &j0, wj);
    for (int fi = -1; fi <= 2 * m + 1; ++fi) {
      int i0 = 0;
      double wi[3];
      const int ni = taps(fi, &i0, wi);
      double sum = 0.0;
      for (int b = 0; b < nj; ++b) {
        const double* row = coarse + static_cast<std::ptrdiff_t>(j0 + b + 1) * cs + (i0 + 1);
        double a = 0.0;
        for (int c = 0; c < ni; ++c) a += wi[c] * row[c];
        sum += wj[b] * a;
      }
      fine[static_cast<std::ptrdiff_t>(fj + 1) * fs + (fi + 1)] = sum;
    }
  }
}

namespace {

// Cell (i, j) of chart point z on a level with m cells per side and the basis weights there.
void Locate(Vec2 z, double half_extent, int m, int* i, int* j, double bs[4], double bt[4]) {
  const double scale = m / (2.0 * half_extent);
  double s = 0.0, t = 0.0, unused[4];
  BsplineCell((z.x + half_extent) * scale, m, i, &s);
  BsplineCell((z.y + half_extent) * scale, m, j, &t);
  CubicBsplineBasis(s, bs, unused);
  CubicBsplineBasis(t, bt, unused);
}

}  // namespace

void FitMultilevelBspline(const Vec2* z, const double* values, std::size_t count,
                          double half_extent, int num_levels, std::vector<double>* lattices,
                          std::vector<double>* residuals, const MbaOptions& options) {
  std::vector<double> r(values, values + count);
  std::vector<double> delta, omega, phi, merged, refined;
  std::vector<double> finest_r, finest_sum;  // residual entering the finest level, its passes
  if (num_levels <= 0) {
    if (residuals) *residuals = std::move(r);
    return;
  }
  // Passes 0 .. num_levels - 1 are the levels; the finest level then repeats its BA on what is
  // left (finest_passes in all), each pass adding its Phi to the same lattice.
  const int passes = num_levels - 1 + std::max(options.finest_passes, 1);
  for (int pass = 0; pass < passes; ++pass) {
    const int level = std::min(pass, num_levels - 1);
    const int m = 1 << level;
    const int stride = m + 3;
    const std::size_t size = static_cast<std::size_t>(stride) * stride;
    if (pass == num_levels - 1) {
      finest_r = r;
      finest_sum.assign(size, 0.0);
    }
    delta.assign(size, 0.0);
    omega.assign(size, 0.0);
    // BA: each point's minimum-norm wish phi_c = w_kl r / sum w^2, averaged with weights w^2.
    for (std::size_t c = 0; c < count; ++c) {
      int i = 0, j = 0;
      double bs[4], bt[4];
      Locate(z[c], half_extent, m, &i, &j, bs, bt);
      double sum_w2 = 0.0;
      for (int l = 0; l < 4; ++l) {
        for (int k = 0; k < 4; ++k) sum_w2 += (bs[k] * bt[l]) * (bs[k] * bt[l]);
      }
      const double rc = r[c] / sum_w2;
      for (int l = 0; l < 4; ++l) {
        const std::size_t row = static_cast<std::size_t>(j + l) * stride + i;
        for (int k = 0; k < 4; ++k) {
          const double w = bs[k] * bt[l];
          const double w2 = w * w;
          delta[row + k] += w2 * w * rc;
          omega[row + k] += w2;
        }
      }
    }
    phi.assign(size, 0.0);
    for (std::size_t n = 0; n < size; ++n) {
      if (omega[n] > 0.0) phi[n] = delta[n] / omega[n];
    }
    // After the finest level's last pass, its whole correction (every pass) is re-solved as
    // the smoothing spline of the residual that entered the level, from the passes' sum.
    if (pass == passes - 1 && options.smoothing > 0.0) {
      std::vector<double> total(size);
      for (std::size_t n = 0; n < size; ++n) total[n] = finest_sum[n] + phi[n];
      SmoothBsplineFit(z, finest_r.data(), count, half_extent, m, options.smoothing,
                       options.tension, options.smoothing_iterations, &total);
      for (std::size_t n = 0; n < size; ++n) phi[n] = total[n] - finest_sum[n];
    }
    // Residuals of this level's function.
    for (std::size_t c = 0; c < count; ++c) {
      int i = 0, j = 0;
      double bs[4], bt[4];
      Locate(z[c], half_extent, m, &i, &j, bs, bt);
      double f = 0.0;
      for (int l = 0; l < 4; ++l) {
        const double* row = phi.data() + static_cast<std::size_t>(j + l) * stride + i;
        f += bt[l] * (bs[0] * row[0] + bs[1] * row[1] + bs[2] * row[2] + bs[3] * row[3]);
      }
      r[c] -= f;
    }
    if (pass >= num_levels - 1) {
      for (std::size_t n = 0; n < size; ++n) finest_sum[n] += phi[n];
    }
    // Psi_k = R(Psi_{k-1}) + Phi_k; a repeated pass adds to Psi_k itself.
    if (pass == 0) {
      merged = phi;
    } else if (pass < num_levels) {
      refined.assign(size, 0.0);
      RefineBsplineLattice(merged.data(), m / 2, refined.data());
      merged.swap(refined);
      for (std::size_t n = 0; n < size; ++n) merged[n] += phi[n];
    } else {
      for (std::size_t n = 0; n < size; ++n) merged[n] += phi[n];
    }
    // Every coarser level is stored once; the finest after its last pass.
    if (pass < num_levels - 1 || pass == passes - 1) {
      lattices->insert(lattices->end(), merged.begin(), merged.end());
    }
  }
  if (residuals) *residuals = std::move(r);
}

}  // namespace dermis
