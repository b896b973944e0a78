// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief The dense input surface a remesher projects onto: its triangles with closest-point
/// queries that respect orientation, and its boundary loops (docs/fitting.md, "Control mesh").
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "dermis/core/status.h"
#include "dermis/core/types.h"
#include "dermis/offline/geometry/triangle_distance.h"

namespace dermis {

/// A manifold, consistently oriented triangle mesh used as the surface that remeshed vertices
/// are projected back onto (Botsch & Kobbelt 2004, "back-projection"). Immutable after Build();
/// every query is const and thread-safe. Positions are in model units.
class ReferenceSurface {
 public:
  /// Builds from welded positions and triangles (3 indices each, none repeated within a
  /// triangle). Fails with a message that starts with `name` when an edge is shared by more than
  /// two triangles or twice in the same direction (non-manifold or inconsistently oriented),
  /// when the triangles around a vertex form more than one fan (a non-manifold vertex), when an
  /// index is out of range or a position is not finite, or when there are no triangles.
  Status Build(const std::vector<Vec3>& positions, const std::vector<std::uint32_t>& triangles,
               const std::string& name);

  const std::vector<Vec3>& positions() const { return positions_; }
  const std::vector<std::uint32_t>& triangles() const { return triangles_; }
  Index num_triangles() const { return static_cast<Index>(triangles_.size() / 3); }
  /// Unit normal of triangle t (zero for a zero-area triangle).
  const Vec3& triangle_normal(Index t) const { return normals_[static_cast<std::size_t>(t)]; }
  /// Total area (model units squared).
  double area() const { return area_; }
  /// Connected components (by shared vertices) and each vertex's component (-1 if unused).
  int num_components() const { return num_components_; }
  int vertex_component(Index v) const { return component_[static_cast<std::size_t>(v)]; }

  /// Boundary loops: their count, each vertex's loop (-1 inside or unused), and their lengths.
  int num_loops() const { return static_cast<int>(loop_length_.size()); }
  int vertex_loop(Index v) const { return vertex_loop_[static_cast<std::size_t>(v)]; }
  double loop_length(int loop) const { return loop_length_[static_cast<std::size_t>(loop)]; }
  /// The vertices of each loop in order (the faces' orientation).
  const std::vector<std::vector<Index>>& loops() const { return loops_; }

  /// The closest point to `p` on a triangle that faces the same way as `normal` (positive dot
  /// product), searched up to `reach` beyond the unrestricted closest point; the unrestricted
  /// closest point when none is that close or `normal` is zero. Keeps a vertex on its own side
  /// of a thin part (an ear, a finger) where the other side is nearer.
  ClosestPoint Project(const Vec3& p, const Vec3& normal, double reach) const;
  /// The closest point to `p` on boundary loop `loop` (its edges as segments).
  Vec3 ProjectToLoop(const Vec3& p, int loop) const;
  /// Arc length along `loop` (from its first vertex, in the faces' direction) of the point of
  /// the loop closest to `p`.
  double LoopParameter(const Vec3& p, int loop) const;
  /// The point of `loop` at arc length `s` (taken modulo the loop's length).
  Vec3 LoopPoint(int loop, double s) const;
  /// The point of `loop` that divides the way from (the points closest to) `a` to `b`, in the
  /// faces' direction, in the ratio t : 1 - t (t = 0.5: half way along the loop between them).
  Vec3 LoopBetween(int loop, const Vec3& a, const Vec3& b, double t) const;
  /// The unit normal at a point of triangle `t` with barycentric coordinates `b` (ClosestPoint
  /// fields): the interpolated area-weighted vertex normals, a smooth field.
  Vec3 Normal(Index t, const Vec3& b) const;

 private:
  std::vector<Vec3> positions_;
  std::vector<std::uint32_t> triangles_;
  std::vector<Vec3> normals_;
  std::vector<Vec3> vertex_normals_;
  double area_ = 0.0;
  int num_components_ = 0;
  std::vector<int> component_;
  std::vector<int> vertex_loop_;
  std::vector<double> loop_length_;
  std::vector<std::vector<Index>> loops_;
  std::vector<int> segment_loop_;      ///< Loop of each boundary segment (tree triangle (a, b, b)).
  std::vector<double> segment_start_;  ///< Arc length of each segment's start along its loop.
  std::vector<std::size_t> loop_first_segment_;
  TriangleDistanceTree tree_, boundary_tree_;
};

}  // namespace dermis
