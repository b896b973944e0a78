// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Samples on a character part's triangles and along its edges, denser along creases and
// boundaries, on the part's shading surface (docs/characters.md).
#include "area_samples.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace dermis::character {

std::vector<Vec3> AreaSamples(const PolygonMesh& mesh, const ShadingSurface& shading,
                              const std::vector<std::array<std::uint32_t, 2>>& smooth_edges,
                              double spacing, double crease_angle, double crease_factor,
                              bool crease_rows) {
  std::vector<Vec3> out;
  if (!(spacing > 0.0)) return out;
  const std::size_t nf = static_cast<std::size_t>(mesh.num_faces());
  std::vector<Vec3> normal(nf);
  // Segments per edge of each triangle's grid of samples (0: too small for a grid).
  std::vector<int> grid(nf, 0);
  std::map<std::pair<Index, Index>, std::vector<Index>> edges;
  const double cos_crease = std::cos(crease_angle);
  for (Index f = 0; f < mesh.num_faces(); ++f) {
    const std::size_t fi = static_cast<std::size_t>(f);
    const Index* v = &mesh.face_vertices[mesh.face_offsets[f]];
    const Vec3 &a = mesh.positions[v[0]], &b = mesh.positions[v[1]], &c = mesh.positions[v[2]];
    const Vec3 n = glm::cross(b - a, c - a);
    const double ln = glm::length(n);
    normal[fi] = ln > 0.0 ? n / ln : Vec3(0.0);
    for (int k = 0; k < 3; ++k) {
      const Index x = v[k], y = v[(k + 1) % 3];
      edges[{std::min(x, y), std::max(x, y)}].push_back(f);
    }
  }
  // The point at barycentric weights w of face f (w[k] for its k-th corner).
  auto at = [&](std::size_t f, const double w[3]) {
    return shading.Point(static_cast<Index>(f), w);
  };
  auto corner = [&](Index f, Index vertex) {
    const Index* v = &mesh.face_vertices[mesh.face_offsets[f]];
    int k = 0;
    while (k < 2 && v[k] != vertex) ++k;
    return k;
  };
  for (std::size_t f = 0; f < nf; ++f) {
    const Index* v = &mesh.face_vertices[mesh.face_offsets[static_cast<Index>(f)]];
    const Vec3 &a = mesh.positions[v[0]], &b = mesh.positions[v[1]], &c = mesh.positions[v[2]];
    const double longest =
        std::max(glm::length(b - a), std::max(glm::length(c - b), glm::length(a - c)));
    if (!(longest > 2.0 * spacing)) continue;
    const int n_grid = std::min(64, static_cast<int>(std::ceil(longest / spacing)));
    grid[f] = n_grid;
    for (int i = 1; i < n_grid; ++i) {
      for (int j = 1; i + j < n_grid; ++j) {
        const double s = double(i) / n_grid, t = double(j) / n_grid;
        const double w[3] = {1.0 - s - t, s, t};
        out.push_back(at(f, w));
      }
    }
  }
  for (const auto& e : edges) {
    bool sharp = e.second.size() != 2;
    if (!sharp) {
      sharp = glm::dot(normal[static_cast<std::size_t>(e.second[0])],
                       normal[static_cast<std::size_t>(e.second[1])]) < cos_crease &&
              !std::binary_search(
                  smooth_edges.begin(), smooth_edges.end(),
                  std::array<std::uint32_t, 2>{static_cast<std::uint32_t>(e.first.first),
                                               static_cast<std::uint32_t>(e.first.second)});
    }
    const Vec3 &a = mesh.positions[e.first.first], &b = mesh.positions[e.first.second];
    const double h = sharp ? spacing / std::max(1.0, crease_factor) : spacing;
    const int n_edge = std::min(128, static_cast<int>(std::ceil(glm::length(b - a) / h)));
    // On the shading surface, which keeps a hard edge straight and curves a smooth one alike
    // from both sides.
    const std::size_t f0 = static_cast<std::size_t>(e.second[0]);
    const int ka = corner(e.second[0], e.first.first), kb = corner(e.second[0], e.first.second);
    for (int i = 1; i < n_edge; ++i) {
      const double s = double(i) / n_edge;
      double w[3] = {0.0, 0.0, 0.0};
      w[ka] = 1.0 - s, w[kb] = s;
      out.push_back(at(f0, w));
    }
    if (!sharp || !crease_rows || crease_factor <= 1.0) continue;
    // The grid inside a large triangle (above) starts one grid row, height / n_grid, away from
    // its edges: beside a sharp edge that gap is up to crease_factor times the spacing h along
    // the edge, and the finest displacement levels, held there only by their smoothing,
    // overshoot the crease (RiggedSimple's cap rim, docs/characters.md). Rows parallel to the
    // sharp edge, h apart (their points spaced like the grid), fill the gap.
    for (Index f : e.second) {
      const int n_grid = grid[static_cast<std::size_t>(f)];
      if (n_grid == 0) continue;  // no grid inside: no gap to fill
      const Index* v = &mesh.face_vertices[mesh.face_offsets[f]];
      int kc = 0;
      for (int k = 0; k < 3; ++k) {
        if (v[k] != e.first.first && v[k] != e.first.second) kc = k;
      }
      const int fa = corner(f, e.first.first), fb = corner(f, e.first.second);
      const Vec3& c = mesh.positions[v[kc]];
      const double base = glm::length(b - a);
      const double height = base > 0.0 ? glm::length(glm::cross(b - a, c - a)) / base : 0.0;
      const double gap = height / n_grid;
      for (int r = 1; r * h < gap; ++r) {
        const double t = r * h / height;
        const Vec3 p = a + t * (c - a), q = b + t * (c - b);
        const int n_row = std::min(128, static_cast<int>(std::ceil(glm::length(q - p) / spacing)));
        for (int i = 0; i <= n_row; ++i) {
          const double s = double(i) / std::max(1, n_row);
          // (1 - s) p + s q in the face's barycentric weights.
          double w[3] = {0.0, 0.0, 0.0};
          w[fa] = (1.0 - s) * (1.0 - t), w[fb] = s * (1.0 - t), w[kc] = t;
          out.push_back(at(static_cast<std::size_t>(f), w));
        }
      }
    }
  }
  return out;
}

}  // namespace dermis::character
