// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Samples on a character part's triangles and along its edges, denser along creases and
// boundaries, on the part's shading surface (docs/characters.md).
#include "area_samples.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace dermis::character {
namespace {

/// ceil(length / step) segments, at most `cap` (0 for a length or step that is not a number):
/// counted in double, so no spacing, however fine, overflows the int.
int Segments(double length, double step, int cap) {
  const double n = std::ceil(length / step);
  if (n >= static_cast<double>(cap)) return cap;
  return n > 0.0 ? static_cast<int>(n) : 0;
}

}  // namespace

std::vector<Vec3> AreaSamples(const PolygonMesh& mesh, const ShadingSurface& shading,
                              const std::vector<std::array<std::uint32_t, 2>>& smooth_edges,
                              double spacing, double crease_angle, double crease_factor,
                              bool crease_rows, double turn_per_sample) {
  std::vector<Vec3> out;
  if (!(spacing > 0.0)) return out;
  const std::size_t nf = static_cast<std::size_t>(mesh.num_faces());
  std::vector<Vec3> normal(nf);
  // Segments per edge of each triangle's grid of samples (0: too small for a grid), or, for a
  // sliver, its rows (below) and the corner opposite its longest edge.
  std::vector<int> grid(nf, 0), rows(nf, 0), apex(nf, 0);
  std::map<std::pair<Index, Index>, std::vector<Index>> edges;
  struct Shape {
    int k0 = 0;
    double longest = 0.0, height = 0.0;
    double twice_area = 0.0;  ///< |(b - a) x (c - a)|
  };
  std::vector<Shape> shape(nf);
  const double cos_crease = std::cos(crease_angle);
  for (Index f = 0; f < mesh.num_faces(); ++f) {
    const std::size_t fi = static_cast<std::size_t>(f);
    const Index* v = &mesh.face_vertices[mesh.face_offsets[f]];
    const Vec3 &a = mesh.positions[v[0]], &b = mesh.positions[v[1]], &c = mesh.positions[v[2]];
    const Vec3 n = glm::cross(b - a, c - a);
    const double ln = glm::length(n);
    normal[fi] = ln > 0.0 ? n / ln : Vec3(0.0);
    shape[fi].twice_area = ln;
    for (int k = 0; k < 3; ++k) {
      const Index x = v[k], y = v[(k + 1) % 3];
      edges[{std::min(x, y), std::max(x, y)}].push_back(f);
    }
    // Its longest edge (from corner k0) and its height over it.
    const Vec3 p[3] = {a, b, c};
    Shape& sh = shape[fi];
    for (int k = 0; k < 3; ++k) {
      const double l = glm::length(p[(k + 1) % 3] - p[k]);
      if (l > sh.longest) sh.longest = l, sh.k0 = k;
    }
    if (sh.longest > 0.0) {
      const int k1 = (sh.k0 + 1) % 3, k2 = (sh.k0 + 2) % 3;
      sh.height = glm::length(glm::cross(p[k1] - p[sh.k0], p[k2] - p[sh.k0])) / sh.longest;
    }
  }
  // A triangle with samples inside (longer than twice the spacing) is a sliver when it is less
  // than a quarter as high as its longest edge: rows along that edge (below), not a grid.
  auto is_sliver = [&](std::size_t f) {
    return shape[f].longest > 2.0 * spacing && shape[f].height < 0.25 * shape[f].longest;
  };
  // Whether an edge (its vertices, its faces) is sharp: a boundary, or a dihedral angle above
  // crease_angle that the source does not shade smooth.
  auto is_sharp = [&](const std::pair<Index, Index>& ends, const std::vector<Index>& faces) {
    if (faces.size() != 2) return true;
    return glm::dot(normal[static_cast<std::size_t>(faces[0])],
                    normal[static_cast<std::size_t>(faces[1])]) < cos_crease &&
           !std::binary_search(
               smooth_edges.begin(), smooth_edges.end(),
               std::array<std::uint32_t, 2>{static_cast<std::uint32_t>(ends.first),
                                            static_cast<std::uint32_t>(ends.second)});
  };
  // Each face's spacing: `spacing`, or closer on a sliver where the part curves (below).
  std::vector<double> face_spacing(nf, spacing);
  if (turn_per_sample > 0.0) {
    // A sliver's width and its neighbour's, across the smooth edge they share, turn the normal
    // by the angle between their faces: the part's curvature there is about that angle over
    // their mean width (RiggedSimple's tube: 11.25 degrees across facets 0.09 to 0.2 wide, a
    // radius of 0.45 to 1). The remesh's sizing keeps its control edges within a turn of
    // SizingOptions::max_turn (halved by the split into quads), finer there than the count's
    // edge the spacing comes from; along the sliver the samples come as close, at most
    // turn_per_sample of turn apart (docs/characters.md, "Samples as close as the control
    // edges along curved slivers"). The counts' caps (64 rows, 128 points on a row or an edge)
    // bound each sliver's points however sharply it turns.
    // Whether face f runs from vertex x to vertex y (consistently oriented neighbours run
    // along their shared edge in opposite directions).
    auto runs = [&](std::size_t f, Index x, Index y) {
      const Index* v = &mesh.face_vertices[mesh.face_offsets[static_cast<Index>(f)]];
      for (int k = 0; k < 3; ++k) {
        if (v[k] == x && v[(k + 1) % 3] == y) return true;
      }
      return false;
    };
    for (const auto& e : edges) {
      if (is_sharp(e.first, e.second)) continue;
      const std::size_t f = static_cast<std::size_t>(e.second[0]);
      const std::size_t g = static_cast<std::size_t>(e.second[1]);
      // A face without area has no normal to turn from.
      if ((!is_sliver(f) && !is_sliver(g)) || normal[f] == Vec3(0.0) || normal[g] == Vec3(0.0)) {
        continue;
      }
      // A neighbour wound the other way (its normal flipped) turns by the angle's supplement.
      const Index x = e.first.first, y = e.first.second;
      const Vec3 ng = runs(f, x, y) == runs(g, x, y) ? -normal[g] : normal[g];
      const double angle =
          std::atan2(glm::length(glm::cross(normal[f], ng)), glm::dot(normal[f], ng));
      if (!(angle > 0.0)) continue;
      // Each face's height over the edge: twice its area over the edge's length (not zero: the
      // faces have area).
      const double length = glm::length(mesh.positions[y] - mesh.positions[x]);
      const double step = turn_per_sample * 0.5 *
                          (shape[f].twice_area / length + shape[g].twice_area / length) / angle;
      if (is_sliver(f)) face_spacing[f] = std::min(face_spacing[f], step);
      if (is_sliver(g)) face_spacing[g] = std::min(face_spacing[g], step);
    }
  }
  // The point at barycentric weights w of face f (w[k] for its k-th corner).
  auto at = [&](std::size_t f, const double w[3]) {
    return shading.Point(static_cast<Index>(f), w);
  };
  // The point of face f at s along the row t of the way from its edge (corners ka, kb) to its
  // corner kc: (1 - t) ((1 - s) p_ka + s p_kb) + t p_kc.
  auto on_row = [&](std::size_t f, int ka, int kb, int kc, double s, double t) {
    double w[3];
    w[ka] = (1.0 - s) * (1.0 - t), w[kb] = s * (1.0 - t), w[kc] = t;
    return at(f, w);
  };
  auto corner = [&](Index f, Index vertex) {
    const Index* v = &mesh.face_vertices[mesh.face_offsets[f]];
    int k = 0;
    while (k < 2 && v[k] != vertex) ++k;
    return k;
  };
  for (std::size_t f = 0; f < nf; ++f) {
    const int k0 = shape[f].k0;
    const double longest = shape[f].longest, height = shape[f].height;
    if (!(longest > 2.0 * spacing)) continue;
    const int k1 = (k0 + 1) % 3, k2 = (k0 + 2) % 3;
    if (!is_sliver(f)) {
      // A barycentric grid: its points are longest / n_grid <= spacing apart along the longest
      // edge and about as far apart along the others.
      const int n_grid = Segments(longest, spacing, 64);
      grid[f] = n_grid;
      for (int i = 1; i < n_grid; ++i) {
        for (int j = 1; i + j < n_grid; ++j) {
          const double s = double(i) / n_grid, t = double(j) / n_grid;
          const double w[3] = {1.0 - s - t, s, t};
          out.push_back(at(f, w));
        }
      }
      continue;
    }
    // A sliver (less than a quarter as high as long), whose grid's rows would be less than a
    // quarter of the spacing apart across it (RiggedSimple's 4.6 by 0.2 tube triangles had
    // points about 0.01 apart around the tube and 0.3 apart along it, docs/characters.md,
    // "Slivers sampled as far apart across as along"): rows parallel to its longest edge, at
    // most its spacing apart (`spacing`, or closer where the part curves, above), each with
    // points at most that far apart; none inside where it is no higher than that (its edges
    // carry samples).
    const double step = face_spacing[f];
    const int n_rows = std::max(1, Segments(height, step, 64));
    rows[f] = n_rows;
    apex[f] = k2;
    for (int r = 1; r < n_rows; ++r) {
      const double t = double(r) / n_rows;
      // The row from (1 - t) p[k0] + t p[k2] to (1 - t) p[k1] + t p[k2]; its ends are on the
      // other edges, which have samples of their own.
      const int n_row = Segments((1.0 - t) * longest, step, 128);
      for (int i = 1; i < n_row; ++i) out.push_back(on_row(f, k0, k1, k2, double(i) / n_row, t));
    }
  }
  for (const auto& e : edges) {
    const bool sharp = is_sharp(e.first, e.second);
    const Vec3 &a = mesh.positions[e.first.first], &b = mesh.positions[e.first.second];
    // The closer of its faces' spacings (a curved sliver's, above).
    double edge_spacing = spacing;
    for (Index f : e.second) {
      edge_spacing = std::min(edge_spacing, face_spacing[static_cast<std::size_t>(f)]);
    }
    const double h =
        sharp ? std::min(edge_spacing, spacing / std::max(1.0, crease_factor)) : edge_spacing;
    const int n_edge = Segments(glm::length(b - a), h, 128);
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
    // its edges, a sliver's rows up to its spacing: beside a sharp edge that gap is up to
    // crease_factor times the spacing h along the edge, and the finest displacement levels,
    // held there only by their smoothing, overshoot the crease (RiggedSimple's cap rim,
    // docs/characters.md). Rows parallel to the sharp edge, h apart (their points spaced like
    // the grid), fill the gap.
    for (Index f : e.second) {
      const std::size_t fs = static_cast<std::size_t>(f);
      const int n_grid = grid[fs], n_rows = rows[fs];
      if (n_grid == 0 && n_rows == 0) continue;  // a small triangle: no gap to fill
      const Index* v = &mesh.face_vertices[mesh.face_offsets[f]];
      int kc = 0;
      for (int k = 0; k < 3; ++k) {
        if (v[k] != e.first.first && v[k] != e.first.second) kc = k;
      }
      const int fa = corner(f, e.first.first), fb = corner(f, e.first.second);
      const Vec3& c = mesh.positions[v[kc]];
      const double base = glm::length(b - a);
      const double height = base > 0.0 ? glm::length(glm::cross(b - a, c - a)) / base : 0.0;
      // A sliver's first row is height / n_rows from its longest edge (the one opposite its
      // apex); from its other edges its nearest points, inside or on its other edges, are at
      // most its spacing away.
      const double gap = n_grid > 0       ? height / n_grid
                         : kc == apex[fs] ? height / n_rows
                                          : std::min(face_spacing[fs], height);
      for (int r = 1; r <= 64 && r * h < gap; ++r) {
        const double t = r * h / height;
        const Vec3 p = a + t * (c - a), q = b + t * (c - b);
        const int n_row = Segments(glm::length(q - p), face_spacing[fs], 128);
        for (int i = 0; i <= n_row; ++i) {
          out.push_back(on_row(fs, fa, fb, kc, double(i) / std::max(1, n_row), t));
        }
      }
    }
  }
  return out;
}

}  // namespace dermis::character
