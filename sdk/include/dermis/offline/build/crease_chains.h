// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief The creases of a reference surface as polylines (docs/fitting.md, "Creases"): edges
/// whose dihedral angle reaches a threshold, chained between corners, with the queries a
/// feature-aware remesher needs to keep its vertices on them.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "dermis/core/types.h"
#include "dermis/offline/build/reference_surface.h"

namespace dermis {

/// Per-vertex feature tag of a remeshed vertex: kNoFeature (free on the surface), a chain index
/// (>= 0: it lies on that crease polyline and moves only along it) or kCornerFeature (fixed).
constexpr int kNoFeature = -1;
constexpr int kCornerFeature = -2;

/// Crease polylines of a ReferenceSurface. Immutable after Build(); queries are const.
class CreaseChains {
 public:
  /// Finds the crease edges of `ref` (interior edges whose two triangle normals are at least
  /// `crease_angle_deg` apart) and chains them. A corner is a vertex where a number of crease
  /// edges other than 2 meet, where the two crease edges turn by more than `corner_turn_deg`,
  /// or a boundary vertex on a crease; chains run from corner to corner, or are closed loops
  /// (a cap's rim). crease_angle_deg <= 0 finds none. The edges in `smooth_edges` (pairs of
  /// reference vertex indices, either order) are never creases, whatever their angle: the
  /// input's own shading marks them smooth (QuadRemeshOptions::smooth_edges).
  void Build(const ReferenceSurface& ref, double crease_angle_deg, double corner_turn_deg,
             const std::vector<std::array<std::uint32_t, 2>>& smooth_edges = {});

  bool empty() const { return chains_.empty(); }
  /// The reference's positions (Build() must have been called).
  const std::vector<Vec3>& reference_positions() const { return ref_->positions(); }
  int num_chains() const { return static_cast<int>(chains_.size()); }
  int num_closed() const;
  /// Crease edges of the reference, each as (a, b) with a < b, sorted.
  const std::vector<std::array<std::uint32_t, 2>>& edges() const { return edges_; }
  /// The chain of each edge in edges().
  const std::vector<int>& edge_chain() const { return edge_chain_; }
  /// kNoFeature, a chain index or kCornerFeature for each reference vertex.
  int vertex_feature(Index v) const { return vertex_feature_[static_cast<std::size_t>(v)]; }
  /// The chain of reference edge {a, b}, or -1 if it is not a crease edge.
  int EdgeChain(std::uint32_t a, std::uint32_t b) const;
  /// The vertices of chain c in order; a closed chain does not repeat its first vertex.
  const std::vector<Index>& chain(int c) const { return chains_[static_cast<std::size_t>(c)]; }
  bool closed(int c) const { return closed_[static_cast<std::size_t>(c)] != 0; }
  double length(int c) const { return arc_[static_cast<std::size_t>(c)].back(); }

  /// Arc length along chain c of its point closest to `p`.
  double Parameter(int c, const Vec3& p) const;
  /// The point of chain c at arc length s (clamped on an open chain, modulo on a closed one).
  Vec3 Point(int c, double s) const;
  /// The point of chain c closest to `p`.
  Vec3 Project(int c, const Vec3& p) const { return Point(c, Parameter(c, p)); }
  /// The point of chain c dividing the way from (the points closest to) `a` to `b` in the
  /// ratio t : 1 - t; on a closed chain along the shorter way.
  Vec3 Between(int c, const Vec3& a, const Vec3& b, double t) const;
  /// The largest distance from the segment (a, b) of the chain's vertices between (the points
  /// closest to) `a` and `b` (the way Between() goes): how far a chord of chain c cuts it.
  double ChordDeviation(int c, const Vec3& a, const Vec3& b) const;

 private:
  const ReferenceSurface* ref_ = nullptr;
  std::vector<std::array<std::uint32_t, 2>> edges_;
  std::vector<int> edge_chain_;
  std::vector<int> vertex_feature_;
  std::vector<std::vector<Index>> chains_;
  std::vector<char> closed_;
  std::vector<std::vector<double>> arc_;  ///< Cumulative length at each chain vertex (+ closing).
};

}  // namespace dermis
