// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Exact closest-point queries against a triangle mesh: a single-triangle primitive and a
/// static axis-aligned bounding-box tree over a triangle soup.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "dermis/core/types.h"
#include "dermis/offline/geometry/polygon_mesh.h"

namespace dermis {

/// Result of a closest-point query.
struct ClosestPoint {
  double distance = 0.0;  ///< Euclidean distance (model units); +inf when the mesh is empty.
  Vec3 point{0.0};        ///< Closest point on the mesh (model units).
  Index triangle = kInvalidIndex;  ///< Index of the triangle holding `point` (input order).
  Vec3 barycentric{0.0};           ///< Of `point` in `triangle`: point = x a + y b + z c.
};

/// Closest point to `p` on the triangle (a, b, c), all in model units.
///
/// Well-shaped triangles use the Voronoi-region method (3 vertex regions, 3 edge regions, the
/// face). Thin triangles, whose region tests would lose accuracy to rounding, instead project `p`
/// onto the plane in a frame aligned with the longest edge and, if the projection falls outside,
/// take the closest of the three edges as segments; degenerate triangles (coincident or collinear
/// corners, zero area) use the edges directly. The result is exact up to rounding for every
/// shape. `barycentric` (optional, may be null) receives (x, y, z), all >= 0 and summing to 1, such
/// that the returned point is x a + y b + z c (up to rounding).
Vec3 ClosestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                            Vec3* barycentric);

/// Static bounding-volume hierarchy over a triangle soup for exact point-to-mesh distance.
///
/// Build once, then query from any number of threads. The tree owns copies of the triangle corner
/// positions (about 110 bytes per triangle with the nodes); the inputs to Build() may be released
/// afterwards. Results are deterministic and independent of traversal order: on exact distance
/// ties the lowest triangle index wins, exactly as a brute-force loop over all triangles would.
class TriangleDistanceTree {
 public:
  TriangleDistanceTree() = default;

  /// Builds the tree from `positions` (model units) and `triangles` (3 vertex indices each,
  /// triangle t = triangles[3t .. 3t + 2]) in O(n log n). Returns false, leaving the tree empty,
  /// if the triangle list is not a multiple of 3, an index is out of range, a used position is
  /// not finite, or there are more triangles than an Index can count. An empty triangle list is
  /// valid and gives an empty tree. Degenerate triangles are allowed.
  bool Build(const std::vector<Vec3>& positions, const std::vector<std::uint32_t>& triangles);

  /// Exact closest point on the mesh to `p`. Thread-safe (const, no shared mutable state) and
  /// allocation-free. If no point of the mesh lies within `max_distance` (model units) of `p`,
  /// the query may stop early and returns distance = +inf, triangle = kInvalidIndex; points at
  /// exactly `max_distance` are found. A negative or NaN `max_distance`, an empty tree or a
  /// non-finite `p` also give distance = +inf.
  ClosestPoint Query(const Vec3& p,
                     double max_distance = std::numeric_limits<double>::infinity()) const;

  /// Decides from a triangle's input index whether a query may return it.
  using TriangleFilter = std::function<bool(Index triangle)>;

  /// As Query(), restricted to the triangles `accept` returns true for (an empty filter accepts
  /// every triangle): the exact closest point among them, with the same tie rule. Used to
  /// project onto the side of a thin part that faces a given way, or onto one boundary loop.
  /// Thread-safe if `accept` is.
  ClosestPoint QueryIf(const Vec3& p, const TriangleFilter& accept,
                       double max_distance = std::numeric_limits<double>::infinity()) const;

  /// Number of triangles in the tree (0 before a successful Build()).
  Index num_triangles() const { return static_cast<Index>(triangle_ids_.size()); }

 private:
  /// A node's box and either its children (inner: left child is the next node, right child is
  /// `right_or_first`) or its triangles (leaf: `count` > 0 triangles from `right_or_first`).
  struct Node {
    Vec3 lo{0.0};
    Vec3 hi{0.0};
    Index right_or_first = 0;
    Index count = 0;
  };
  /// Corner positions of one triangle, stored in leaf order.
  struct Corners {
    Vec3 a, b, c;
  };

  /// A triangle's centroid and input index while building.
  struct BuildItem;
  /// Appends the nodes (without boxes) of the subtree over items[begin, end), reordering the
  /// items into leaf order; returns the subtree's node index. `max_depth` tracks the depth.
  Index BuildNode(Index begin, Index end, int depth, std::vector<BuildItem>* items, int* max_depth);
  /// The traversal behind Query() and QueryIf(); `accept` may be null (every triangle).
  ClosestPoint QueryImpl(const Vec3& p, double max_distance, const TriangleFilter* accept) const;

  std::vector<Node> nodes_;          ///< Depth-first order; nodes_[0] is the root.
  std::vector<Corners> corners_;     ///< Triangles in leaf order.
  std::vector<Index> triangle_ids_;  ///< Input index of each triangle in leaf order.
};

/// Triangulates every face of `mesh` as a fan around its first vertex, in face order:
/// (v0, v1, v2), (v0, v2, v3), ... Faces with fewer than 3 vertices are skipped. Indices are
/// copied as is (an invalid negative index becomes a huge value that Build() rejects).
std::vector<std::uint32_t> TriangulateFan(const PolygonMesh& mesh);

}  // namespace dermis
