// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Support rows beside closed crease loops (docs/characters.md, "Support rows beside crease
// loops"): the modeller's holding edge loop, placed on a built control mesh so that the
// C-infinity domain surface (Yoon, section 3, Eq. 1) rounds a kept crease over a narrower band.
#include "dermis/offline/build/crease_support.h"

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace dermis {
namespace {

constexpr int kOff = -1;     // not on a crease / beside none
constexpr int kCorner = -2;  // on two chains at once
constexpr int kMixed = -3;   // beside two chains, a corner or an open chain

// Calls fn(a, b) for each side (a, b) of each face of `m`, in face order (an interior edge
// twice, once from each face).
template <typename Fn>
void ForEachEdge(const PolygonMesh& m, Fn fn) {
  for (Index f = 0; f < m.num_faces(); ++f) {
    const Index base = m.face_offsets[static_cast<std::size_t>(f)];
    const Index size = m.face_size(f);
    for (Index k = 0; k < size; ++k) {
      fn(m.face_vertices[static_cast<std::size_t>(base + k)],
         m.face_vertices[static_cast<std::size_t>(base + (k + 1) % size)]);
    }
  }
}

}  // namespace

Status SupportCreaseLoops(const CreaseChains& chains, double keep, double tolerance,
                          const std::function<Vec3(const Vec3&)>& project, PolygonMesh* control,
                          CreaseSupportResult* result) {
  CreaseSupportResult res;
  if (!(keep > 0.0 && keep <= 1.0)) {
    return Status::InvalidInput("crease support: the fraction kept must be in (0, 1], not " +
                                std::to_string(keep));
  }
  if (!(tolerance >= 0.0 && std::isfinite(tolerance))) {
    return Status::InvalidInput("crease support: the tolerance must be finite and >= 0");
  }
  if (!control) return Status::InvalidInput("crease support: no control mesh");
  const std::size_t n = control->positions.size();
  for (Index v : control->face_vertices) {
    if (v < 0 || static_cast<std::size_t>(v) >= n) {
      return Status::InvalidInput("crease support: a face names vertex " + std::to_string(v) +
                                  " of " + std::to_string(n));
    }
  }
  if (result) *result = res;
  if (chains.empty() || keep == 1.0) return Status::Ok();
  const int num_chains = chains.num_chains();
  // Each chain's bounding box, grown by the tolerance: most vertices are far from most chains.
  const std::vector<Vec3>& ref = chains.reference_positions();
  std::vector<Vec3> lo(static_cast<std::size_t>(num_chains)),
      hi(static_cast<std::size_t>(num_chains));
  for (int c = 0; c < num_chains; ++c) {
    Vec3 a(std::numeric_limits<double>::infinity()), b(-std::numeric_limits<double>::infinity());
    for (Index v : chains.chain(c)) {
      a = glm::min(a, ref[static_cast<std::size_t>(v)]);
      b = glm::max(b, ref[static_cast<std::size_t>(v)]);
    }
    lo[static_cast<std::size_t>(c)] = a - Vec3(tolerance);
    hi[static_cast<std::size_t>(c)] = b + Vec3(tolerance);
  }
  // The chain each control vertex lies on (kOff, a chain, or kCorner).
  std::vector<int> on(n, kOff);
  std::vector<char> loop_used(static_cast<std::size_t>(num_chains), 0);
  for (std::size_t v = 0; v < n; ++v) {
    const Vec3& x = control->positions[v];
    for (int c = 0; c < num_chains; ++c) {
      const Vec3 &a = lo[static_cast<std::size_t>(c)], &b = hi[static_cast<std::size_t>(c)];
      if (x.x < a.x || x.y < a.y || x.z < a.z || x.x > b.x || x.y > b.y || x.z > b.z) continue;
      if (!(glm::length(x - chains.Project(c, x)) <= tolerance)) continue;  // NaN: not on it
      on[v] = on[v] == kOff ? c : kCorner;
    }
    if (on[v] >= 0 && chains.closed(on[v])) loop_used[static_cast<std::size_t>(on[v])] = 1;
  }
  for (char u : loop_used) res.loops += u;
  // The one closed chain each vertex is beside, through its control edges.
  std::vector<int> beside(n, kOff);
  auto mark = [&](Index v, int chain) {
    int& b = beside[static_cast<std::size_t>(v)];
    if (on[static_cast<std::size_t>(v)] != kOff) return;
    const int c = chain >= 0 && chains.closed(chain) ? chain : kMixed;
    b = b == kOff || b == c ? c : kMixed;
  };
  ForEachEdge(*control, [&](Index a, Index b) {
    if (on[static_cast<std::size_t>(a)] != kOff) mark(b, on[static_cast<std::size_t>(a)]);
    if (on[static_cast<std::size_t>(b)] != kOff) mark(a, on[static_cast<std::size_t>(b)]);
  });
  // Each vertex's neighbours on its loop, through its control edges (each once).
  std::vector<std::vector<Index>> ring(n);
  auto add = [&](Index v, Index w) {
    std::vector<Index>& r = ring[static_cast<std::size_t>(v)];
    if (beside[static_cast<std::size_t>(v)] < 0) return;
    for (Index u : r) {
      if (u == w) return;
    }
    r.push_back(w);
  };
  ForEachEdge(*control, [&](Index a, Index b) {
    if (on[static_cast<std::size_t>(a)] >= 0) add(b, a);
    if (on[static_cast<std::size_t>(b)] >= 0) add(a, b);
  });
  // Every target from the positions before any move: straight towards the loop's point c
  // closest to the vertex. It stays where its neighbours on the loop surround it (their mean
  // within half their mean distance of it, as a small cap's centre joined to its rim: no side
  // to move to), and where c is further from its nearest neighbour on the loop than the vertex
  // is (c on another stretch of the loop, across a narrow waist).
  std::vector<Vec3> moved = control->positions;
  for (std::size_t v = 0; v < n; ++v) {
    if (beside[v] < 0 || ring[v].empty()) continue;
    const Vec3& x = control->positions[v];
    Vec3 mean(0.0);
    double mean_distance = 0.0;
    double nearest = std::numeric_limits<double>::infinity();
    Vec3 nearest_point(0.0);
    for (Index w : ring[v]) {
      const Vec3& y = control->positions[static_cast<std::size_t>(w)];
      const double d = glm::length(y - x);
      mean += y;
      mean_distance += d;
      if (d < nearest) nearest = d, nearest_point = y;
    }
    const double k = static_cast<double>(ring[v].size());
    if (!(glm::length(mean / k - x) >= 0.5 * mean_distance / k)) continue;  // NaN: stays
    const Vec3 c = chains.Project(beside[v], x);
    if (!(glm::length(c - nearest_point) <= nearest)) continue;
    const Vec3 y = project(c + keep * (x - c));
    if (!std::isfinite(y.x) || !std::isfinite(y.y) || !std::isfinite(y.z)) continue;
    moved[v] = y;
    ++res.moved;
  }
  control->positions = std::move(moved);
  if (result) *result = res;
  return Status::Ok();
}

}  // namespace dermis
