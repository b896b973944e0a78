// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Umbrella-operator smoothing of control-vertex skin weights (docs/characters.md, "Skin weights
// smoothed on the control mesh"). The painted weights of game characters change across single
// edges, and a surface that interpolates its posed control vertices (Yoon's local patches, Eq.
// 2) turns such a kink into a ripple; a few Laplacian steps (Taubin 1995, the umbrella
// operator) spread each change over a ring or two of the control mesh. Written here: the
// vectors are sparse over joints and short, a sparse-matrix library would add nothing.
#include "skin_smoothing.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <utility>

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

bool SamePosition(const Vec3& a, const Vec3& b) { return std::memcmp(&a, &b, sizeof(Vec3)) == 0; }

}  // namespace

void SmoothSkinWeights(const MeshTopology& topology, const std::vector<Vec3>& rest, int iterations,
                       double step, std::vector<glm::u16vec4>* joints,
                       std::vector<glm::vec4>* weights) {
  const std::size_t n = rest.size();
  if (iterations <= 0 || !(step > 0.0) || joints->size() != n || weights->size() != n ||
      static_cast<std::size_t>(topology.num_vertices()) != n) {
    return;
  }
  step = std::min(step, 1.0);
  // Groups of vertices at the same rest position, numbered by their first vertex.
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  auto less = [&](std::size_t a, std::size_t b) {
    const Vec3 &p = rest[a], &q = rest[b];
    if (p.x != q.x) return p.x < q.x;
    if (p.y != q.y) return p.y < q.y;
    if (p.z != q.z) return p.z < q.z;
    return a < b;
  };
  std::sort(order.begin(), order.end(), less);
  std::vector<std::size_t> group(n);
  std::size_t groups = 0;
  std::vector<std::size_t> first;  // a group's vertices start at first[g] in `order`
  for (std::size_t k = 0; k < n; ++k) {
    if (k == 0 || !SamePosition(rest[order[k]], rest[order[k - 1]])) {
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
  // Each group's weights: the mean over its vertices (equal for a cut crease's two sides).
  std::vector<Sparse> w(groups), next(groups);
  for (std::size_t g = 0; g < groups; ++g) {
    const double members = static_cast<double>(first[g + 1] - first[g]);
    for (std::size_t k = first[g]; k < first[g + 1]; ++k) {
      Sparse one;
      for (int c = 0; c < 4; ++c) {
        const double x = static_cast<double>((*weights)[order[k]][c]);
        if (x > 0.0) one.emplace_back((*joints)[order[k]][c], x / members);
      }
      std::sort(one.begin(), one.end());
      // Merge duplicate joints of one vertex.
      Sparse merged;
      for (const auto& e : one) {
        if (!merged.empty() && merged.back().first == e.first) {
          merged.back().second += e.second;
        } else {
          merged.push_back(e);
        }
      }
      w[g] = Combine(w[g], 1.0, merged, 1.0);
    }
  }
  for (int it = 0; it < iterations; ++it) {
    for (std::size_t g = 0; g < groups; ++g) {
      if (nbr[g].empty()) {
        next[g] = w[g];
        continue;
      }
      Sparse mean;
      const double share = 1.0 / static_cast<double>(nbr[g].size());
      for (std::size_t h : nbr[g]) mean = Combine(mean, 1.0, w[h], share);
      next[g] = Combine(w[g], 1.0 - step, mean, step);
    }
    w.swap(next);
  }
  for (std::size_t v = 0; v < n; ++v) {
    Sparse s = w[group[v]];
    std::stable_sort(s.begin(), s.end(), [](const auto& a, const auto& b) {
      return a.second != b.second ? a.second > b.second : a.first < b.first;
    });
    if (s.size() > 4) s.resize(4);
    double total = 0.0;
    for (const auto& e : s) total += e.second;
    (*joints)[v] = glm::u16vec4(0);
    (*weights)[v] = glm::vec4(0.0f);
    if (!(total > 0.0)) continue;
    for (std::size_t k = 0; k < s.size(); ++k) {
      (*joints)[v][static_cast<int>(k)] = s[k].first;
      (*weights)[v][static_cast<int>(k)] = static_cast<float>(s[k].second / total);
    }
  }
}

}  // namespace dermis::character
