// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Half-edge connectivity of a polygon mesh with ordered vertex one-rings.
///
/// Conventions (docs/notes/manifold.md section 0): faces are counter-clockwise. The half-edge h of
/// corner k of face f runs from corner k to corner k+1 and has index face_offset(f) + k. Around a
/// vertex the incident faces are numbered counter-clockwise so that the edge to the *previous*
/// corner of ring face i is the edge to the *next* corner of ring face i+1 (the d-axis of face i is
/// the c-axis of face i+1). On a boundary vertex ring face 0 is the face whose outgoing edge lies
/// on the boundary, and the ring is open.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "dermis/core/status.h"
#include "dermis/core/types.h"

namespace dermis {

/// One entry of a vertex one-ring: an incident face and the corner of that face at the vertex.
struct RingCorner {
  Index face = kInvalidIndex;
  int corner = 0;
};

/// Optional names for faces and vertices in error messages (for example "face 3 (line 17)").
/// Either function may be empty; the default is "face N" / "vertex N".
struct ElementNamer {
  std::function<std::string(Index)> face;
  std::function<std::string(Index)> vertex;
};

/// Immutable half-edge topology. Built once per control mesh (OpenSubdiv's "topology once").
///
/// Requirements checked by Build(): every face has >= 3 distinct in-range vertices; every
/// directed edge is used once (consistent orientation, at most two faces per edge); every vertex
/// used by a face has a single fan of faces (manifold vertex); several connected components and
/// boundaries are allowed. Vertices used by no face are allowed and have valence 0.
class MeshTopology {
 public:
  MeshTopology() = default;

  /// Builds the topology of `num_vertices` vertices and faces given in CSR form:
  /// face f has vertices face_vertices[face_offsets[f] .. face_offsets[f+1]).
  /// `face_offsets` has num_faces + 1 entries and starts with 0.
  /// On failure returns a Status naming the face (0-based) and the problem; `out` is untouched.
  static Status Build(Index num_vertices, const std::vector<Index>& face_offsets,
                      const std::vector<Index>& face_vertices, MeshTopology* out,
                      const ElementNamer* namer = nullptr);

  /// Convenience overload for an all-quad mesh: 4 vertex indices per face.
  static Status BuildQuads(Index num_vertices, const std::vector<Index>& quad_vertices,
                           MeshTopology* out, const ElementNamer* namer = nullptr);

  Index num_vertices() const { return num_vertices_; }
  Index num_faces() const { return static_cast<Index>(face_offsets_.size()) - 1; }
  Index num_halfedges() const { return static_cast<Index>(face_vertices_.size()); }
  /// Bytes held by the topology's arrays.
  std::size_t memory_bytes() const;
  Index num_edges() const { return static_cast<Index>(edge_halfedge_.size()); }
  /// True when every face has exactly 4 corners.
  bool is_all_quads() const { return all_quads_; }

  Index face_size(Index f) const { return face_offsets_[f + 1] - face_offsets_[f]; }
  Index face_offset(Index f) const { return face_offsets_[f]; }
  /// Vertex at corner k of face f.
  Index face_vertex(Index f, int k) const { return face_vertices_[face_offsets_[f] + k]; }

  /// Face that owns half-edge h.
  Index halfedge_face(Index h) const { return halfedge_face_[h]; }
  /// Origin vertex of half-edge h.
  Index halfedge_origin(Index h) const { return face_vertices_[h]; }
  /// Destination vertex of half-edge h.
  Index halfedge_dest(Index h) const { return face_vertices_[next(h)]; }
  /// Next half-edge in the same face.
  Index next(Index h) const;
  /// Previous half-edge in the same face.
  Index prev(Index h) const;
  /// Opposite half-edge, or kInvalidIndex on a boundary edge.
  Index twin(Index h) const { return twin_[h]; }
  /// Undirected edge of half-edge h.
  Index halfedge_edge(Index h) const { return halfedge_edge_[h]; }
  /// Canonical half-edge of edge e (the one with the smaller index, or the only one).
  Index edge_halfedge(Index e) const { return edge_halfedge_[e]; }
  /// Position of face halfedge_face(h) in the one-ring of halfedge_origin(h).
  int halfedge_ring_index(Index h) const { return halfedge_ring_index_[h]; }

  /// Number of faces around vertex v (its valence for interior vertices).
  int valence(Index v) const { return ring_offsets_[v + 1] - ring_offsets_[v]; }
  bool is_boundary_vertex(Index v) const { return vertex_boundary_[v] != 0; }
  /// Whether any vertex of face f is a boundary vertex.
  bool face_touches_boundary(Index f) const {
    for (Index k = 0; k < face_size(f); ++k) {
      if (is_boundary_vertex(face_vertices_[face_offsets_[f] + k])) return true;
    }
    return false;
  }
  /// Face i (0-based, counter-clockwise) around vertex v and its corner there.
  RingCorner ring(Index v, int i) const { return ring_[ring_offsets_[v] + i]; }
  /// Index of the connected component (by shared edges and vertices) of face f.
  Index face_component(Index f) const { return face_component_[f]; }
  Index num_components() const { return num_components_; }
  bool has_boundary() const { return has_boundary_; }

 private:
  // The steps of Build(), in order, each on the members the previous ones filled.
  Status CheckFaces(const ElementNamer* namer);  // sizes, ranges, repeats; halfedge_face_
  Status LinkTwins(const ElementNamer* namer);   // twin_, edges, has_boundary_
  Status OrderRings(const ElementNamer* namer);  // ring_, ring_offsets_, boundary vertices
  void FindComponents();                         // face_component_, num_components_

  Index num_vertices_ = 0;
  bool all_quads_ = false;
  bool has_boundary_ = false;
  Index num_components_ = 0;
  std::vector<Index> face_offsets_{0};
  std::vector<Index> face_vertices_;
  std::vector<Index> halfedge_face_;
  std::vector<Index> twin_;
  std::vector<Index> halfedge_edge_;
  std::vector<Index> edge_halfedge_;
  std::vector<int> halfedge_ring_index_;
  std::vector<Index> ring_offsets_;
  std::vector<RingCorner> ring_;
  std::vector<unsigned char> vertex_boundary_;
  std::vector<Index> face_component_;
};

}  // namespace dermis
