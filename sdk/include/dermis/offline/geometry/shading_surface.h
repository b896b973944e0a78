// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief The surface a low-poly mesh's shading normals describe: Phong tessellation
/// (Boubekeur and Alexa 2008) that keeps the mesh's hard edges straight, so it has no cracks
/// (docs/characters.md, "Smooth-shaded parts follow their shading").
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "dermis/core/types.h"
#include "dermis/offline/geometry/polygon_mesh.h"

namespace dermis {

/// Phong tessellation of a triangle mesh with per-corner shading normals. A point of a face at
/// barycentric weights w is p = Σ w_k x_k moved towards Σ w_k π_k(p), π_k the projection onto
/// the plane through corner k perpendicular to its normal, by the shape factor. That move is a
/// sum over the face's edges, each term w_k w_l times a vector of the edge's two ends alone,
/// so the surface passes through the vertices, and along an edge whose two faces carry the same
/// normals at its ends it is one curve from both sides. At an edge where they differ (a hard
/// edge), at a boundary edge and on a face without normals the edge's term is left out: the
/// edge stays straight and the surface has no cracks. Each edge's term is capped (Build()'s
/// max_move): a box shaded smooth, or long triangles whose normals lean, would otherwise
/// bulge far past the silhouette a renderer keeps. Immutable after Build(); queries are const.
class ShadingSurface {
 public:
  /// `mesh`: triangles (a face of another size, or without area, stays flat, and Point() on a
  /// larger face interpolates its first three corners); `corner_normals`: 3 per face in face
  /// order (normalised here; a face with a zero or non-finite one stays flat; any other count:
  /// no normals at all);
  /// `shape`: the shape factor in [0, 1] (0: the flat triangles). The mesh must outlive this.
  /// `max_move` (model units, <= 0: no limit): the most an edge's own term moves the surface
  /// from the flat triangles (on the edge, at its midpoint); a larger term is scaled down to
  /// it, the same from both sides. Inside a face the three edges' terms add up: at most 4/3
  /// max_move (at the centroid each term is 4/9 of its midpoint value). Long triangles whose
  /// normals lean would otherwise bulge far past the source's silhouette.
  void Build(const PolygonMesh& mesh, const std::vector<Vec3>& corner_normals, double shape,
             double max_move);
  /// The point of face `f` at barycentric weights `w` (w[k] for its k-th corner, summing to 1).
  /// Build() must have been called.
  Vec3 Point(Index f, const double w[3]) const;
  /// The shading normal of face `f` at barycentric weights `w`: the corners' normals
  /// interpolated (sum w_k n_k) and normalised, as a renderer shades the source; the zero
  /// vector on a face without normals or where they cancel. Build() must have been called.
  Vec3 Normal(Index f, const double w[3]) const;
  /// How far this surface's own normals are from the shading normals it was built from: the
  /// mean angle (radians, by area, over the faces with normals; 0 where there are none)
  /// between the lines of the surface's normal and of the interpolated shading normal
  /// (Σ w_k n_k; either direction, as Phong's surface does not depend on it), at 16 points per
  /// face (the centroids of its 4 x 4 split). Build() must have been called. Built at shape 0 it
  /// measures the flat triangles. Normals that describe a smooth surface (a tube shaded round) come
  /// closer on the curved surface; normals averaged across the bends of long flat facets (a
  /// box-modelled limb shaded smooth) do not, and Phong's parabolas over those facets only add
  /// bumps.
  double NormalDeviation() const;
  /// Whether the surface differs from the flat triangles anywhere.
  bool curved() const { return curved_; }
  /// Edges whose term max_move scaled down.
  int capped_edges() const { return capped_; }
  /// The interior edges the source shades smooth (whatever the shape factor): exactly two
  /// faces, both with normals, that give each end of the edge the same stored normal. A hard edge
  /// in a glTF asset has its vertices split, one normal per side, so after the weld its two faces
  /// carry different normals at its ends. Sorted (a, b) vertex pairs, a < b.
  const std::vector<std::array<std::uint32_t, 2>>& smooth_edges() const { return smooth_edges_; }

 private:
  /// The term of face f's edge opposite corner c, before its scale and the shape factor:
  /// ((x_l - x_k).n_k) n_k + ((x_k - x_l).n_l) n_l, k and l the edge's corners (Phong's move
  /// is minus the sum of w_k w_l times these).
  Vec3 EdgeTerm(Index f, std::size_t c) const;

  const PolygonMesh* mesh_ = nullptr;
  double shape_ = 0.0;
  bool curved_ = false;
  int capped_ = 0;
  std::vector<Vec3> normals_;  ///< 3 per face: the shading normal of each corner.
  std::vector<char> shaded_;   ///< Per face: it has shading normals.
  std::vector<char> hard_;     ///< 3 per face: the edge opposite corner k keeps straight.
  std::vector<std::array<std::uint32_t, 2>> smooth_edges_;
  std::vector<double> scale_;  ///< 3 per face: the factor of the edge opposite corner k's term.
};

}  // namespace dermis
