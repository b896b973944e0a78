// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Umbrella-operator smoothing of control-vertex skin weights (docs/characters.md, "Skin weights
// smoothed on the control mesh"). The painted weights of game characters change across single
// edges, and a surface that interpolates its posed control vertices (Yoon's local patches, Eq.
// 2) turns such a kink into a ripple; a few Laplacian steps (Taubin 1995, the umbrella
// operator) spread each change over a ring or two of the control mesh. Written here: the
// vectors are sparse over joints and short, a sparse-matrix library would add nothing.
#include "skin_smoothing.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <utility>

#include "dermis/offline/character/skin_transfer.h"

namespace dermis::character {
namespace {

using Sparse = std::vector<std::pair<std::uint16_t, double>>;  // sorted by joint

// sa * a + sb * b, both sorted by joint.
Sparse Combine(const Sparse& a, double sa, const Sparse& b, double sb) {
  Sparse out;
  out.reserve(a.size() + b.size());
  std::size_t i = 0, j = 0;
  while (i < a.size() || j < b.size()) {
    if (j == b.size() || (i < a.size() && a[i].first < b[j].first)) {
      out.emplace_back(a[i].first, sa * a[i].second);
      ++i;
    } else if (i == a.size() || b[j].first < a[i].first) {
      out.emplace_back(b[j].first, sb * b[j].second);
      ++j;
    } else {
      out.emplace_back(a[i].first, sa * a[i].second + sb * b[j].second);
      ++i, ++j;
    }
  }
  return out;
}

// The bit patterns of a point, so that grouping and sorting agree (+0 and -0 differ, and a
// NaN compares like any other pattern).
std::array<std::uint64_t, 3> Bits(const Vec3& p) {
  std::array<std::uint64_t, 3> b{};
  static_assert(sizeof(p.x) == sizeof(std::uint64_t), "double coordinates");
  std::memcpy(&b[0], &p.x, sizeof(std::uint64_t));
  std::memcpy(&b[1], &p.y, sizeof(std::uint64_t));
  std::memcpy(&b[2], &p.z, sizeof(std::uint64_t));
  return b;
}

}  // namespace

void SmoothSkinWeights(const MeshTopology& topology, const std::vector<Vec3>& rest, int iterations,
                       double step, std::vector<glm::u16vec4>* joints,
                       std::vector<glm::vec4>* weights) {
  const std::size_t n = rest.size();
  assert(joints->size() == n && weights->size() == n &&
         static_cast<std::size_t>(topology.num_vertices()) == n);
  if (iterations <= 0 || !(step > 0.0) || joints->size() != n || weights->size() != n ||
      static_cast<std::size_t>(topology.num_vertices()) != n) {
    return;
  }
  step = std::min(step, 1.0);
  // Groups of vertices at bitwise the same rest position, numbered in the order of their
  // positions' bit patterns.
  std::vector<std::array<std::uint64_t, 3>> bits(n);
  for (std::size_t v = 0; v < n; ++v) bits[v] = Bits(rest[v]);
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return bits[a] != bits[b] ? bits[a] < bits[b] : a < b;
  });
  std::vector<std::size_t> group(n);
  std::size_t groups = 0;
  std::vector<std::size_t> first;  // a group's vertices start at first[g] in `order`
  for (std::size_t k = 0; k < n; ++k) {
    if (k == 0 || bits[order[k]] != bits[order[k - 1]]) {
      first.push_back(k);
      ++groups;
    }
    group[order[k]] = groups - 1;
  }
  first.push_back(n);
  // Each group's neighbour groups, sorted, without itself.
  std::vector<std::vector<std::size_t>> nbr(groups);
  for (Index f = 0; f < topology.num_faces(); ++f) {
    const int k = topology.face_size(f);
    for (int i = 0; i < k; ++i) {
      const std::size_t a = group[static_cast<std::size_t>(topology.face_vertex(f, i))];
      const std::size_t b = group[static_cast<std::size_t>(topology.face_vertex(f, (i + 1) % k))];
      if (a == b) continue;
      nbr[a].push_back(b);
      nbr[b].push_back(a);
    }
  }
  for (auto& v : nbr) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
  }
  // Each group's weights: the mean of its vertices' normalised weights (equal for a cut
  // crease's two sides); a vertex without weights counts for nothing, a group without any
  // stays without (it is not skinned, and its neighbours' means leave it out).
  std::vector<Sparse> w(groups), next(groups);
  for (std::size_t g = 0; g < groups; ++g) {
    double members = 0.0;
    for (std::size_t k = first[g]; k < first[g + 1]; ++k) {
      Sparse one;
      double total = 0.0;
      for (int c = 0; c < 4; ++c) {
        const double x = static_cast<double>((*weights)[order[k]][c]);
        if (x > 0.0) one.emplace_back((*joints)[order[k]][c], x), total += x;
      }
      if (!(total > 0.0)) continue;
      std::sort(one.begin(), one.end());
      // Merge duplicate joints of one vertex.
      Sparse merged;
      for (const auto& e : one) {
        if (!merged.empty() && merged.back().first == e.first) {
          merged.back().second += e.second / total;
        } else {
          merged.emplace_back(e.first, e.second / total);
        }
      }
      w[g] = Combine(w[g], 1.0, merged, 1.0);
      members += 1.0;
    }
    for (auto& e : w[g]) e.second /= std::max(members, 1.0);
  }
  for (int it = 0; it < iterations; ++it) {
    for (std::size_t g = 0; g < groups; ++g) {
      Sparse sum;
      double count = 0.0;
      for (std::size_t h : nbr[g]) {
        if (w[h].empty()) continue;
        sum = Combine(sum, 1.0, w[h], 1.0);
        count += 1.0;
      }
      if (w[g].empty() || count == 0.0) {
        next[g] = w[g];
        continue;
      }
      next[g] = Combine(w[g], 1.0 - step, sum, step / count);
    }
    w.swap(next);
  }
  // Each vertex keeps its group's 4 largest influences, normalised (BlendInfluences' rule).
  const std::vector<Influence> none;
  for (std::size_t v = 0; v < n; ++v) {
    std::vector<Influence> list;
    for (const auto& e : w[group[v]]) {
      if (e.second > 0.0) list.push_back({e.first, static_cast<float>(e.second)});
    }
    BlendInfluences(list, none, none, Vec3(1.0, 0.0, 0.0), &(*joints)[v], &(*weights)[v]);
  }
}

}  // namespace dermis::character
