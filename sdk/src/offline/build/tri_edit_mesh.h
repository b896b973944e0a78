// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// An editable manifold triangle mesh for remeshing (private to offline/build): faces as vertex
// triples, counter-clockwise, and per vertex the list of its faces. Edge split, edge collapse
// and edge flip keep it manifold and consistently oriented; the checks that decide whether a
// collapse or flip is topologically allowed are here, the geometric ones are the caller's
// (isotropic_remesh.cpp). Deleted vertices and faces leave holes in the numbering until
// Compact(). Every operation is deterministic (fixed iteration orders).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "dermis/core/types.h"

namespace dermis {
namespace remesh_detail {

class TriEditMesh {
 public:
  /// Takes positions and triangles (3 indices each); the caller guarantees a manifold,
  /// consistently oriented mesh without degenerate (repeated-index) triangles.
  void Init(std::vector<Vec3> positions, const std::vector<std::uint32_t>& triangles);

  Index num_vertex_slots() const { return static_cast<Index>(position_.size()); }
  Index num_face_slots() const { return static_cast<Index>(face_.size()); }
  Index num_vertices() const { return live_vertices_; }
  Index num_faces() const { return live_faces_; }
  bool vertex_alive(Index v) const { return alive_v_[static_cast<std::size_t>(v)] != 0; }
  bool face_alive(Index f) const { return alive_f_[static_cast<std::size_t>(f)] != 0; }
  const std::array<Index, 3>& face(Index f) const { return face_[static_cast<std::size_t>(f)]; }
  /// The live faces around v (unordered, deterministic).
  const std::vector<Index>& vertex_faces(Index v) const {
    return vfaces_[static_cast<std::size_t>(v)];
  }
  Vec3& position(Index v) { return position_[static_cast<std::size_t>(v)]; }
  const Vec3& position(Index v) const { return position_[static_cast<std::size_t>(v)]; }

  /// Per-vertex data the remesher carries: the reference boundary loop a boundary vertex
  /// belongs to (-1 inside) and its target edge length.
  std::vector<int> loop;
  std::vector<double> size;
  /// Feature tag of each vertex (crease_chains.h: kNoFeature, a chain, kCornerFeature); a vertex
  /// made by SplitEdge() gets kNoFeature (the caller tags it).
  std::vector<int> feature;

  /// The face holding the directed edge a -> b, or kInvalidIndex.
  Index DirectedEdgeFace(Index a, Index b) const;
  /// The third vertex of face f opposite the edge {a, b}.
  Index Opposite(Index f, Index a, Index b) const;
  bool HasEdge(Index a, Index b) const;
  /// True if exactly one face holds the edge {a, b}.
  bool IsBoundaryEdge(Index a, Index b) const;
  bool IsBoundaryVertex(Index v) const;
  /// Neighbouring vertices of v, sorted by index.
  void Neighbors(Index v, std::vector<Index>* out) const;
  int Valence(Index v) const;
  /// The boundary neighbours of boundary vertex v: `next` follows v along its loop in the
  /// direction of the faces' orientation (v -> next is a boundary edge with a face), `prev`
  /// precedes it. Both kInvalidIndex for an interior vertex.
  void BoundaryNeighbors(Index v, Index* prev, Index* next) const;
  /// Number of vertices on the boundary loop through boundary vertex v.
  int BoundaryLoopLength(Index v) const;

  /// Edges as (a, b), each once, in face order: a -> b of a face with a < b, or the
  /// boundary edge's single direction.
  void Edges(std::vector<std::array<Index, 2>>* out) const;

  /// Splits edge {a, b} with a new vertex at p (data copied from a, size = mean); returns it.
  Index SplitEdge(Index a, Index b, const Vec3& p);
  /// Whether collapsing `from` into `to` (removing `from`) keeps the mesh a manifold with
  /// interior valence >= 3, boundary loops of >= 3 vertices and no dangling triangles.
  bool CanCollapse(Index from, Index to) const;
  /// Removes `from`: its faces that hold `to` disappear, the others take `to` in its place.
  void Collapse(Index from, Index to);
  /// Whether the interior edge {a, b} can be flipped (its opposite vertices not yet joined,
  /// a and b keep valence >= 3).
  bool CanFlip(Index a, Index b) const;
  /// Flips the interior edge {a, b} to join its two opposite vertices.
  void Flip(Index a, Index b);

  /// Live positions and triangles renumbered in slot order; `old_to_new` (optional) receives
  /// the new index of each vertex slot or kInvalidIndex. The per-vertex data is compacted too.
  void Compact(std::vector<Index>* old_to_new = nullptr);
  /// The live mesh as positions and triangles (after Compact(), indices are slots).
  void Export(std::vector<Vec3>* positions, std::vector<std::uint32_t>* triangles) const;

 private:
  void RemoveFaceFrom(Index v, Index f);
  std::vector<Vec3> position_;
  std::vector<std::array<Index, 3>> face_;
  std::vector<std::vector<Index>> vfaces_;
  std::vector<char> alive_v_, alive_f_;
  Index live_vertices_ = 0, live_faces_ = 0;
};

}  // namespace remesh_detail
}  // namespace dermis
