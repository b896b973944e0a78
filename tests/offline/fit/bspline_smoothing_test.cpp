// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The finest level's smoothing spline: the conjugate-gradient solution against the normal
// equations of its stated objective solved densely, exact reproduction of a linear function,
// zero coefficients away from the data, a smoother surface than BA between noisy points, and
// MBA with smoothing leaving every coarser level untouched.
#include "dermis/offline/fit/bspline_smoothing.h"

#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "dermis/offline/fit/mba_fit.h"
#include "dermis/surface/bspline_displacement.h"
#include "test_meshes.h"

using namespace dermis;
using namespace dermis::test;

namespace {

// Basis weights of point z on a lattice with m cells on [-r, r]^2: node index -> weight.
void PointRow(Vec2 z, double r, int m, Eigen::VectorXd* row) {
  const int s = m + 3;
  row->setZero(s * s);
  int i = 0, j = 0;
  double u = 0.0, v = 0.0, bs[4], bt[4], d[4];
  BsplineCell((z.x + r) * m / (2 * r), m, &i, &u);
  BsplineCell((z.y + r) * m / (2 * r), m, &j, &v);
  CubicBsplineBasis(u, bs, d);
  CubicBsplineBasis(v, bt, d);
  for (int l = 0; l < 4; ++l) {
    for (int k = 0; k < 4; ++k) (*row)[(j + l) * s + i + k] += bs[k] * bt[l];
  }
}

double Eval(const std::vector<double>& phi, Vec2 z, double r, int m) {
  Eigen::VectorXd row;
  PointRow(z, r, m, &row);
  double f = 0.0;
  for (Eigen::Index k = 0; k < row.size(); ++k) f += row[k] * phi[static_cast<std::size_t>(k)];
  return f;
}

// Adds lambda times the penalties of SmoothBsplineFit()'s objective to the dense normal
// matrix of an s x s lattice: the thin plate, the membrane weighted by the per-node gap weights
// (none when `gap` is empty) and the 1e-6 ridge.
void AddPenalties(int s, double lambda, double tension, const std::vector<double>& gap,
                  Eigen::MatrixXd* a) {
  const int n = s * s;
  auto add = [&](std::initializer_list<std::pair<int, double>> terms, double w) {
    Eigen::VectorXd d = Eigen::VectorXd::Zero(n);
    for (const auto& [k, c] : terms) d[k] += c;
    *a += lambda * w * d * d.transpose();
  };
  auto g = [&](int k) { return gap[static_cast<std::size_t>(k)]; };
  for (int j = 0; j < s; ++j) {
    for (int i = 0; i < s; ++i) {
      const int p = j * s + i;
      if (i >= 1 && i + 1 < s) add({{p - 1, 1.0}, {p, -2.0}, {p + 1, 1.0}}, 1.0);
      if (j >= 1 && j + 1 < s) add({{p - s, 1.0}, {p, -2.0}, {p + s, 1.0}}, 1.0);
      if (i + 1 < s && j + 1 < s) {
        add({{p, 1.0}, {p + 1, -1.0}, {p + s, -1.0}, {p + s + 1, 1.0}}, 2.0);
      }
      if (!gap.empty() && i + 1 < s)
        add({{p, -1.0}, {p + 1, 1.0}}, tension * 0.5 * (g(p) + g(p + 1)));
      if (!gap.empty() && j + 1 < s)
        add({{p, -1.0}, {p + s, 1.0}}, tension * 0.5 * (g(p) + g(p + s)));
      (*a)(p, p) += 1e-6 * lambda;
    }
  }
}

}  // namespace

TEST_CASE("smoothing spline: matches the dense solution of its objective") {
  // Points cover the whole square, so every node is an unknown; no gaps (tension 0).
  const int m = 4, s = m + 3;
  const double r = 1.0, smoothing = 0.05;
  Lcg rng(17);
  std::vector<Vec2> z;
  std::vector<double> values;
  for (int j = 0; j < 14; ++j) {
    for (int i = 0; i < 14; ++i) {
      const Vec2 p(-r + (i + rng.Uniform(0.2, 0.8)) * 2 * r / 14,
                   -r + (j + rng.Uniform(0.2, 0.8)) * 2 * r / 14);
      z.push_back(p);
      values.push_back(std::sin(3 * p.x) * std::cos(2 * p.y) + rng.Uniform(-0.05, 0.05));
    }
  }
  std::vector<double> phi;  // start: zero
  SmoothBsplineFit(z.data(), values.data(), z.size(), r, m, smoothing, 0.0, 1000, &phi);
  // Dense normal equations of sum (f(z) - v)^2 + lambda (E + 1e-6 |phi|^2).
  const int n = s * s;
  const double lambda = smoothing * static_cast<double>(z.size()) / n;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
  Eigen::VectorXd row;
  for (std::size_t c = 0; c < z.size(); ++c) {
    PointRow(z[c], r, m, &row);
    a += row * row.transpose();
    b += row * values[c];
  }
  AddPenalties(s, lambda, 0.0, {}, &a);
  const Eigen::VectorXd expected = a.ldlt().solve(b);
  double worst = 0.0, scale = 0.0;
  for (int k = 0; k < n; ++k) {
    worst = std::max(worst, std::abs(phi[static_cast<std::size_t>(k)] - expected[k]));
    scale = std::max(scale, std::abs(expected[k]));
  }
  INFO("largest difference " << worst << " of " << scale);
  CHECK(worst < 1e-6 * scale);  // CG stops at a residual of 1e-8 of the right-hand side
}

TEST_CASE("smoothing spline: membrane, start and unknown nodes match the stated objective") {
  // Data over the left 60% of the square with a gap in the middle; tension > 0 and a non-zero
  // start, so the gap-weighted membrane, the ridge towards the start and the set of unknowns
  // all take part. The reference assembles the objective of the header densely and solves it
  // on the unknown nodes (the others fixed at 0).
  const int m = 6, s = m + 3, n = s * s;
  const double r = 1.0, smoothing = 0.02, tension = 10.0;
  Lcg rng(23);
  std::vector<Vec2> z;
  std::vector<double> values;
  while (z.size() < 150) {
    const Vec2 p(rng.Uniform(-r, 0.2), rng.Uniform(-r, r));
    if (std::abs(p.x + 0.4) < 0.12 && std::abs(p.y) < 0.3) continue;  // the gap
    z.push_back(p);
    values.push_back(std::cos(2 * p.x) * p.y + rng.Uniform(-0.02, 0.02));
  }
  std::vector<double> start(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) start[static_cast<std::size_t>(k)] = 0.1 * std::sin(0.7 * k);
  std::vector<double> phi = start;
  SmoothBsplineFit(z.data(), values.data(), z.size(), r, m, smoothing, tension, 2000, &phi);
  // Unknowns: nodes within one node of a point's 4 x 4 support; data weight per node.
  std::vector<char> active(static_cast<std::size_t>(n), 0);
  std::vector<double> omega(static_cast<std::size_t>(n), 0.0);
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(n), row;
  for (std::size_t c = 0; c < z.size(); ++c) {
    PointRow(z[c], r, m, &row);
    a += row * row.transpose();
    b += row * values[c];
    int i0 = s, j0 = s;
    for (int k = 0; k < n; ++k) {
      omega[static_cast<std::size_t>(k)] += row[k] * row[k];
      if (row[k] != 0.0) i0 = std::min(i0, k % s), j0 = std::min(j0, k / s);
    }
    for (int j = j0 - 1; j <= j0 + 4; ++j) {
      for (int i = i0 - 1; i <= i0 + 4; ++i) {
        if (i >= 0 && i < s && j >= 0 && j < s) active[static_cast<std::size_t>(j * s + i)] = 1;
      }
    }
  }
  double mean = 0.0, count = 0.0;
  for (int k = 0; k < n; ++k) {
    if (active[static_cast<std::size_t>(k)]) mean += omega[static_cast<std::size_t>(k)], ++count;
  }
  mean /= count;
  std::vector<double> gap(static_cast<std::size_t>(n));
  for (std::size_t k = 0; k < gap.size(); ++k) gap[k] = 0.1 * mean / (0.1 * mean + omega[k]);
  const double lambda = smoothing * static_cast<double>(z.size()) / n;
  AddPenalties(s, lambda, tension, gap, &a);
  for (int k = 0; k < n; ++k) {
    if (active[static_cast<std::size_t>(k)]) {
      b[k] += 1e-6 * lambda * start[static_cast<std::size_t>(k)];
    }
  }
  std::vector<int> ids;
  for (int k = 0; k < n; ++k) {
    if (active[static_cast<std::size_t>(k)]) ids.push_back(k);
  }
  const int na = static_cast<int>(ids.size());
  REQUIRE(na < n);  // some nodes are not unknowns
  Eigen::MatrixXd aa(na, na);
  Eigen::VectorXd ba(na);
  for (int x = 0; x < na; ++x) {
    ba[x] = b[ids[static_cast<std::size_t>(x)]];
    for (int y = 0; y < na; ++y)
      aa(x, y) = a(ids[static_cast<std::size_t>(x)], ids[static_cast<std::size_t>(y)]);
  }
  const Eigen::VectorXd expected = aa.ldlt().solve(ba);
  double worst = 0.0, scale = 0.0;
  for (int x = 0; x < na; ++x) {
    const double v = phi[static_cast<std::size_t>(ids[static_cast<std::size_t>(x)])];
    worst = std::max(worst, std::abs(v - expected[x]));
    scale = std::max(scale, std::abs(expected[x]));
  }
  for (int k = 0; k < n; ++k) {
    if (!active[static_cast<std::size_t>(k)]) REQUIRE(phi[static_cast<std::size_t>(k)] == 0.0);
  }
  INFO("largest difference " << worst << " of " << scale << " over " << na << " unknowns");
  CHECK(worst < 1e-6 * scale);
}

TEST_CASE("smoothing spline: a linear function is reproduced, nodes away from data stay 0") {
  const int m = 16, s = m + 3;
  const double r = 1.0;
  auto linear = [](Vec2 p) { return 0.3 + 0.7 * p.x - 0.4 * p.y; };
  Lcg rng(5);
  {
    // Data over the whole square: every node is an unknown and a linear function has no
    // thin-plate energy, so the fit is exact.
    std::vector<Vec2> z;
    std::vector<double> values;
    for (int c = 0; c < 800; ++c) {
      z.emplace_back(rng.Uniform(-r, r), rng.Uniform(-r, r));
      values.push_back(linear(z.back()));
    }
    std::vector<double> phi;
    SmoothBsplineFit(z.data(), values.data(), z.size(), r, m, 1e-3, 0.0, 1000, &phi);
    double worst = 0.0;
    for (int c = 0; c < 200; ++c) {
      const Vec2 p(rng.Uniform(-r, r), rng.Uniform(-r, r));
      worst = std::max(worst, std::abs(Eval(phi, p, r, m) - linear(p)));
    }
    CHECK(worst < 1e-6);
  }
  // Data only in the left part: nodes more than one node beyond every point's 4 x 4 support
  // (node positions above x = 0.25 here) keep a zero coefficient.
  std::vector<Vec2> z;
  std::vector<double> values;
  for (int c = 0; c < 400; ++c) {
    z.emplace_back(rng.Uniform(-r, -0.1), rng.Uniform(-r, r));
    values.push_back(linear(z.back()));
  }
  std::vector<double> phi;
  SmoothBsplineFit(z.data(), values.data(), z.size(), r, m, 1e-3, 0.0, 400, &phi);
  int zero = 0, nonzero_inside = 0;
  for (int j = 0; j < s; ++j) {
    for (int i = 0; i < s; ++i) {
      const double node_x = -r + (i - 1) * 2 * r / m;
      const double v = phi[static_cast<std::size_t>(j * s + i)];
      if (node_x > 0.3) {
        REQUIRE(v == 0.0);
        ++zero;
      }
      if (node_x < -0.3 && v != 0.0) ++nonzero_inside;
    }
  }
  CHECK(zero > 0);
  CHECK(nonzero_inside > 0);
  // Away from the edge of the data the fit is still close to the linear function (the zero
  // nodes beyond the edge pull the thin plate slightly towards 0 near it).
  double worst = 0.0;
  for (int c = 0; c < 200; ++c) {
    const Vec2 p(rng.Uniform(-0.9, -0.5), rng.Uniform(-0.9, 0.9));
    worst = std::max(worst, std::abs(Eval(phi, p, r, m) - linear(p)));
  }
  CHECK(worst < 1e-3);
}

TEST_CASE("smoothing spline: bends less than BA between noisy points, fitting them better") {
  // A fine lattice over scattered noisy samples of a smooth field: BA leaves a bump at each
  // point, the smoothing spline fits the points at least as well with less curvature.
  const double r = 1.0;
  const int levels = 6, m = 1 << (levels - 1);
  Lcg rng(9);
  auto field = [](Vec2 p) { return 0.2 * std::sin(2.5 * p.x) * std::cos(2.0 * p.y); };
  std::vector<Vec2> z;
  std::vector<double> values;
  for (int c = 0; c < 300; ++c) {
    z.emplace_back(rng.Uniform(-r, r), rng.Uniform(-r, r));
    values.push_back(field(z.back()) + rng.Uniform(-0.002, 0.002));
  }
  auto finest = [&](const MbaOptions& o) {
    std::vector<double> lattices;
    FitMultilevelBspline(z.data(), values.data(), z.size(), r, levels, &lattices, nullptr, o);
    return std::vector<double>(lattices.end() - BsplineLatticeSize(levels - 1), lattices.end());
  };
  MbaOptions plain, smooth;
  const std::vector<double> ba = finest(plain);
  smooth.smoothing = 0.03;  // about BA's error at the points
  const std::vector<double> sp = finest(smooth);
  auto data_error = [&](const std::vector<double>& phi) {
    double e = 0.0;
    for (std::size_t c = 0; c < z.size(); ++c) e += std::abs(Eval(phi, z[c], r, m) - values[c]);
    return e / static_cast<double>(z.size());
  };
  // Mean squared second derivatives by central differences on a grid inside the square, of a
  // function of the point.
  auto bending_of = [&](auto&& f) {
    const double h = 0.01;
    double sum = 0.0;
    int n = 0;
    for (double y = -0.85; y <= 0.85; y += 0.05) {
      for (double x = -0.85; x <= 0.85; x += 0.05) {
        const double c = f(Vec2(x, y));
        const double fxx = (f(Vec2(x + h, y)) - 2 * c + f(Vec2(x - h, y))) / (h * h);
        const double fyy = (f(Vec2(x, y + h)) - 2 * c + f(Vec2(x, y - h))) / (h * h);
        sum += fxx * fxx + fyy * fyy, ++n;
      }
    }
    return sum / n;
  };
  // The bending beyond the field's own: what the noise put in.
  const double own = bending_of(field);
  auto excess = [&](const std::vector<double>& phi) {
    return bending_of([&](Vec2 p) { return Eval(phi, p, r, m); }) - own;
  };
  INFO("field " << own << "; BA: data " << data_error(ba) << " excess bending " << excess(ba)
                << "; smoothing: data " << data_error(sp) << " excess bending " << excess(sp));
  CHECK(data_error(sp) <= data_error(ba));
  CHECK(excess(sp) < 0.85 * excess(ba));
}

TEST_CASE("smoothing spline: MBA keeps every coarser level as the plain fit") {
  Lcg rng(21);
  std::vector<Vec2> z;
  std::vector<double> values;
  for (int c = 0; c < 500; ++c) {
    z.emplace_back(rng.Uniform(-0.7, 0.7), rng.Uniform(-0.7, 0.7));
    values.push_back(std::sin(4 * z.back().x) + rng.Uniform(-0.01, 0.01));
  }
  std::vector<double> plain, smooth;
  FitMultilevelBspline(z.data(), values.data(), z.size(), 0.8, 6, &plain);
  MbaOptions o;
  o.smoothing = 5e-4;
  o.finest_passes = 3;
  FitMultilevelBspline(z.data(), values.data(), z.size(), 0.8, 6, &smooth, nullptr, o);
  REQUIRE(plain.size() == smooth.size());
  const std::size_t coarse = plain.size() - static_cast<std::size_t>(BsplineLatticeSize(5));
  for (std::size_t i = 0; i < coarse; ++i) REQUIRE(plain[i] == smooth[i]);
  bool finest_differs = false;
  for (std::size_t i = coarse; i < plain.size(); ++i) finest_differs |= plain[i] != smooth[i];
  CHECK(finest_differs);
}
