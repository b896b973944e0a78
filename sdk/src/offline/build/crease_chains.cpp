// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Crease polylines of a reference surface (docs/fitting.md, "Creases"): edges whose dihedral
// angle reaches the crease angle, chained between corners (Botsch & Kobbelt 2004 keep such
// feature edges in their remesher the way they keep boundaries).
#include "dermis/offline/build/crease_chains.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dermis {

void CreaseChains::Build(const ReferenceSurface& ref, double crease_angle_deg,
                         double corner_turn_deg,
                         const std::vector<std::array<std::uint32_t, 2>>& smooth_edges) {
  ref_ = &ref;
  edges_.clear();
  edge_chain_.clear();
  chains_.clear();
  closed_.clear();
  arc_.clear();
  const std::vector<Vec3>& x = ref.positions();
  vertex_feature_.assign(x.size(), kNoFeature);
  if (!(crease_angle_deg > 0.0)) return;
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  const double cos_crease = std::cos(crease_angle_deg * kDeg);
  const std::vector<std::uint32_t>& t = ref.triangles();
  // Directed edges (a, b, triangle), sorted, to find each interior edge's two triangles.
  std::vector<std::array<std::uint32_t, 3>> directed;
  directed.reserve(t.size());
  for (std::size_t i = 0; i < t.size(); i += 3) {
    for (std::size_t k = 0; k < 3; ++k) {
      directed.push_back({t[i + k], t[i + (k + 1) % 3], static_cast<std::uint32_t>(i / 3)});
    }
  }
  std::sort(directed.begin(), directed.end());
  std::vector<std::array<std::uint32_t, 2>> smooth;
  smooth.reserve(smooth_edges.size());
  for (const auto& e : smooth_edges) smooth.push_back({std::min(e[0], e[1]), std::max(e[0], e[1])});
  std::sort(smooth.begin(), smooth.end());
  for (const auto& d : directed) {
    if (d[0] > d[1]) continue;
    const auto it = std::lower_bound(directed.begin(), directed.end(),
                                     std::array<std::uint32_t, 3>{d[1], d[0], 0});
    if (it == directed.end() || (*it)[0] != d[1] || (*it)[1] != d[0]) continue;  // boundary
    const Vec3& n1 = ref.triangle_normal(static_cast<Index>(d[2]));
    const Vec3& n2 = ref.triangle_normal(static_cast<Index>((*it)[2]));
    if (glm::dot(n1, n1) == 0.0 || glm::dot(n2, n2) == 0.0) continue;  // no area, no angle
    if (glm::dot(n1, n2) > cos_crease) continue;
    if (std::binary_search(smooth.begin(), smooth.end(),
                           std::array<std::uint32_t, 2>{d[0], d[1]})) {
      continue;  // shaded smooth
    }
    edges_.push_back({d[0], d[1]});
  }
  std::sort(edges_.begin(), edges_.end());
  edges_.erase(std::unique(edges_.begin(), edges_.end()), edges_.end());
  edge_chain_.assign(edges_.size(), -1);
  if (edges_.empty()) return;
  std::vector<std::vector<std::uint32_t>> adj(x.size());
  for (const auto& e : edges_) adj[e[0]].push_back(e[1]), adj[e[1]].push_back(e[0]);
  for (auto& a : adj) std::sort(a.begin(), a.end());
  const double cos_turn = std::cos(corner_turn_deg * kDeg);
  std::vector<char> corner(x.size(), 0);
  for (std::size_t v = 0; v < x.size(); ++v) {
    const std::size_t deg = adj[v].size();
    if (deg == 0) continue;
    if (deg != 2 || ref.vertex_loop(static_cast<Index>(v)) >= 0) {
      corner[v] = 1;
      continue;
    }
    const Vec3 u = x[v] - x[adj[v][0]], w = x[adj[v][1]] - x[v];
    const double lu = glm::length(u), lw = glm::length(w);
    if (!(lu > 0.0 && lw > 0.0) || glm::dot(u, w) < cos_turn * lu * lw) corner[v] = 1;
  }
  auto edge_index = [&](std::uint32_t a, std::uint32_t b) {
    const std::array<std::uint32_t, 2> key{std::min(a, b), std::max(a, b)};
    return static_cast<std::size_t>(std::lower_bound(edges_.begin(), edges_.end(), key) -
                                    edges_.begin());
  };
  // Walks from `start` over the unassigned edge to `first` until a corner or back at start.
  auto walk = [&](std::uint32_t start, std::uint32_t first) {
    const int c = static_cast<int>(chains_.size());
    std::vector<Index> chain{static_cast<Index>(start)};
    std::uint32_t prev = start, cur = first;
    edge_chain_[edge_index(prev, cur)] = c;
    bool is_closed = false;
    while (true) {
      if (cur == start) {
        is_closed = true;
        break;
      }
      chain.push_back(static_cast<Index>(cur));
      if (corner[cur]) break;
      const std::uint32_t next = adj[cur][0] == prev ? adj[cur][1] : adj[cur][0];
      prev = cur, cur = next;
      edge_chain_[edge_index(prev, cur)] = c;
    }
    chains_.push_back(std::move(chain));
    closed_.push_back(is_closed ? 1 : 0);
  };
  for (std::size_t v = 0; v < x.size(); ++v) {
    if (!corner[v]) continue;
    for (std::uint32_t w : adj[v]) {
      if (edge_chain_[edge_index(static_cast<std::uint32_t>(v), w)] < 0) {
        walk(static_cast<std::uint32_t>(v), w);
      }
    }
  }
  for (std::size_t e = 0; e < edges_.size(); ++e) {
    if (edge_chain_[e] < 0) walk(edges_[e][0], edges_[e][1]);  // a loop without corners
  }
  for (std::size_t c = 0; c < chains_.size(); ++c) {
    const std::vector<Index>& ch = chains_[c];
    for (Index v : ch) {
      vertex_feature_[static_cast<std::size_t>(v)] =
          corner[static_cast<std::size_t>(v)] ? kCornerFeature : static_cast<int>(c);
    }
    std::vector<double> arc(1, 0.0);
    const std::size_t segments = closed_[c] ? ch.size() : ch.size() - 1;
    for (std::size_t i = 0; i < segments; ++i) {
      arc.push_back(arc.back() + glm::length(x[static_cast<std::size_t>(ch[(i + 1) % ch.size()])] -
                                             x[static_cast<std::size_t>(ch[i])]));
    }
    arc_.push_back(std::move(arc));
  }
}

int CreaseChains::num_closed() const {
  return static_cast<int>(std::count(closed_.begin(), closed_.end(), 1));
}

int CreaseChains::EdgeChain(std::uint32_t a, std::uint32_t b) const {
  const std::array<std::uint32_t, 2> key{std::min(a, b), std::max(a, b)};
  const auto it = std::lower_bound(edges_.begin(), edges_.end(), key);
  if (it == edges_.end() || *it != key) return -1;
  return edge_chain_[static_cast<std::size_t>(it - edges_.begin())];
}

double CreaseChains::Parameter(int c, const Vec3& p) const {
  const std::vector<Index>& ch = chains_[static_cast<std::size_t>(c)];
  const std::vector<double>& arc = arc_[static_cast<std::size_t>(c)];
  const std::vector<Vec3>& x = ref_->positions();
  double best = std::numeric_limits<double>::infinity(), s = 0.0;
  for (std::size_t i = 0; i + 1 < arc.size(); ++i) {
    const Vec3& a = x[static_cast<std::size_t>(ch[i])];
    const Vec3& b = x[static_cast<std::size_t>(ch[(i + 1) % ch.size()])];
    const Vec3 d = b - a;
    const double dd = glm::dot(d, d);
    const double u = dd > 0.0 ? std::clamp(glm::dot(p - a, d) / dd, 0.0, 1.0) : 0.0;
    const Vec3 q = a + u * d;
    const double dist = glm::dot(p - q, p - q);
    if (dist < best) best = dist, s = arc[i] + u * (arc[i + 1] - arc[i]);
  }
  return s;
}

Vec3 CreaseChains::Point(int c, double s) const {
  const std::vector<Index>& ch = chains_[static_cast<std::size_t>(c)];
  const std::vector<double>& arc = arc_[static_cast<std::size_t>(c)];
  const std::vector<Vec3>& x = ref_->positions();
  const double len = arc.back();
  if (closed(c) && len > 0.0) {
    s = std::fmod(s, len);
    if (s < 0.0) s += len;
  }
  s = std::clamp(s, 0.0, len);
  std::size_t i =
      static_cast<std::size_t>(std::upper_bound(arc.begin(), arc.end(), s) - arc.begin());
  i = std::min(std::max<std::size_t>(i, 1), arc.size() - 1) - 1;
  const Vec3& a = x[static_cast<std::size_t>(ch[i])];
  const Vec3& b = x[static_cast<std::size_t>(ch[(i + 1) % ch.size()])];
  const double span = arc[i + 1] - arc[i];
  return span > 0.0 ? a + ((s - arc[i]) / span) * (b - a) : a;
}

Vec3 CreaseChains::Between(int c, const Vec3& a, const Vec3& b, double t) const {
  const double sa = Parameter(c, a), sb = Parameter(c, b);
  double d = sb - sa;
  if (closed(c)) {
    const double len = length(c);
    if (d > 0.5 * len) d -= len;
    if (d < -0.5 * len) d += len;
  }
  return Point(c, sa + t * d);
}

double CreaseChains::ChordDeviation(int c, const Vec3& a, const Vec3& b) const {
  const std::vector<Index>& ch = chains_[static_cast<std::size_t>(c)];
  const std::vector<double>& arc = arc_[static_cast<std::size_t>(c)];
  const std::vector<Vec3>& x = ref_->positions();
  double sa = Parameter(c, a), sb = Parameter(c, b);
  const double len = length(c);
  double d = sb - sa;
  if (closed(c)) {
    if (d > 0.5 * len) d -= len;
    if (d < -0.5 * len) d += len;
  }
  if (d < 0.0) std::swap(sa, sb), d = -d;  // from sa forward by d
  const Vec3 pa = Point(c, sa), pb = Point(c, sa + d), e = pb - pa;
  const double ee = glm::dot(e, e);
  double worst = 0.0;
  // Chain vertices at arc lengths in (sa, sa + d), once round a closed chain.
  const std::size_t n = ch.size();
  for (std::size_t i = 0; i < n; ++i) {
    double s = arc[i];
    if (closed(c) && s <= sa) s += len;
    if (!(s > sa && s < sa + d)) continue;
    const Vec3& p = x[static_cast<std::size_t>(ch[i])];
    const double u = ee > 0.0 ? std::clamp(glm::dot(p - pa, e) / ee, 0.0, 1.0) : 0.0;
    worst = std::max(worst, glm::length(p - (pa + u * e)));
  }
  return worst;
}

}  // namespace dermis
