// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The reference surface of remeshing (docs/fitting.md, "Control mesh"): manifold validation of
// the input triangles, boundary loops, and orientation-aware back-projection (Botsch & Kobbelt
// 2004, section 3: "project the vertices back onto the original surface").
#include "dermis/offline/build/reference_surface.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

namespace dermis {
namespace {

bool Finite(const Vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

Index FindRoot(std::vector<Index>* parent, Index x) {
  while ((*parent)[static_cast<std::size_t>(x)] != x) {
    Index& p = (*parent)[static_cast<std::size_t>(x)];
    p = (*parent)[static_cast<std::size_t>(p)];
    x = p;
  }
  return x;
}

}  // namespace

Status ReferenceSurface::Build(const std::vector<Vec3>& positions,
                               const std::vector<std::uint32_t>& triangles,
                               const std::string& name) {
  *this = ReferenceSurface();
  if (triangles.empty() || triangles.size() % 3 != 0) {
    return Status::InvalidInput(name + ": no triangles to remesh");
  }
  const std::size_t nv = positions.size(), nt = triangles.size() / 3;
  for (std::size_t t = 0; t < nt; ++t) {
    const std::uint32_t* v = &triangles[3 * t];
    for (int k = 0; k < 3; ++k) {
      if (v[k] >= nv) {
        return Status::InvalidInput(name + ": triangle " + std::to_string(t) + " uses vertex " +
                                    std::to_string(v[k]) + " of only " + std::to_string(nv));
      }
      if (!Finite(positions[v[k]])) {
        return Status::InvalidInput(name + ": vertex " + std::to_string(v[k]) +
                                    " has a non-finite coordinate");
      }
    }
    if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) {
      return Status::InvalidInput(name + ": triangle " + std::to_string(t) + " repeats a vertex");
    }
  }
  // Directed edges (a, b, triangle), sorted: each may appear once.
  std::vector<std::array<std::uint32_t, 3>> directed;
  directed.reserve(3 * nt);
  for (std::size_t t = 0; t < nt; ++t) {
    for (int k = 0; k < 3; ++k) {
      directed.push_back({triangles[3 * t + static_cast<std::size_t>(k)],
                          triangles[3 * t + static_cast<std::size_t>((k + 1) % 3)],
                          static_cast<std::uint32_t>(t)});
    }
  }
  std::sort(directed.begin(), directed.end());
  for (std::size_t i = 1; i < directed.size(); ++i) {
    if (directed[i][0] == directed[i - 1][0] && directed[i][1] == directed[i - 1][1]) {
      return Status::InvalidInput(
          name + ": edge (" + std::to_string(directed[i][0]) + ", " +
          std::to_string(directed[i][1]) + ") is used in the same direction by triangles " +
          std::to_string(directed[i - 1][2]) + " and " + std::to_string(directed[i][2]) +
          " (a non-manifold edge or inconsistent orientation)");
    }
  }
  auto has_directed = [&](std::uint32_t a, std::uint32_t b) {
    auto it =
        std::lower_bound(directed.begin(), directed.end(), std::array<std::uint32_t, 3>{a, b, 0});
    return it != directed.end() && (*it)[0] == a && (*it)[1] == b;
  };
  // Each vertex's triangles must form one fan: its link edges (x -> y of the triangle
  // (v, x, y)) make a single path or cycle.
  std::vector<std::size_t> start(nv + 1, 0);
  for (std::uint32_t v : triangles) ++start[v + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<std::array<std::uint32_t, 2>> link(3 * nt);
  {
    std::vector<std::size_t> fill(start.begin(), start.end() - 1);
    for (std::size_t t = 0; t < nt; ++t) {
      const std::uint32_t* v = &triangles[3 * t];
      for (int k = 0; k < 3; ++k) link[fill[v[k]]++] = {v[(k + 1) % 3], v[(k + 2) % 3]};
    }
  }
  for (std::size_t v = 0; v < nv; ++v) {
    const std::size_t b = start[v], e = start[v + 1];
    if (b == e) continue;
    std::sort(link.begin() + static_cast<std::ptrdiff_t>(b),
              link.begin() + static_cast<std::ptrdiff_t>(e));
    auto next_of = [&](std::uint32_t x) -> std::ptrdiff_t {
      auto it = std::lower_bound(link.begin() + static_cast<std::ptrdiff_t>(b),
                                 link.begin() + static_cast<std::ptrdiff_t>(e),
                                 std::array<std::uint32_t, 2>{x, 0});
      if (it == link.begin() + static_cast<std::ptrdiff_t>(e) || (*it)[0] != x) return -1;
      return it - link.begin();
    };
    // Path starts: link sources that are no link's target.
    std::vector<char> is_target(e - b, 0);
    for (std::size_t i = b; i < e; ++i) {
      const std::ptrdiff_t j = next_of(link[i][1]);
      if (j >= 0) is_target[static_cast<std::size_t>(j) - b] = 1;
    }
    std::size_t first = b;
    int starts = 0;
    for (std::size_t i = b; i < e; ++i) {
      if (!is_target[i - b]) {
        if (starts == 0) first = i;
        ++starts;
      }
    }
    std::size_t steps = 0;
    if (starts <= 1) {
      std::ptrdiff_t i = static_cast<std::ptrdiff_t>(first);
      do {
        ++steps;
        i = next_of(link[static_cast<std::size_t>(i)][1]);
      } while (i >= 0 && i != static_cast<std::ptrdiff_t>(first) && steps <= e - b);
    }
    if (starts > 1 || steps != e - b) {
      return Status::InvalidInput(name + ": vertex " + std::to_string(v) +
                                  " is non-manifold (its triangles form more than one fan)");
    }
  }
  positions_ = positions;
  triangles_ = triangles;
  normals_.resize(nt);
  for (std::size_t t = 0; t < nt; ++t) {
    const Vec3& a = positions_[triangles_[3 * t]];
    const Vec3 n =
        glm::cross(positions_[triangles_[3 * t + 1]] - a, positions_[triangles_[3 * t + 2]] - a);
    const double l = glm::length(n);
    area_ += 0.5 * l;
    normals_[t] = l > 0.0 ? n / l : Vec3(0.0);
  }
  vertex_normals_.assign(nv, Vec3(0.0));
  for (std::size_t t = 0; t < nt; ++t) {
    const Vec3& a = positions_[triangles_[3 * t]];
    const Vec3 n =
        glm::cross(positions_[triangles_[3 * t + 1]] - a, positions_[triangles_[3 * t + 2]] - a);
    for (int k = 0; k < 3; ++k)
      vertex_normals_[triangles_[3 * t + static_cast<std::size_t>(k)]] += n;
  }
  for (Vec3& n : vertex_normals_) {
    const double l = glm::length(n);
    if (l > 0.0) n /= l;
  }
  // Components by shared vertices, numbered by their first vertex.
  std::vector<Index> parent(nv);
  std::iota(parent.begin(), parent.end(), 0);
  for (std::size_t t = 0; t < nt; ++t) {
    for (int k = 1; k < 3; ++k) {
      const Index a = FindRoot(&parent, static_cast<Index>(triangles_[3 * t])),
                  c = FindRoot(&parent,
                               static_cast<Index>(triangles_[3 * t + static_cast<std::size_t>(k)]));
      if (a != c) parent[static_cast<std::size_t>(std::max(a, c))] = std::min(a, c);
    }
  }
  component_.assign(nv, -1);
  std::vector<int> id_of_root(nv, -1);
  for (std::size_t v = 0; v < nv; ++v) {
    if (start[v] == start[v + 1]) continue;
    const std::size_t r = static_cast<std::size_t>(FindRoot(&parent, static_cast<Index>(v)));
    if (id_of_root[r] < 0) id_of_root[r] = num_components_++;
    component_[v] = id_of_root[r];
  }
  // Boundary loops: directed edges without a twin, followed in the faces' direction.
  vertex_loop_.assign(nv, -1);
  std::vector<std::uint32_t> next(nv, ~0u);
  std::vector<std::uint32_t> heads;
  for (const auto& d : directed) {
    if (!has_directed(d[1], d[0])) {
      next[d[0]] = d[1];
      heads.push_back(d[0]);
    }
  }
  std::vector<std::uint32_t> segments;
  for (std::uint32_t h : heads) {
    if (vertex_loop_[h] >= 0) continue;
    const int id = static_cast<int>(loops_.size());
    loops_.emplace_back();
    loop_first_segment_.push_back(segment_loop_.size());
    double length = 0.0;
    for (std::uint32_t v = h; vertex_loop_[v] < 0; v = next[v]) {
      vertex_loop_[v] = id;
      loops_.back().push_back(static_cast<Index>(v));
      segment_start_.push_back(length);
      length += glm::length(positions_[next[v]] - positions_[v]);
      segments.insert(segments.end(), {v, next[v], next[v]});
      segment_loop_.push_back(id);
    }
    loop_length_.push_back(length);
  }
  tree_.Build(positions_, triangles_);
  boundary_tree_.Build(positions_, segments);
  return Status::Ok();
}

ClosestPoint ReferenceSurface::Project(const Vec3& p, const Vec3& normal, double reach) const {
  const ClosestPoint any = tree_.Query(p);
  if (any.triangle == kInvalidIndex || !(glm::dot(normal, normal) > 0.0)) return any;
  if (glm::dot(normals_[static_cast<std::size_t>(any.triangle)], normal) > 0.0) return any;
  const ClosestPoint facing = tree_.QueryIf(
      p, [&](Index t) { return glm::dot(normals_[static_cast<std::size_t>(t)], normal) > 0.0; },
      any.distance + reach);
  return facing.triangle != kInvalidIndex ? facing : any;
}

Vec3 ReferenceSurface::ProjectToLoop(const Vec3& p, int loop) const {
  const ClosestPoint q = boundary_tree_.QueryIf(
      p, [&](Index s) { return segment_loop_[static_cast<std::size_t>(s)] == loop; });
  return q.triangle != kInvalidIndex ? q.point : p;
}

Vec3 ReferenceSurface::Normal(Index t, const Vec3& b) const {
  const std::size_t i = 3 * static_cast<std::size_t>(t);
  const Vec3 n = b.x * vertex_normals_[triangles_[i]] + b.y * vertex_normals_[triangles_[i + 1]] +
                 b.z * vertex_normals_[triangles_[i + 2]];
  const double l = glm::length(n);
  return l > 0.0 ? n / l : normals_[static_cast<std::size_t>(t)];
}

double ReferenceSurface::LoopParameter(const Vec3& p, int loop) const {
  const ClosestPoint q = boundary_tree_.QueryIf(
      p, [&](Index seg) { return segment_loop_[static_cast<std::size_t>(seg)] == loop; });
  if (q.triangle == kInvalidIndex) return 0.0;
  const std::size_t seg = static_cast<std::size_t>(q.triangle);
  const std::size_t first = loop_first_segment_[static_cast<std::size_t>(loop)];
  const std::size_t n = loops_[static_cast<std::size_t>(loop)].size();
  const Vec3& a =
      positions_[static_cast<std::size_t>(loops_[static_cast<std::size_t>(loop)][seg - first])];
  const Vec3& b = positions_[static_cast<std::size_t>(
      loops_[static_cast<std::size_t>(loop)][(seg - first + 1) % n])];
  return segment_start_[seg] + glm::length(q.point - a) * (glm::length(b - a) > 0.0 ? 1.0 : 0.0);
}

Vec3 ReferenceSurface::LoopPoint(int loop, double s) const {
  const std::vector<Index>& l = loops_[static_cast<std::size_t>(loop)];
  const double length = loop_length_[static_cast<std::size_t>(loop)];
  const std::size_t first = loop_first_segment_[static_cast<std::size_t>(loop)];
  if (!(length > 0.0)) return positions_[static_cast<std::size_t>(l[0])];
  s = std::fmod(s, length);
  if (s < 0.0) s += length;
  // The last segment starting at or before s.
  const auto begin = segment_start_.begin() + static_cast<std::ptrdiff_t>(first);
  const auto end = begin + static_cast<std::ptrdiff_t>(l.size());
  const std::size_t k = static_cast<std::size_t>(std::upper_bound(begin, end, s) - begin) - 1;
  const Vec3& a = positions_[static_cast<std::size_t>(l[k])];
  const Vec3& b = positions_[static_cast<std::size_t>(l[(k + 1) % l.size()])];
  const double len = glm::length(b - a);
  const double t = len > 0.0 ? std::min(1.0, (s - segment_start_[first + k]) / len) : 0.0;
  return a + t * (b - a);
}

Vec3 ReferenceSurface::LoopBetween(int loop, const Vec3& a, const Vec3& b, double t) const {
  const double length = loop_length_[static_cast<std::size_t>(loop)];
  const double sa = LoopParameter(a, loop), sb = LoopParameter(b, loop);
  double span = sb - sa;
  if (span < 0.0) span += length;
  return LoopPoint(loop, sa + t * span);
}

}  // namespace dermis
