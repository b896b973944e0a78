// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Deformer quality benchmark: LBS, DQS and the sweep deformer side by side.
//
// Part 1, the cylinder experiment of docs/notes/sweep.md section 3: a solid cylinder (radius 1,
// x in [-4, 4]) on a 3-joint chain (joints at x = -4, 0, 4), smoothstep weights over |x| < h (h = 1
// and 1.5). Bend joint 1 about z by 90/120/150 degrees and report occupied volume, signed
// volume, folded volume and the thickness at the joint; twist it about x (animated 0..360
// degrees) and report the minimum radius, the largest twist rate and frame-to-frame jumps.
// Part 2: the shared glTF characters, every clip sampled evenly: largest relative change of the
// enclosed volume and largest frame-to-frame vertex jump per deformer (the dense glTF vertices
// deformed directly).
// Part 3 (deform_real_rigs.cpp): the shared rigs fitted and posed on their lod surface: bends and
// twists built on their own skeletons, and every clip.
//
// It prints numbers and asserts nothing. Metric definitions: see PrintDefinitions() below.
// Usage (from the repo root):
//   bench_deform [--spacing D] [--voxel V] [--ring-points N] [--twist-step DEG]
//                [--frames F] [--data DIR] [--level L] [--no-characters] [--no-cylinder]
//                [--no-real-rigs] [--no-clips] [--only NAME] [--pictures DIR]
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "deform_real_rigs.h"
#include "dermis/asset/asset.h"
#include "dermis/asset/asset_pose.h"
#include "dermis/asset/asset_validate.h"
#include "dermis/deform/deformer.h"
#include "dermis/deform/sweep_chains.h"
#include "dermis/plugins/gltf.h"

using namespace dermis;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRadius = 1.0;
constexpr double kHalfLength = 4.0;

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

// ---------------------------------------------------------------------------------------------
// Deformer variants.

struct Variant {
  std::string label;
  DeformerKind kind = DeformerKind::kLbs;
  SweepOptions sweep;
  // True: blend_radius_factor = h / r90, r90 = the 90th percentile of the sample's distance from
  // the axis over |x| <= 2 (what sweep_deformer.cpp takes as the joint's r when this was
  // written), so that the sweep's blend half-length equals the weights' h.
  bool match_h = false;
};

std::vector<Variant> CylinderVariants() {
  std::vector<Variant> v(5);
  v[0].label = "lbs";
  v[0].kind = DeformerKind::kLbs;
  v[1].label = "dqs";
  v[1].kind = DeformerKind::kDqs;
  v[2].label = "sweep";
  v[2].kind = DeformerKind::kSweep;
  v[3].label = "sweep novol";
  v[3].kind = DeformerKind::kSweep;
  v[3].sweep.preserve_volume = false;
  v[4].label = "sweep h-match";
  v[4].kind = DeformerKind::kSweep;
  v[4].match_h = true;
  return v;
}

Status MakeVariant(const Variant& variant, double h, double r90, const SkinRig& rig,
                   const std::vector<Vec3>& rest, const std::vector<VertexWeights>& weights,
                   std::unique_ptr<Deformer>* out) {
  if (variant.kind == DeformerKind::kSweep) {
    SweepOptions o = variant.sweep;
    if (variant.match_h) o.blend_radius_factor = h / r90;
    return MakeSweepDeformer(rig, rest.data(), nullptr, weights.data(), rest.size(), o, out);
  }
  return MakeDeformer(variant.kind, rig, rest.data(), nullptr, weights.data(), rest.size(), out);
}

// ---------------------------------------------------------------------------------------------
// Cylinder rig, weights and poses.

SkinRig CylinderRig() {
  SkinRig rig;
  rig.parents = {-1, 0, 1};
  rig.names = {"root", "joint", "end"};
  for (double x : {-kHalfLength, 0.0, kHalfLength}) {
    rig.bind.push_back(glm::translate(glm::dmat4(1.0), Vec3(x, 0.0, 0.0)));
  }
  return rig;
}

// w1(x) = smoothstep over [-h, h]: 0 at x = -h, 1 at x = +h; w0 = 1 - w1; joint 2 unweighted.
std::vector<VertexWeights> CylinderWeights(const std::vector<Vec3>& points, double h) {
  std::vector<VertexWeights> w(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double t = std::clamp((points[i].x + h) / (2.0 * h), 0.0, 1.0);
    const double w1 = t * t * (3.0 - 2.0 * t);
    w[i].joints = glm::u16vec4(0, 1, 0, 0);
    w[i].weights = glm::vec4(static_cast<float>(1.0 - w1), static_cast<float>(w1), 0.0f, 0.0f);
  }
  return w;
}

// Every vertex fully on joint 1: a rigid motion, the sanity check of the metrics.
std::vector<VertexWeights> RigidWeights(std::size_t n) {
  std::vector<VertexWeights> w(n);
  for (VertexWeights& v : w) {
    v.joints = glm::u16vec4(1, 0, 0, 0);
    v.weights = glm::vec4(1.0f, 0.0f, 0.0f, 0.0f);
  }
  return w;
}

// Skin matrices rotating joint 1 (at the origin) and its child by `angle` about `axis`:
// T(0) * R * T(0)^-1; joint 0 stays put.
std::array<glm::dmat4, 3> JointPose(double angle_deg, const Vec3& axis) {
  const Vec3 joint(0.0);
  const glm::dmat4 m = glm::translate(glm::dmat4(1.0), joint) *
                       glm::rotate(glm::dmat4(1.0), angle_deg * kPi / 180.0, axis) *
                       glm::translate(glm::dmat4(1.0), -joint);
  return {glm::dmat4(1.0), m, m};
}

// ---------------------------------------------------------------------------------------------
// The solid sample: grid cells of spacing ~d whose centres lie inside the cylinder; their corner
// nodes are the deformed "vertices". Each cell is split into the 6 Kuhn tetrahedra (around the
// diagonal from corner 0 to corner 7; a conforming split), on which the deformation is taken
// piecewise linear.

constexpr int kKuhn[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7},
                             {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};

struct SolidSample {
  double dx = 0.0, dyz = 0.0;
  std::vector<Vec3> nodes;                // Cell corners, then the two probes.
  std::vector<std::array<int, 8>> cells;  // Corner c at (+dx*(c&1), +dyz*(c>>1&1), +dyz*(c>>2&1)).
  std::size_t grid_nodes = 0;             // nodes[0, grid_nodes) are cell corners.
  std::size_t probe_plus = 0, probe_minus = 0;  // (0, +1, 0) and (0, -1, 0).
  std::array<double, 6> rest_sign{};            // Orientation of each Kuhn tet at rest.
  double r90 = 0.0;  // 90th percentile of the nodes' distance from the axis, |x| <= 2.
};

// The 90th percentile of the distance from the x axis of the points with |x| <= 2 (half a bone
// from the joint), as the sweep deformer measures a joint's radius.
double Radius90(const std::vector<Vec3>& points) {
  std::vector<double> r;
  for (const Vec3& p : points) {
    if (std::fabs(p.x) <= 0.5 * kHalfLength) r.push_back(std::hypot(p.y, p.z));
  }
  if (r.empty()) return 1.0;
  std::sort(r.begin(), r.end());
  return r[std::min(r.size() - 1, static_cast<std::size_t>(0.9 * static_cast<double>(r.size())))];
}

SolidSample BuildSolid(double spacing) {
  SolidSample s;
  const int nx = std::max(2, static_cast<int>(std::lround(2.0 * kHalfLength / spacing)));
  const int ny = std::max(2, static_cast<int>(std::lround(2.0 * kRadius / spacing)));
  s.dx = 2.0 * kHalfLength / nx;
  s.dyz = 2.0 * kRadius / ny;
  const auto node_id = [&](int i, int j, int k) {
    return (static_cast<std::size_t>(i) * static_cast<std::size_t>(ny + 1) +
            static_cast<std::size_t>(j)) *
               static_cast<std::size_t>(ny + 1) +
           static_cast<std::size_t>(k);
  };
  std::vector<int> index(node_id(nx, ny, ny) + 1, -1);
  for (int i = 0; i < nx; ++i) {
    for (int j = 0; j < ny; ++j) {
      for (int k = 0; k < ny; ++k) {
        const double yc = -kRadius + (j + 0.5) * s.dyz, zc = -kRadius + (k + 0.5) * s.dyz;
        if (yc * yc + zc * zc > kRadius * kRadius) continue;
        std::array<int, 8> cell{};
        for (int c = 0; c < 8; ++c) {
          const int ci = i + (c & 1), cj = j + ((c >> 1) & 1), ck = k + ((c >> 2) & 1);
          int& id = index[node_id(ci, cj, ck)];
          if (id < 0) {
            id = static_cast<int>(s.nodes.size());
            s.nodes.emplace_back(-kHalfLength + ci * s.dx, -kRadius + cj * s.dyz,
                                 -kRadius + ck * s.dyz);
          }
          cell[static_cast<std::size_t>(c)] = id;
        }
        s.cells.push_back(cell);
      }
    }
  }
  s.grid_nodes = s.nodes.size();
  s.r90 = Radius90(s.nodes);
  s.probe_plus = s.nodes.size();
  s.nodes.emplace_back(0.0, kRadius, 0.0);
  s.probe_minus = s.nodes.size();
  s.nodes.emplace_back(0.0, -kRadius, 0.0);
  for (int t = 0; t < 6; ++t) {
    Vec3 corner[4];
    for (int q = 0; q < 4; ++q) {
      const int c = kKuhn[t][q];
      corner[q] = Vec3(c & 1, (c >> 1) & 1, (c >> 2) & 1);
    }
    const double det = glm::determinant(
        glm::dmat3(corner[1] - corner[0], corner[2] - corner[0], corner[3] - corner[0]));
    s.rest_sign[static_cast<std::size_t>(t)] = det > 0.0 ? 1.0 : -1.0;
  }
  return s;
}

struct SolidMetrics {
  std::size_t covered = 0;  // Lattice points covered by the image (each once).
  double signed_volume = 0.0;
  double folded_volume = 0.0;  // Rest volume of the tets whose image has det <= 0.
  double thick = 0.0;
};

// Rasterises the piecewise-linear image of the solid on a lattice of spacing `voxel` (points at
// (n + delta) * voxel, delta slightly off the cell centres so that no lattice point sits on a
// rest face); counts the covered lattice points once each. Also signed and folded volume.
SolidMetrics MeasureSolid(const SolidSample& s, const std::vector<Vec3>& p, double voxel) {
  SolidMetrics m;
  const Vec3 delta(0.5123, 0.5234, 0.5345);
  Vec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  for (std::size_t i = 0; i < s.grid_nodes; ++i) {
    lo = glm::min(lo, p[i]);
    hi = glm::max(hi, p[i]);
  }
  const glm::dvec3 n0 = glm::floor(lo / voxel - delta) - 1.0;
  const glm::dvec3 n1 = glm::ceil(hi / voxel - delta) + 1.0;
  const std::array<std::int64_t, 3> size = {static_cast<std::int64_t>(n1.x - n0.x) + 1,
                                            static_cast<std::int64_t>(n1.y - n0.y) + 1,
                                            static_cast<std::int64_t>(n1.z - n0.z) + 1};
  std::vector<std::uint8_t> covered(static_cast<std::size_t>(size[0] * size[1] * size[2]), 0);
  const double rest_tet = s.dx * s.dyz * s.dyz / 6.0;
  const double tiny = 1e-14 * s.dx * s.dyz * s.dyz;
  const double eps = 1e-12;
  for (const std::array<int, 8>& cell : s.cells) {
    for (int t = 0; t < 6; ++t) {
      const Vec3& a = p[static_cast<std::size_t>(cell[static_cast<std::size_t>(kKuhn[t][0])])];
      const Vec3& b = p[static_cast<std::size_t>(cell[static_cast<std::size_t>(kKuhn[t][1])])];
      const Vec3& c = p[static_cast<std::size_t>(cell[static_cast<std::size_t>(kKuhn[t][2])])];
      const Vec3& d = p[static_cast<std::size_t>(cell[static_cast<std::size_t>(kKuhn[t][3])])];
      const glm::dmat3 e(b - a, c - a, d - a);
      const double det = glm::determinant(e) * s.rest_sign[static_cast<std::size_t>(t)];
      m.signed_volume += det / 6.0;
      if (det <= 0.0) m.folded_volume += rest_tet;
      if (std::fabs(det) <= tiny) continue;
      const glm::dmat3 inv = glm::inverse(e);
      const Vec3 tlo = glm::min(glm::min(a, b), glm::min(c, d));
      const Vec3 thi = glm::max(glm::max(a, b), glm::max(c, d));
      const glm::dvec3 i0 = glm::ceil(tlo / voxel - delta) - n0;
      const glm::dvec3 i1 = glm::floor(thi / voxel - delta) - n0;
      for (auto ix = static_cast<std::int64_t>(i0.x); ix <= static_cast<std::int64_t>(i1.x); ++ix) {
        for (auto iy = static_cast<std::int64_t>(i0.y); iy <= static_cast<std::int64_t>(i1.y);
             ++iy) {
          for (auto iz = static_cast<std::int64_t>(i0.z); iz <= static_cast<std::int64_t>(i1.z);
               ++iz) {
            const auto idx = static_cast<std::size_t>((ix * size[1] + iy) * size[2] + iz);
            if (covered[idx]) continue;
            const Vec3 q = (n0 +
                            glm::dvec3(static_cast<double>(ix), static_cast<double>(iy),
                                       static_cast<double>(iz)) +
                            delta) *
                               voxel -
                           a;
            const Vec3 l = inv * q;
            if (l.x >= -eps && l.y >= -eps && l.z >= -eps && l.x + l.y + l.z <= 1.0 + eps) {
              covered[idx] = 1;
              ++m.covered;
            }
          }
        }
      }
    }
  }
  m.thick = glm::length(p[s.probe_plus] - p[s.probe_minus]);
  return m;
}

// ---------------------------------------------------------------------------------------------
// The surface sample of the twist experiment: rings of `per_ring` points on the radius-1
// surface at x = -4 + i * dx.

struct RingSample {
  int rings = 0, per_ring = 0;
  double dx = 0.0;
  std::vector<Vec3> points;  // Ring i, point k at i * per_ring + k.
  double r90 = 1.0;
};

RingSample BuildRings(double spacing, int per_ring) {
  RingSample r;
  const int nx = std::max(2, static_cast<int>(std::lround(2.0 * kHalfLength / spacing)));
  r.rings = nx + 1;
  r.per_ring = per_ring;
  r.dx = 2.0 * kHalfLength / nx;
  for (int i = 0; i < r.rings; ++i) {
    for (int k = 0; k < per_ring; ++k) {
      const double psi = 2.0 * kPi * k / per_ring;
      r.points.emplace_back(-kHalfLength + i * r.dx, kRadius * std::cos(psi),
                            kRadius * std::sin(psi));
    }
  }
  return r;
}

struct TwistMetrics {
  double min_radius = 0.0;
  double max_rate = 0.0;  // Infinity if a ring collapsed onto the axis.
};

TwistMetrics MeasureTwist(const RingSample& r, const std::vector<Vec3>& rest,
                          const std::vector<Vec3>& p) {
  TwistMetrics m;
  m.min_radius = std::numeric_limits<double>::max();
  std::vector<double> angle(static_cast<std::size_t>(r.rings));
  bool collapsed = false;
  for (int i = 0; i < r.rings; ++i) {
    double re = 0.0, im = 0.0, mean_radius = 0.0;
    for (int k = 0; k < r.per_ring; ++k) {
      const std::size_t v = static_cast<std::size_t>(i) * static_cast<std::size_t>(r.per_ring) +
                            static_cast<std::size_t>(k);
      const double radius = std::hypot(p[v].y, p[v].z);
      m.min_radius = std::min(m.min_radius, radius);
      mean_radius += radius / r.per_ring;
      // (y' + i z') * conj(y + i z): the rotation of this point about the x axis.
      re += p[v].y * rest[v].y + p[v].z * rest[v].z;
      im += p[v].z * rest[v].y - p[v].y * rest[v].z;
    }
    if (mean_radius < 1e-6 || std::hypot(re, im) < 1e-9 * r.per_ring) collapsed = true;
    angle[static_cast<std::size_t>(i)] = std::atan2(im, re);
  }
  for (std::size_t i = 0; i + 1 < angle.size(); ++i) {
    double da = std::remainder(angle[i + 1] - angle[i], 2.0 * kPi);
    m.max_rate = std::max(m.max_rate, std::fabs(da) / r.dx);
  }
  if (collapsed) m.max_rate = std::numeric_limits<double>::infinity();
  return m;
}

// ---------------------------------------------------------------------------------------------
// Part 1 drivers.

struct BendRow {
  bool ok = false;
  std::string error;
  std::array<SolidMetrics, 3> metrics{};
};

BendRow RunBend(const SolidSample& s, const std::vector<VertexWeights>& weights, const Variant& v,
                double h, const std::array<double, 3>& angles, double voxel) {
  BendRow row;
  const SkinRig rig = CylinderRig();
  std::unique_ptr<Deformer> deformer;
  Status st = MakeVariant(v, h, s.r90, rig, s.nodes, weights, &deformer);
  if (!st.ok()) {
    row.error = st.message();
    return row;
  }
  std::vector<Vec3> p(s.nodes.size());
  for (std::size_t a = 0; a < angles.size(); ++a) {
    const std::array<glm::dmat4, 3> pose = JointPose(angles[a], Vec3(0.0, 0.0, 1.0));
    deformer->ResetHistory();
    st = deformer->SetPose(pose.data());
    if (!st.ok()) {
      row.error = st.message();
      return row;
    }
    deformer->Deform(0, p.size(), p.data(), nullptr);
    row.metrics[a] = MeasureSolid(s, p, voxel);
  }
  row.ok = true;
  return row;
}

struct TwistRow {
  bool ok = false;
  std::string error;
  std::array<TwistMetrics, 4> metrics{};
  std::array<double, 4> jump{};  // Largest frame-to-frame vertex jump since the previous angle.
};

// Animates the twist from 0 to 360 degrees in `step` degree steps (ResetHistory once at the
// start); records the metrics at 90, 180, 270, 360 degrees.
TwistRow RunTwist(const RingSample& r, const std::vector<VertexWeights>& weights, const Variant& v,
                  double h, double step) {
  TwistRow row;
  const SkinRig rig = CylinderRig();
  std::unique_ptr<Deformer> deformer;
  Status st = MakeVariant(v, h, r.r90, rig, r.points, weights, &deformer);
  if (!st.ok()) {
    row.error = st.message();
    return row;
  }
  deformer->ResetHistory();
  std::vector<Vec3> p(r.points.size()), prev(r.points.size());
  const int steps = static_cast<int>(std::lround(360.0 / step));
  const int per_record = steps / 4;
  double jump = 0.0;
  for (int f = 0; f <= steps; ++f) {
    const std::array<glm::dmat4, 3> pose = JointPose(f * step, Vec3(1.0, 0.0, 0.0));
    st = deformer->SetPose(pose.data());
    if (!st.ok()) {
      row.error = st.message();
      return row;
    }
    deformer->Deform(0, p.size(), p.data(), nullptr);
    if (f > 0) {
      for (std::size_t i = 0; i < p.size(); ++i) jump = std::max(jump, glm::length(p[i] - prev[i]));
    }
    if (f > 0 && f % per_record == 0) {
      const auto k = static_cast<std::size_t>(f / per_record - 1);
      row.metrics[k] = MeasureTwist(r, r.points, p);
      row.jump[k] = jump;
      jump = 0.0;
    }
    std::swap(p, prev);
  }
  row.ok = true;
  return row;
}

void PrintDefinitions() {
  std::printf(
      "Definitions:\n"
      "  occ    = lattice points (spacing = grid spacing, offset off the rest cell centres) "
      "covered by\n"
      "           the piecewise-linear image of the solid (6 Kuhn tets per grid cell, each "
      "lattice\n"
      "           point counted once however many tets cover it) / the same count at rest.\n"
      "  vol    = signed volume of the image (sum of tet determinants) / rest volume; hides "
      "folds.\n"
      "  folded = share of the rest volume (tets) whose image has det J <= 0 (J = the tet's\n"
      "           forward-difference Jacobian over grid neighbours).\n"
      "  thick  = |image(0,+1,0) - image(0,-1,0)| (rest 2).\n"
      "  minR   = min over all surface ring points of the distance from the x axis (rest 1).\n"
      "  rate   = max over adjacent rings of |d(twist angle)|/dx, the ring's twist angle being\n"
      "           arg sum_k (y'+iz')(y-iz) over its points (rad per unit); inf: a ring collapsed.\n"
      "  jump   = largest displacement of a surface point between consecutive twist frames since\n"
      "           the previous row's angle (a rigid point at radius 1 moves 2 sin(step/2)).\n");
}

void RunCylinder(double spacing, double voxel_ratio, int ring_points, double twist_step) {
  const auto start = std::chrono::steady_clock::now();
  const SolidSample solid = BuildSolid(spacing);
  const std::array<double, 2> hs = {1.0, 1.5};
  const std::array<double, 3> bends = {90.0, 120.0, 150.0};
  const std::vector<Variant> variants = CylinderVariants();

  // Rest reference count: the identity image.
  const double voxel = solid.dx * voxel_ratio;
  const std::size_t rest_count = MeasureSolid(solid, solid.nodes, voxel).covered;
  const double rest_volume =
      static_cast<double>(solid.cells.size()) * solid.dx * solid.dyz * solid.dyz;

  std::printf(
      "== Cylinder bend (docs/notes/sweep.md section 3): solid r=1, x in [-4,4], joints at "
      "x=-4,0,4;\n"
      "   grid spacing %.4f x %.4f, %zu cells, %zu nodes, voxel lattice %.4f, rest lattice count "
      "%zu\n"
      "   (rest volume %.4f vs pi*8 = %.4f); smoothstep weights over |x|<h, h=1 | h=1.5\n",
      solid.dx, solid.dyz, solid.cells.size(), solid.grid_nodes, voxel, rest_count, rest_volume,
      8.0 * kPi);
  std::printf(
      "   sweep, sweep novol: SweepOptions defaults (blend half-length from the sample's radius, "
      "not "
      "h);\n"
      "   sweep h-match: blend_radius_factor = h / %.4f (90th percentile of the node distance from "
      "the axis)\n",
      solid.r90);
  std::printf("%-14s %5s | %6s %6s %7s %6s | %6s %6s %7s %6s\n", "deformer", "bend", "occ", "vol",
              "folded", "thick", "occ", "vol", "folded", "thick");
  const auto print_group = [&](const BendRow& row, std::size_t a) {
    if (!row.ok) return;
    const SolidMetrics& m = row.metrics[a];
    // Rasterising the rest configuration with the same lattice gives rest_count; measure the
    // deformed one with the same lattice spacing.
    std::printf(" | %6.3f %6.3f %7.3f %6.3f",
                static_cast<double>(m.covered) / static_cast<double>(rest_count),
                m.signed_volume / rest_volume, m.folded_volume / rest_volume, m.thick);
  };
  for (const Variant& v : variants) {
    std::array<BendRow, 2> rows;
    for (std::size_t k = 0; k < hs.size(); ++k) {
      rows[k] = RunBend(solid, CylinderWeights(solid.nodes, hs[k]), v, hs[k], bends, voxel);
    }
    if (!rows[0].ok || !rows[1].ok) {
      std::printf("%s: n/a (%s)\n", v.label.c_str(),
                  (!rows[0].ok ? rows[0].error : rows[1].error).c_str());
      continue;
    }
    for (std::size_t a = 0; a < bends.size(); ++a) {
      std::printf("%-14s %5.0f", v.label.c_str(), bends[a]);
      for (const BendRow& row : rows) print_group(row, a);
      std::printf("\n");
    }
  }
  {
    Variant lbs;
    lbs.label = "rigid (check)";
    const BendRow row = RunBend(solid, RigidWeights(solid.nodes.size()), lbs, 1.0, bends, voxel);
    for (std::size_t a = 0; a < bends.size(); ++a) {
      std::printf("%-14s %5.0f", lbs.label.c_str(), bends[a]);
      print_group(row, a);
      print_group(row, a);
      std::printf("\n");
    }
  }
  std::printf(
      "   (docs/notes/sweep.md [exp] at h=1: lbs 90: occ 0.964 thick 1.41; dqs 90: occ 0.994 "
      "folded "
      "0.003 thick 2.00)\n");
  std::printf("   bend part: %.1f s\n\n", Seconds(start));

  const auto twist_start = std::chrono::steady_clock::now();
  const RingSample rings = BuildRings(spacing, ring_points);
  const int per_quarter = std::max(1, static_cast<int>(std::lround(90.0 / twist_step)));
  const double step = 90.0 / per_quarter;
  std::printf(
      "== Cylinder twist of joint 1 about x, animated 0..360 deg in %.3g deg steps (ResetHistory "
      "once);\n"
      "   surface rings: %d rings (dx %.4f) x %d points; h=1 | h=1.5\n",
      step, rings.rings, rings.dx, rings.per_ring);
  std::printf("   sweep h-match: blend_radius_factor = h / %.4f\n", rings.r90);
  std::printf("%-14s %5s | %6s %7s %6s | %6s %7s %6s\n", "deformer", "twist", "minR", "rate",
              "jump", "minR", "rate", "jump");
  for (const Variant& v : variants) {
    std::array<TwistRow, 2> rows;
    for (std::size_t k = 0; k < hs.size(); ++k) {
      rows[k] = RunTwist(rings, CylinderWeights(rings.points, hs[k]), v, hs[k], step);
    }
    if (!rows[0].ok || !rows[1].ok) {
      std::printf("%s: n/a (%s)\n", v.label.c_str(),
                  (!rows[0].ok ? rows[0].error : rows[1].error).c_str());
      continue;
    }
    for (std::size_t a = 0; a < 4; ++a) {
      std::printf("%-14s %5.0f", v.label.c_str(), 90.0 * static_cast<double>(a + 1));
      for (const TwistRow& row : rows) {
        std::printf(" | %6.3f %7.3f %6.3f", row.metrics[a].min_radius, row.metrics[a].max_rate,
                    row.jump[a]);
      }
      std::printf("\n");
    }
  }
  std::printf(
      "   (docs/notes/sweep.md: minR at 90/180: lbs 0.707/0, dqs 1/1, sweep 1/1; rate: dqs ~3.0 at "
      "h=1, "
      "sweep pi/4 = 0.785 over a bone of length 4)\n");
  std::printf("   twist part: %.1f s\n\n", Seconds(twist_start));
  PrintDefinitions();
  std::printf("\n");
}

// ---------------------------------------------------------------------------------------------
// Part 2: the shared characters.

std::vector<std::array<std::uint32_t, 3>> Triangles(const AssetPrimitive& prim) {
  std::vector<std::array<std::uint32_t, 3>> tris;
  std::vector<std::uint32_t> idx = prim.indices;
  if (idx.empty()) {
    idx.resize(prim.positions.size());
    for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = static_cast<std::uint32_t>(i);
  }
  if (prim.mode == PrimitiveMode::kTriangles) {
    for (std::size_t i = 0; i + 2 < idx.size(); i += 3)
      tris.push_back({idx[i], idx[i + 1], idx[i + 2]});
  } else if (prim.mode == PrimitiveMode::kTriangleStrip) {
    for (std::size_t i = 0; i + 2 < idx.size(); ++i) {
      if (i % 2 == 0) {
        tris.push_back({idx[i], idx[i + 1], idx[i + 2]});
      } else {
        tris.push_back({idx[i + 1], idx[i], idx[i + 2]});
      }
    }
  } else if (prim.mode == PrimitiveMode::kTriangleFan) {
    for (std::size_t i = 1; i + 1 < idx.size(); ++i) tris.push_back({idx[0], idx[i], idx[i + 1]});
  }
  return tris;
}

// Boundary and non-manifold edge counts after welding vertices with equal positions (glTF
// splits vertices at UV seams); both 0 and consistently oriented: closed.
struct Closedness {
  std::size_t boundary = 0, nonmanifold = 0, misoriented = 0;
  bool closed() const { return boundary == 0 && nonmanifold == 0 && misoriented == 0; }
};

Closedness CheckClosed(const std::vector<glm::vec3>& positions,
                       const std::vector<std::array<std::uint32_t, 3>>& tris) {
  std::map<std::array<float, 3>, std::uint32_t> weld;
  std::vector<std::uint32_t> id(positions.size());
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const std::array<float, 3> key = {positions[i].x, positions[i].y, positions[i].z};
    id[i] = weld.emplace(key, static_cast<std::uint32_t>(weld.size())).first->second;
  }
  // Directed edge counts.
  std::unordered_map<std::uint64_t, int> directed;
  for (const auto& t : tris) {
    for (int e = 0; e < 3; ++e) {
      const std::uint64_t a = id[t[static_cast<std::size_t>(e)]];
      const std::uint64_t b = id[t[static_cast<std::size_t>((e + 1) % 3)]];
      if (a != b) ++directed[(a << 32) | b];
    }
  }
  Closedness c;
  for (const auto& [key, n] : directed) {
    const std::uint64_t a = key >> 32, b = key & 0xffffffffu;
    const auto it = directed.find((b << 32) | a);
    const int back = it == directed.end() ? 0 : it->second;
    if (a < b || back == 0) {
      const int total = n + back;
      if (total == 1) ++c.boundary;
      if (total > 2) ++c.nonmanifold;
      if (total == 2 && back != 1) ++c.misoriented;
    }
  }
  return c;
}

// Signed volume enclosed by the triangles, about the vertex centroid (so that it does not depend
// on translation even when the mesh is open).
double SignedVolume(const std::vector<Vec3>& p,
                    const std::vector<std::array<std::uint32_t, 3>>& tris) {
  Vec3 c(0.0);
  for (const Vec3& x : p) c += x;
  c /= static_cast<double>(std::max<std::size_t>(1, p.size()));
  double v = 0.0;
  for (const auto& t : tris) {
    v += glm::dot(p[t[0]] - c, glm::cross(p[t[1]] - c, p[t[2]] - c));
  }
  return v / 6.0;
}

double BoxDiagonal(const std::vector<Vec3>& p) {
  if (p.empty()) return 0.0;
  Vec3 lo = p[0], hi = p[0];
  for (const Vec3& x : p) {
    lo = glm::min(lo, x);
    hi = glm::max(hi, x);
  }
  return glm::length(hi - lo);
}

std::vector<Variant> CharacterVariants() {
  std::vector<Variant> v = CylinderVariants();
  v.pop_back();  // No h to match on a character.
  return v;
}

void RunCharacter(const std::string& path, int frames) {
  const auto start = std::chrono::steady_clock::now();
  const std::string name = std::filesystem::path(path).filename().string();
  if (!std::filesystem::exists(path)) {
    std::printf("%s: skipped (not found: %s)\n", name.c_str(), path.c_str());
    return;
  }
  Asset asset;
  Status st = ImportGltf(path, &asset);
  if (st.ok()) st = ValidateAsset(asset);
  if (!st.ok()) {
    std::printf("%s: skipped (%s)\n", name.c_str(), st.message().c_str());
    return;
  }
  const std::vector<Variant> variants = CharacterVariants();
  std::printf("%s: %zu nodes, %zu skins, %zu clips\n", name.c_str(), asset.nodes.size(),
              asset.skins.size(), asset.animations.size());
  if (asset.animations.empty()) {
    std::printf("  no animation clips: nothing to sample\n");
    return;
  }
  // Per clip, the poses sampled evenly over its duration: node world matrices.
  std::vector<std::vector<std::vector<glm::dmat4>>> worlds(asset.animations.size());
  std::vector<std::vector<AssetPose>> poses(asset.animations.size());
  for (std::size_t a = 0; a < asset.animations.size(); ++a) {
    const double duration = asset.animations[a].Duration();
    for (int f = 0; f < frames; ++f) {
      const double t = frames > 1 ? duration * f / (frames - 1) : 0.0;
      AssetPose pose;
      SamplePose(asset, static_cast<int>(a), t, &pose);
      std::vector<glm::dmat4> world;
      ComputeWorldMatrices(asset, pose, &world);
      worlds[a].push_back(std::move(world));
      poses[a].push_back(std::move(pose));
    }
  }
  for (std::size_t n = 0; n < asset.nodes.size(); ++n) {
    const AssetNode& node = asset.nodes[n];
    if (node.mesh < 0 || node.skin < 0) continue;
    const AssetMesh& mesh = asset.meshes[static_cast<std::size_t>(node.mesh)];
    const AssetSkin& skin = asset.skins[static_cast<std::size_t>(node.skin)];
    // The rig: parents = nearest ancestor that is a joint of this skin.
    SkinRig rig;
    std::unordered_map<Index, Index> joint_of_node;
    for (std::size_t j = 0; j < skin.joints.size(); ++j) {
      joint_of_node[skin.joints[j]] = static_cast<Index>(j);
    }
    for (std::size_t j = 0; j < skin.joints.size(); ++j) {
      Index parent = -1;
      for (Index up = asset.nodes[static_cast<std::size_t>(skin.joints[j])].parent; up >= 0;
           up = asset.nodes[static_cast<std::size_t>(up)].parent) {
        const auto it = joint_of_node.find(up);
        if (it != joint_of_node.end()) {
          parent = it->second;
          break;
        }
      }
      rig.parents.push_back(parent);
      rig.bind.push_back(j < skin.inverse_bind_matrices.size()
                             ? glm::inverse(glm::dmat4(skin.inverse_bind_matrices[j]))
                             : glm::dmat4(1.0));
      rig.names.push_back(asset.nodes[static_cast<std::size_t>(skin.joints[j])].name);
    }
    for (std::size_t pi = 0; pi < mesh.primitives.size(); ++pi) {
      const AssetPrimitive& prim = mesh.primitives[pi];
      const std::string label =
          "  node " + std::to_string(n) + " '" + node.name + "' prim " + std::to_string(pi);
      if (prim.joints.empty() || prim.weights.empty()) {
        std::printf("%s: no JOINTS_0/WEIGHTS_0, skipped\n", label.c_str());
        continue;
      }
      const std::vector<std::array<std::uint32_t, 3>> tris = Triangles(prim);
      if (tris.empty()) {
        std::printf("%s: not a triangle primitive, skipped\n", label.c_str());
        continue;
      }
      const std::size_t count = prim.positions.size();
      std::vector<Vec3> rest(count);
      for (std::size_t i = 0; i < count; ++i) rest[i] = Vec3(prim.positions[i]);
      std::vector<VertexWeights> influences(count);
      std::size_t unweighted = 0;
      for (std::size_t i = 0; i < count; ++i) {
        glm::vec4 w = glm::max(prim.weights[0][i], glm::vec4(0.0f));
        const float sum = w.x + w.y + w.z + w.w;
        if (!(sum > 0.0f)) {
          ++unweighted;
          influences[i].joints = glm::u16vec4(0);
          influences[i].weights = glm::vec4(1.0f, 0.0f, 0.0f, 0.0f);
          continue;
        }
        influences[i].joints = prim.joints[0][i];
        influences[i].weights = w / sum;
      }
      const Closedness closed = CheckClosed(prim.positions, tris);
      std::printf("%s: %zu vertices, %zu triangles, %zu joints, %s", label.c_str(), count,
                  tris.size(), skin.joints.size(),
                  closed.closed() ? "closed" : "OPEN (volume not meaningful)");
      if (!closed.closed()) {
        std::printf(" [%zu boundary, %zu non-manifold, %zu misoriented edges]", closed.boundary,
                    closed.nonmanifold, closed.misoriented);
      }
      if (prim.joints.size() > 1) {
        std::printf(", %zu influence sets (only set 0 used)", prim.joints.size());
      }
      if (unweighted > 0) std::printf(", %zu unweighted vertices put on joint 0", unweighted);
      if (!prim.targets.empty()) std::printf(", morph targets ignored");
      std::printf("\n");
      const double rest_volume = SignedVolume(rest, tris);
      std::printf("    rest (bind shape) signed volume %.6g\n", rest_volume);
      // The sweep's chains (sweep_chains.h): ' | ' between chains, '(v)' a virtual end bone.
      std::vector<SweepChain> chains;
      if (BuildSweepChains(rig, rest.data(), influences.data(), count, SweepOptions{}, &chains)
              .ok()) {
        std::string line;
        for (const SweepChain& c : chains) {
          if (!line.empty()) line += " | ";
          for (std::size_t i = 0; i < c.joints.size(); ++i) {
            const std::string& nm = rig.names[static_cast<std::size_t>(c.joints[i])];
            line += (i ? " > " : "") + (nm.empty() ? "#" + std::to_string(c.joints[i]) : nm);
          }
          if (c.virtual_end) line += " > (v)";
        }
        std::printf("    sweep chains: %s\n", line.c_str());
      }
      // Deformers, built once per primitive.
      std::vector<std::unique_ptr<Deformer>> deformers(variants.size());
      std::vector<std::string> errors(variants.size());
      for (std::size_t k = 0; k < variants.size(); ++k) {
        st = MakeVariant(variants[k], 1.0, 1.0, rig, rest, influences, &deformers[k]);
        if (!st.ok()) {
          errors[k] = st.message();
          deformers[k].reset();
        }
      }
      std::printf("    %-18s %6s", "clip", "dur");
      for (const Variant& v : variants)
        std::printf(" | %-12s %7s %7s", v.label.c_str(), "dvol", "jump");
      std::printf("\n");
      for (std::size_t a = 0; a < asset.animations.size(); ++a) {
        std::string clip = asset.animations[a].name;
        if (clip.empty()) clip = "#" + std::to_string(a);
        if (clip.size() > 18) clip = clip.substr(0, 18);
        // Normalisation: bbox diagonal of the glTF viewer's pose at the clip's first frame.
        std::vector<Vec3> viewer;
        PosePrimitive(asset, poses[a][0], worlds[a][0], static_cast<Index>(n), prim, &viewer,
                      nullptr);
        const double diag = BoxDiagonal(viewer);
        const double rest_diag = BoxDiagonal(rest);
        // A (near) zero rest volume: the relative change is undefined.
        const bool flat = !(std::fabs(rest_volume) > 1e-9 * rest_diag * rest_diag * rest_diag);
        std::printf("    %-18s %6.2f", clip.c_str(), asset.animations[a].Duration());
        for (std::size_t k = 0; k < variants.size(); ++k) {
          if (!deformers[k]) {
            std::printf(" | %-12s %15s", variants[k].label.c_str(), "n/a");
            continue;
          }
          Deformer& d = *deformers[k];
          d.ResetHistory();
          std::vector<Vec3> p(count), prev(count);
          double dvol = 0.0, jump = 0.0;
          std::string error;
          std::vector<glm::dmat4> palette;
          for (int f = 0; f < frames && error.empty(); ++f) {
            ComputeJointMatrices(skin, worlds[a][static_cast<std::size_t>(f)], &palette);
            st = d.SetPose(palette.data());
            if (!st.ok()) {
              error = st.message();
              break;
            }
            d.Deform(0, count, p.data(), nullptr);
            dvol = std::max(dvol, std::fabs(SignedVolume(p, tris) / rest_volume - 1.0));
            if (f > 0) {
              for (std::size_t i = 0; i < count; ++i) {
                jump = std::max(jump, glm::length(p[i] - prev[i]));
              }
            }
            std::swap(p, prev);
          }
          if (!error.empty()) {
            errors[k] = error;
            std::printf(" | %-12s %15s", variants[k].label.c_str(), "n/a");
            continue;
          }
          const double j = diag > 0.0 ? jump / diag : 0.0;
          if (flat) {
            std::printf(" | %-12s %7s %7.4f", variants[k].label.c_str(), "-", j);
          } else {
            std::printf(" | %-12s %7.5f %7.4f", variants[k].label.c_str(), dvol, j);
          }
        }
        std::printf("\n");
      }
      for (std::size_t k = 0; k < variants.size(); ++k) {
        if (!errors[k].empty()) {
          std::printf("    %s: n/a (%s)\n", variants[k].label.c_str(), errors[k].c_str());
        }
      }
    }
  }
  std::printf("  (%.1f s)\n", Seconds(start));
}

}  // namespace

int main(int argc, char** argv) {
  double spacing = 0.05, voxel_ratio = 1.0, twist_step = 2.0;
  int ring_points = 64, frames = 60;
  std::string data = "../shared/data/gltf";
  bool characters = true, cylinder = true, real_rigs = true, clips = true;
  int level = 4;
  std::string only, pictures;
  double input_quads = -1.0;
  for (int i = 1; i < argc; ++i) {
    const auto next = [&](const char* flag) -> const char* {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "bench_deform: %s needs a value\n", flag);
        std::exit(2);
      }
      return argv[++i];
    };
    if (std::strcmp(argv[i], "--spacing") == 0) {
      spacing = std::atof(next("--spacing"));
    } else if (std::strcmp(argv[i], "--voxel") == 0) {
      voxel_ratio = std::atof(next("--voxel"));
    } else if (std::strcmp(argv[i], "--ring-points") == 0) {
      ring_points = std::atoi(next("--ring-points"));
    } else if (std::strcmp(argv[i], "--twist-step") == 0) {
      twist_step = std::atof(next("--twist-step"));
    } else if (std::strcmp(argv[i], "--frames") == 0) {
      frames = std::atoi(next("--frames"));
    } else if (std::strcmp(argv[i], "--data") == 0) {
      data = next("--data");
    } else if (std::strcmp(argv[i], "--no-characters") == 0) {
      characters = false;
    } else if (std::strcmp(argv[i], "--no-cylinder") == 0) {
      cylinder = false;
    } else if (std::strcmp(argv[i], "--no-real-rigs") == 0) {
      real_rigs = false;
    } else if (std::strcmp(argv[i], "--no-clips") == 0) {
      clips = false;
    } else if (std::strcmp(argv[i], "--pictures") == 0) {
      pictures = next("--pictures");
    } else if (std::strcmp(argv[i], "--only") == 0) {
      only = next("--only");
    } else if (std::strcmp(argv[i], "--input-quads") == 0) {
      input_quads = std::atof(next("--input-quads"));
    } else if (std::strcmp(argv[i], "--level") == 0) {
      level = std::atoi(next("--level"));
    } else {
      std::fprintf(stderr,
                   "usage: bench_deform [--spacing D] [--voxel RATIO] [--ring-points N] "
                   "[--twist-step DEG] [--frames F] [--data DIR] [--level L] [--no-characters] "
                   "[--no-cylinder] [--no-real-rigs] [--no-clips] [--only NAME] [--pictures DIR] "
                   "[--input-quads R]\n");
      return 2;
    }
  }
  if (!(spacing > 0.0 && spacing <= 1.0) || !(voxel_ratio > 0.0) || ring_points < 3 ||
      !(twist_step > 0.0 && twist_step <= 90.0) || frames < 2 || level < 1 || level > 64) {
    std::fprintf(stderr, "bench_deform: option out of range\n");
    return 2;
  }
  if (cylinder) RunCylinder(spacing, voxel_ratio, ring_points, twist_step);
  if (characters) {
    std::printf(
        "== Characters (%s): every clip sampled at %d evenly spaced times; per deformer:\n"
        "   dvol = max over frames |V/V_rest - 1|, V = signed volume of the deformed triangles\n"
        "          about their vertex centroid, V_rest = that of the bind shape (meaningful for\n"
        "          closed meshes only; reported anyway; '-': zero rest volume);\n"
        "   jump = max over frames and vertices of the frame-to-frame displacement / bbox\n"
        "          diagonal of the glTF viewer's pose at the clip's first frame (includes the\n"
        "          real motion).\n",
        data.c_str(), frames);
    for (const char* file :
         {"SimpleSkin.gltf", "RiggedSimple.glb", "RiggedFigure.glb", "Fox.glb", "CesiumMan.glb"}) {
      RunCharacter(data + "/" + file, frames);
    }
  }
  if (real_rigs) {
    bench::RealRigOptions o;
    o.data = data;
    o.level = level;
    o.clip_frames = frames;
    o.clips = clips;
    o.only = only;
    o.input_quads = input_quads;
    o.pictures = pictures;
    std::printf("\n");
    bench::RunRealRigs(o);
  }
  return 0;
}
