// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// One level of the adaptive displacement fit (docs/fitting.md, "Adaptive displacement levels"):
// the density and residual criteria choose each chart's active lattice nodes, and the level's
// correction is the penalised least squares of docs/notes/fit.md section 4c over all charts jointly
// (the displaced surface's error at the fitted parameters plus each chart's thin-plate
// energy), solved matrix-free by Jacobi-preconditioned conjugate gradients. Written here
// rather than with Eigen's ConjugateGradient: the operator is a gather and a scatter over the
// samples plus a stencil, and assembling it as a sparse matrix costs more than the solve
// (docs/fitting.md).
#include "dermis/offline/fit/displacement_level_fit.h"

#include <algorithm>
#include <cmath>

#include "dermis/core/parallel.h"
#include "dermis/surface/bspline_displacement.h"

namespace dermis {
namespace {

// Weight of |phi|^2 relative to lambda: pins the thin plate's null space (linear functions)
// where the data leave it free.
constexpr double kRidge = 1e-6;

// Uniform cubic B-spline basis values on a cell, t in [0, 1] (docs/notes/fit.md section 1).
template <typename Real>
void Basis(double t, Real b[4]) {
  const double s = 1.0 - t, t2 = t * t, t3 = t2 * t;
  b[0] = static_cast<Real>(s * s * s / 6.0);
  b[1] = static_cast<Real>((3.0 * t3 - 6.0 * t2 + 4.0) / 6.0);
  b[2] = static_cast<Real>((-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) / 6.0);
  b[3] = static_cast<Real>(t3 / 6.0);
}

// Cell (i, j) of chart point z on a level with m cells per side (its lower-left node has
// lattice index j (m + 3) + i) and the basis weights along x and y.
template <typename Real>
void Locate(Vec2 z, double half_extent, int m, int* i, int* j, Real bs[4], Real bt[4]) {
  const double scale = m / (2.0 * half_extent);
  double s = 0.0, t = 0.0;
  BsplineCell((z.x + half_extent) * scale, m, i, &s);
  BsplineCell((z.y + half_extent) * scale, m, j, &t);
  Basis(s, bs);
  Basis(t, bt);
}

double Dot(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) s += a[i] * b[i];
  return s;
}

// The thin-plate energy's rows at one node: sum over the second differences phi_xx, phi_yy
// (weight 1) and phi_xy (weight 2) that contain the node and lie inside the lattice, of
// coefficient * difference. x: window values (inactive nodes 0), p: the node's window
// position, (i, j) its lattice cell, w the window width, stride the lattice side. With x null
// it returns the diagonal entry instead.
double ThinPlateRow(const double* x, std::int64_t p, int i, int j, int w, int stride) {
  double out = 0.0;
  for (int d = -1; d <= 1; ++d) {
    const double coef = d == 0 ? -2.0 : 1.0;
    if (i + d >= 1 && i + d <= stride - 2) {
      out += x ? coef * (x[p + d - 1] - 2.0 * x[p + d] + x[p + d + 1]) : coef * coef;
    }
    if (j + d >= 1 && j + d <= stride - 2) {
      const std::int64_t c = p + static_cast<std::int64_t>(d) * w;
      out += x ? coef * (x[c - w] - 2.0 * x[c] + x[c + w]) : coef * coef;
    }
  }
  for (int dj = -1; dj <= 0; ++dj) {
    for (int di = -1; di <= 0; ++di) {
      if (i + di < 0 || j + dj < 0 || i + di + 1 > stride - 1 || j + dj + 1 > stride - 1) continue;
      const double coef = (di == dj) ? 1.0 : -1.0;  // +1 at the cell's corners (0,0), (1,1)
      const std::int64_t c = p + di + static_cast<std::int64_t>(dj) * w;
      out += x ? 2.0 * coef * (x[c] - x[c + 1] - x[c + w] + x[c + w + 1]) : 2.0;
    }
  }
  return out;
}

}  // namespace

DisplacementLevelFitter::DisplacementLevelFitter(const std::vector<double>& half_extent,
                                                 const std::vector<DisplacementTarget>& targets,
                                                 std::vector<std::uint32_t> fit,
                                                 std::vector<std::uint32_t> eval,
                                                 const LevelFitOptions& options)
    : half_(half_extent),
      targets_(targets),
      fit_(std::move(fit)),
      eval_(std::move(eval)),
      opt_(options) {
  opt_.threads = std::max(opt_.threads, 1);
  const std::size_t nc = half_.size();
  // Points in the order of their dominant chart, so that the samples of a chart (stored chart
  // by chart) belong to nearby points: the solver's gathers and scatters stay in cache.
  auto dominant = [&](std::uint32_t i) {
    const DisplacementTarget& t = targets_[i];
    int best = 0;
    for (int s = 1; s < t.count; ++s) {
      if (glm::dot(t.a[s], t.a[s]) > glm::dot(t.a[best], t.a[best])) best = s;
    }
    return t.chart[best];
  };
  std::stable_sort(fit_.begin(), fit_.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return dominant(a) < dominant(b); });
  f_.assign(targets_.size(), Vec3(0.0));
  target_.assign(targets_.size(), Vec3(0.0));
  for (const std::vector<std::uint32_t>* set : {&fit_, &eval_}) {
    for (std::uint32_t i : *set) {
      const DisplacementTarget& t = targets_[i];
      Vec3 n(0.0);
      for (int s = 0; s < t.count; ++s) n += t.a[s];
      // A weighted point's row and target are scaled by sqrt(weight), so that its squared
      // error counts weight times (f_ and target_ are in those units).
      target_[i] = std::sqrt(t.weight) * t.delta * n;
    }
  }
  // The samples of the fitted points grouped by chart, in point order.
  chart_begin_.assign(nc + 1, 0);
  for (std::uint32_t i : fit_) {
    for (int s = 0; s < targets_[i].count; ++s) {
      ++chart_begin_[static_cast<std::size_t>(targets_[i].chart[s]) + 1];
    }
  }
  for (std::size_t c = 0; c < nc; ++c) chart_begin_[c + 1] += chart_begin_[c];
  entries_.resize(static_cast<std::size_t>(chart_begin_[nc]));
  point_entries_.assign(fit_.size() * 4, -1);
  std::vector<std::int64_t> next(chart_begin_.begin(), chart_begin_.end() - 1);
  for (std::size_t p = 0; p < fit_.size(); ++p) {
    const DisplacementTarget& t = targets_[fit_[p]];
    for (int s = 0; s < t.count; ++s) {
      const std::int64_t e = next[static_cast<std::size_t>(t.chart[s])]++;
      Entry& en = entries_[static_cast<std::size_t>(e)];
      en.point = static_cast<std::uint32_t>(p);
      en.psi = glm::length(t.a[s]);
      en.z = t.z[s];
      en.a = std::sqrt(t.weight) * t.a[s];
      point_entries_[4 * p + static_cast<std::size_t>(s)] = e;
    }
  }
  charts_.resize(nc);
  cur_.assign(entries_.size(), 0.0);
}

double DisplacementLevelFitter::FitError() const {
  double sum = 0.0;  // f_ and target_ carry sqrt(weight): divided out, |D - p| in model units
  for (std::uint32_t i : fit_)
    sum += glm::length(f_[i] - target_[i]) / std::sqrt(targets_[i].weight);
  return fit_.empty() ? 0.0 : sum / static_cast<double>(fit_.size());
}

double DisplacementLevelFitter::EvalError() const {
  double sum = 0.0;
  for (std::uint32_t i : eval_)
    sum += glm::length(f_[i] - target_[i]) / std::sqrt(targets_[i].weight);
  return eval_.empty() ? 0.0 : sum / static_cast<double>(eval_.size());
}

std::int64_t DisplacementLevelFitter::FitLevel(int level, double residual_threshold,
                                               std::int64_t max_nodes, int* iterations) {
  m_ = 1 << level;
  stride_ = m_ + 3;
  *iterations = 0;
  LocateEntries();
  const std::int64_t active = SelectNodes(residual_threshold, max_nodes);
  if (active == 0) return 0;
  Prepare();
  Solve(iterations);
  // The stored coefficients are f32: the next levels fit what the stored ones leave.
  for (std::size_t c = 0; c < charts_.size(); ++c) {
    Chart& ch = charts_[c];
    ch.values.resize(ch.nodes.size());
    for (std::size_t k = 0; k < ch.nodes.size(); ++k) {
      ch.values[k] = static_cast<float>(x_[static_cast<std::size_t>(ch.first) + k]);
    }
  }
  for (std::int64_t u = 0; u < unknowns_; ++u) {
    const auto c = static_cast<std::size_t>(active_chart_[static_cast<std::size_t>(u)]);
    x_[static_cast<std::size_t>(u)] =
        charts_[c].values[static_cast<std::size_t>(u - charts_[c].first)];
  }
  Update();
  return active;
}

void DisplacementLevelFitter::LocateEntries() {
  blocks_.resize(entries_.size());
  ParallelFor(opt_.threads, half_.size(), [&](std::size_t b, std::size_t e) {
    for (std::size_t c = b; c < e; ++c) {
      for (std::int64_t q = chart_begin_[c]; q < chart_begin_[c + 1]; ++q) {
        Block& bl = blocks_[static_cast<std::size_t>(q)];
        Locate(entries_[static_cast<std::size_t>(q)].z, half_[c], m_, &bl.i, &bl.j, bl.bs, bl.bt);
        bl.base = -1;
        bl.w = 0;
      }
    }
  });
}

// Per chart: the data weight W = sum psi B and the weighted squared error R = sum psi B |D - p|^2
// of every node under its samples; the nodes with W >= min_node_weight (and R > tau^2 W when
// tau > 0) are candidates. If there are more than max_nodes (>= 0), those with the largest R are
// kept. Then the windows and the unknowns are laid out.
std::int64_t DisplacementLevelFitter::SelectNodes(double tau, std::int64_t max_nodes) {
  const std::size_t nc = half_.size();
  for (Chart& ch : charts_) ch = Chart{};
  r2_.resize(fit_.size());
  for (std::size_t p = 0; p < fit_.size(); ++p) {
    const Vec3 r = f_[fit_[p]] - target_[fit_[p]];
    r2_[p] = glm::dot(r, r);
  }
  std::vector<std::vector<double>> weight(nc), energy(nc);
  ParallelFor(opt_.threads, nc, [&](std::size_t b, std::size_t e) {
    std::vector<double> wsum, rsum;
    for (std::size_t c = b; c < e; ++c) {
      const std::int64_t e0 = chart_begin_[c], e1 = chart_begin_[c + 1];
      if (e0 == e1) continue;
      int lo_i = stride_, lo_j = stride_, hi_i = -1, hi_j = -1;
      for (std::int64_t q = e0; q < e1; ++q) {
        const Block& bl = blocks_[static_cast<std::size_t>(q)];
        lo_i = std::min(lo_i, bl.i), lo_j = std::min(lo_j, bl.j);
        hi_i = std::max(hi_i, bl.i + 3), hi_j = std::max(hi_j, bl.j + 3);
      }
      const int bw = hi_i - lo_i + 1, bh = hi_j - lo_j + 1;
      wsum.assign(static_cast<std::size_t>(bw) * static_cast<std::size_t>(bh), 0.0);
      rsum.assign(wsum.size(), 0.0);
      for (std::int64_t q = e0; q < e1; ++q) {
        const Entry& en = entries_[static_cast<std::size_t>(q)];
        const Block& bl = blocks_[static_cast<std::size_t>(q)];
        const double r2 = r2_[en.point];
        for (int l = 0; l < 4; ++l) {
          const std::size_t row =
              static_cast<std::size_t>(bl.j + l - lo_j) * static_cast<std::size_t>(bw) +
              static_cast<std::size_t>(bl.i - lo_i);
          for (int k = 0; k < 4; ++k) {
            const double wb = en.psi * static_cast<double>(bl.bs[k]) * bl.bt[l];
            wsum[row + static_cast<std::size_t>(k)] += wb;
            rsum[row + static_cast<std::size_t>(k)] += wb * r2;
          }
        }
      }
      for (int j = 0; j < bh; ++j) {
        for (int i = 0; i < bw; ++i) {
          const std::size_t n = static_cast<std::size_t>(j) * static_cast<std::size_t>(bw) +
                                static_cast<std::size_t>(i);
          if (!(wsum[n] >= opt_.min_node_weight)) continue;
          if (tau > 0.0 && !(rsum[n] > tau * tau * wsum[n])) continue;
          charts_[c].nodes.push_back(static_cast<std::uint32_t>((lo_j + j) * stride_ + lo_i + i));
          weight[c].push_back(wsum[n]);
          energy[c].push_back(rsum[n]);
        }
      }
    }
  });
  std::int64_t candidates = 0;
  for (const Chart& ch : charts_) candidates += static_cast<std::int64_t>(ch.nodes.size());
  if (max_nodes >= 0 && candidates > max_nodes) {
    // Keep the max_nodes candidates with the largest residual energy (ties: lower chart, then
    // lower node first).
    struct Key {
      double energy;
      std::uint32_t chart, k;
    };
    std::vector<Key> keys;
    keys.reserve(static_cast<std::size_t>(candidates));
    for (std::size_t c = 0; c < nc; ++c) {
      for (std::size_t k = 0; k < charts_[c].nodes.size(); ++k) {
        keys.push_back(
            {energy[c][k], static_cast<std::uint32_t>(c), static_cast<std::uint32_t>(k)});
      }
    }
    const auto better = [](const Key& a, const Key& b) {
      if (a.energy != b.energy) return a.energy > b.energy;
      return a.chart != b.chart ? a.chart < b.chart : a.k < b.k;
    };
    std::nth_element(keys.begin(), keys.begin() + max_nodes, keys.end(), better);
    std::vector<std::vector<char>> keep(nc);
    for (std::size_t c = 0; c < nc; ++c) keep[c].assign(charts_[c].nodes.size(), 0);
    for (std::int64_t a = 0; a < max_nodes; ++a) {
      keep[keys[static_cast<std::size_t>(a)].chart][keys[static_cast<std::size_t>(a)].k] = 1;
    }
    for (std::size_t c = 0; c < nc; ++c) {
      std::size_t out = 0;
      for (std::size_t k = 0; k < charts_[c].nodes.size(); ++k) {
        if (!keep[c][k]) continue;
        charts_[c].nodes[out] = charts_[c].nodes[k];
        weight[c][out] = weight[c][k];
        ++out;
      }
      charts_[c].nodes.resize(out);
      weight[c].resize(out);
    }
  }
  // Windows (the active nodes' box with a margin of 3) and the smoothing weight per chart.
  unknowns_ = 0;
  window_size_ = 0;
  for (std::size_t c = 0; c < nc; ++c) {
    Chart& ch = charts_[c];
    if (!ch.nodes.empty()) {
      int ai0 = stride_, aj0 = stride_, ai1 = -1, aj1 = -1;
      double total = 0.0;
      for (std::size_t k = 0; k < ch.nodes.size(); ++k) {
        const int i = static_cast<int>(ch.nodes[k] % static_cast<std::uint32_t>(stride_));
        const int j = static_cast<int>(ch.nodes[k] / static_cast<std::uint32_t>(stride_));
        ai0 = std::min(ai0, i), aj0 = std::min(aj0, j);
        ai1 = std::max(ai1, i), aj1 = std::max(aj1, j);
        total += weight[c][k];
      }
      ch.i0 = std::max(ai0 - 3, 0), ch.j0 = std::max(aj0 - 3, 0);
      ch.w = std::min(ai1 + 3, stride_ - 1) - ch.i0 + 1;
      ch.h = std::min(aj1 + 3, stride_ - 1) - ch.j0 + 1;
      ch.lambda = opt_.smoothing * total / static_cast<double>(ch.nodes.size());
    }
    ch.first = unknowns_;
    ch.window = window_size_;
    unknowns_ += static_cast<std::int64_t>(ch.nodes.size());
    window_size_ += static_cast<std::int64_t>(ch.w) * ch.h;
  }
  return unknowns_;
}

// The unknowns' window positions, the samples' blocks and the Jacobi preconditioner.
void DisplacementLevelFitter::Prepare() {
  const auto n = static_cast<std::size_t>(unknowns_);
  active_pos_.resize(n);
  active_chart_.resize(n);
  active_node_.resize(n);
  for (std::size_t c = 0; c < charts_.size(); ++c) {
    const Chart& ch = charts_[c];
    for (std::size_t k = 0; k < ch.nodes.size(); ++k) {
      const std::uint32_t node = ch.nodes[k];
      const int i = static_cast<int>(node % static_cast<std::uint32_t>(stride_)) - ch.i0;
      const int j = static_cast<int>(node / static_cast<std::uint32_t>(stride_)) - ch.j0;
      const auto u = static_cast<std::size_t>(ch.first) + k;
      active_pos_[u] = static_cast<std::int32_t>(ch.window + j * ch.w + i);
      active_chart_[u] = static_cast<std::int32_t>(c);
      active_node_[u] = node;
    }
  }
  xw_.assign(static_cast<std::size_t>(window_size_), 0.0);
  yw_.assign(static_cast<std::size_t>(window_size_), 0.0);
  // Blocks, and the data part of the diagonal accumulated in the window layout.
  ParallelFor(opt_.threads, charts_.size(), [&](std::size_t b, std::size_t e) {
    for (std::size_t c = b; c < e; ++c) {
      const Chart& ch = charts_[c];
      if (ch.nodes.empty()) continue;
      double* d = yw_.data() + ch.window;
      for (std::int64_t q = chart_begin_[c]; q < chart_begin_[c + 1]; ++q) {
        Block& bl = blocks_[static_cast<std::size_t>(q)];
        const int i = bl.i - ch.i0, j = bl.j - ch.j0;
        if (i < 0 || j < 0 || i + 3 >= ch.w || j + 3 >= ch.h) continue;  // touches no active node
        bl.base = static_cast<std::int32_t>(ch.window + j * ch.w + i);
        bl.w = ch.w;
        const Entry& en = entries_[static_cast<std::size_t>(q)];
        const double w = targets_[fit_[en.point]].weight;  // |en.a|^2 = w psi^2
        const double a2 = w * en.psi * en.psi + opt_.consistency * en.psi;
        for (int l = 0; l < 4; ++l) {
          for (int k = 0; k < 4; ++k) {
            const double wk = static_cast<double>(bl.bs[k]) * bl.bt[l];
            d[(j + l) * ch.w + i + k] += a2 * wk * wk;
          }
        }
      }
    }
  });
  diag_.resize(n);
  for (std::size_t u = 0; u < n; ++u) {
    const Chart& ch = charts_[static_cast<std::size_t>(active_chart_[u])];
    const int i = static_cast<int>(active_node_[u] % static_cast<std::uint32_t>(stride_));
    const int j = static_cast<int>(active_node_[u] / static_cast<std::uint32_t>(stride_));
    diag_[u] = yw_[static_cast<std::size_t>(active_pos_[u])] +
               ch.lambda * (ThinPlateRow(nullptr, 0, i, j, ch.w, stride_) + kRidge);
    if (!(diag_[u] > 0.0)) diag_[u] = 1.0;
  }
  std::fill(yw_.begin(), yw_.end(), 0.0);
  x_.assign(n, 0.0);
}

// v_ = the level's value of every sample's chart at the sample, from window values xw.
void DisplacementLevelFitter::SampleValues(const std::vector<double>& xw) {
  v_.resize(entries_.size());
  ParallelFor(opt_.threads, entries_.size(), [&](std::size_t b, std::size_t e) {
    for (std::size_t q = b; q < e; ++q) {
      const Block& bl = blocks_[q];
      if (bl.base < 0) {
        v_[q] = 0.0;
        continue;
      }
      const double* row = xw.data() + bl.base;
      double v = 0.0;
      for (int l = 0; l < 4; ++l, row += bl.w) {
        v += bl.bt[l] *
             (bl.bs[0] * row[0] + bl.bs[1] * row[1] + bl.bs[2] * row[2] + bl.bs[3] * row[3]);
      }
      v_[q] = v;
    }
  });
}

// yw_ += B^T g at every block (per chart, its samples in point order), after zeroing the
// active positions (the others are never read).
void DisplacementLevelFitter::ScatterTransposed(const std::vector<Vec3>& g) {
  for (std::int32_t pos : active_pos_) yw_[static_cast<std::size_t>(pos)] = 0.0;
  ParallelFor(opt_.threads, charts_.size(), [&](std::size_t b, std::size_t e) {
    for (std::size_t c = b; c < e; ++c) {
      for (std::int64_t q = chart_begin_[c]; q < chart_begin_[c + 1]; ++q) {
        const Block& bl = blocks_[static_cast<std::size_t>(q)];
        if (bl.base < 0) continue;
        const Entry& en = entries_[static_cast<std::size_t>(q)];
        double s = glm::dot(en.a, g[en.point]);
        if (own_ != nullptr) s += opt_.consistency * en.psi * (*own_)[static_cast<std::size_t>(q)];
        double* row = yw_.data() + bl.base;
        for (int l = 0; l < 4; ++l, row += bl.w) {
          const double sl = s * bl.bt[l];
          for (int k = 0; k < 4; ++k) row[k] += sl * bl.bs[k];
        }
      }
    }
  });
}

// y = (B^T B + sum_c lambda_c (K_c + eps I)) x over the unknowns, B the map from coefficients
// to the points' vector errors.
void DisplacementLevelFitter::Apply(const std::vector<double>& x, std::vector<double>* y) {
  const std::size_t n = x.size();
  for (std::size_t u = 0; u < n; ++u) xw_[static_cast<std::size_t>(active_pos_[u])] = x[u];
  SampleValues(xw_);
  g_.resize(fit_.size());
  ParallelFor(opt_.threads, fit_.size(), [&](std::size_t b, std::size_t e) {
    for (std::size_t p = b; p < e; ++p) {
      Vec3 g(0.0);
      for (std::size_t s = 0; s < 4; ++s) {
        const std::int64_t q = point_entries_[4 * p + s];
        if (q < 0) break;
        g += v_[static_cast<std::size_t>(q)] * entries_[static_cast<std::size_t>(q)].a;
      }
      g_[p] = g;
    }
  });
  own_ = opt_.consistency > 0.0 ? &v_ : nullptr;
  ScatterTransposed(g_);
  own_ = nullptr;
  y->resize(n);
  ParallelFor(opt_.threads, n, [&](std::size_t b, std::size_t e) {
    for (std::size_t u = b; u < e; ++u) {
      const Chart& ch = charts_[static_cast<std::size_t>(active_chart_[u])];
      const int i = static_cast<int>(active_node_[u] % static_cast<std::uint32_t>(stride_));
      const int j = static_cast<int>(active_node_[u] / static_cast<std::uint32_t>(stride_));
      const std::int64_t p = active_pos_[u];
      (*y)[u] = yw_[static_cast<std::size_t>(p)] +
                ch.lambda * (ThinPlateRow(xw_.data(), p, i, j, ch.w, stride_) + kRidge * x[u]);
    }
  });
}

void DisplacementLevelFitter::Solve(int* iterations) {
  const auto n = static_cast<std::size_t>(unknowns_);
  // Right-hand side -B^T r, r the points' current errors.
  std::vector<Vec3> r(fit_.size());
  for (std::size_t p = 0; p < fit_.size(); ++p) r[p] = target_[fit_[p]] - f_[fit_[p]];
  std::vector<double> own(entries_.size());
  for (std::size_t q = 0; q < entries_.size(); ++q) {
    own[q] = targets_[fit_[entries_[q].point]].delta - cur_[q];
  }
  own_ = opt_.consistency > 0.0 ? &own : nullptr;
  ScatterTransposed(r);
  own_ = nullptr;
  std::vector<double> rhs(n);
  for (std::size_t u = 0; u < n; ++u) rhs[u] = yw_[static_cast<std::size_t>(active_pos_[u])];
  std::vector<double> res = rhs, z(n), p(n), q(n);
  for (std::size_t u = 0; u < n; ++u) z[u] = res[u] / diag_[u];
  p = z;
  double rz = Dot(res, z);
  const double stop = opt_.tolerance * opt_.tolerance * Dot(rhs, rhs);
  int it = 0;
  for (; it < opt_.iterations && Dot(res, res) > stop; ++it) {
    Apply(p, &q);
    const double pq = Dot(p, q);
    if (!(pq > 0.0)) break;
    const double alpha = rz / pq;
    for (std::size_t u = 0; u < n; ++u) x_[u] += alpha * p[u], res[u] -= alpha * q[u];
    for (std::size_t u = 0; u < n; ++u) z[u] = res[u] / diag_[u];
    const double rz_next = Dot(res, z);
    const double beta = rz_next / rz;
    rz = rz_next;
    for (std::size_t u = 0; u < n; ++u) p[u] = z[u] + beta * p[u];
  }
  *iterations = it;
}

double DisplacementLevelFitter::LevelValue(std::size_t c, Vec2 z) const {
  const Chart& ch = charts_[c];
  if (ch.nodes.empty()) return 0.0;
  int i = 0, j = 0;
  double bs[4], bt[4];
  Locate(z, half_[c], m_, &i, &j, bs, bt);
  double v = 0.0;
  for (int l = 0; l < 4; ++l) {
    const int jj = j + l - ch.j0;
    if (jj < 0 || jj >= ch.h) continue;
    for (int k = 0; k < 4; ++k) {
      const int ii = i + k - ch.i0;
      if (ii < 0 || ii >= ch.w) continue;
      v += bs[k] * bt[l] * xw_[static_cast<std::size_t>(ch.window + jj * ch.w + ii)];
    }
  }
  return v;
}

// Adds the level to the current fit of every fitted and evaluated point.
void DisplacementLevelFitter::Update() {
  std::fill(xw_.begin(), xw_.end(), 0.0);
  for (std::size_t u = 0; u < x_.size(); ++u) xw_[static_cast<std::size_t>(active_pos_[u])] = x_[u];
  SampleValues(xw_);
  ParallelFor(opt_.threads, fit_.size(), [&](std::size_t b, std::size_t e) {
    for (std::size_t p = b; p < e; ++p) {
      for (std::size_t s = 0; s < 4; ++s) {
        const std::int64_t q = point_entries_[4 * p + s];
        if (q < 0) break;
        f_[fit_[p]] += v_[static_cast<std::size_t>(q)] * entries_[static_cast<std::size_t>(q)].a;
        cur_[static_cast<std::size_t>(q)] += v_[static_cast<std::size_t>(q)];
      }
    }
  });
  ParallelFor(opt_.threads, eval_.size(), [&](std::size_t b, std::size_t e) {
    for (std::size_t p = b; p < e; ++p) {
      const std::uint32_t i = eval_[p];
      const DisplacementTarget& t = targets_[i];
      const double sw = std::sqrt(t.weight);
      for (int s = 0; s < t.count; ++s) {
        f_[i] += LevelValue(static_cast<std::size_t>(t.chart[s]), t.z[s]) * (sw * t.a[s]);
      }
    }
  });
}

}  // namespace dermis
