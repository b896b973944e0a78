// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Half-edge construction with manifold validation and counter-clockwise one-rings
// (docs/notes/manifold.md section 0: the next face around a vertex is twin(prev(h)), as in
// Ying-Zorin's gpmesh `edge = conj(prev(edge))`).
#include "dermis/core/mesh_topology.h"

#include <algorithm>
#include <numeric>
#include <string>

namespace dermis {
namespace {

struct DirectedEdge {
  Index from;
  Index to;
  Index halfedge;
  bool operator<(const DirectedEdge& o) const {
    if (from != o.from) return from < o.from;
    if (to != o.to) return to < o.to;
    return halfedge < o.halfedge;
  }
};

std::string FaceName(const ElementNamer* namer, Index f) {
  return namer && namer->face ? namer->face(f) : "face " + std::to_string(f);
}

std::string VertexName(const ElementNamer* namer, Index v) {
  return namer && namer->vertex ? namer->vertex(v) : "vertex " + std::to_string(v);
}

Index FindRoot(std::vector<Index>& parent, Index x) {
  while (parent[x] != x) {
    parent[x] = parent[parent[x]];
    x = parent[x];
  }
  return x;
}

}  // namespace

Index MeshTopology::next(Index h) const {
  const Index f = halfedge_face_[h];
  return h + 1 == face_offsets_[f + 1] ? face_offsets_[f] : h + 1;
}

Index MeshTopology::prev(Index h) const {
  const Index f = halfedge_face_[h];
  return h == face_offsets_[f] ? face_offsets_[f + 1] - 1 : h - 1;
}

Status MeshTopology::BuildQuads(Index num_vertices, const std::vector<Index>& quad_vertices,
                                MeshTopology* out, const ElementNamer* namer) {
  if (quad_vertices.size() % 4 != 0) {
    return Status::InvalidInput("quad index array size " + std::to_string(quad_vertices.size()) +
                                " is not a multiple of 4");
  }
  std::vector<Index> offsets(quad_vertices.size() / 4 + 1);
  for (size_t f = 0; f < offsets.size(); ++f) offsets[f] = static_cast<Index>(4 * f);
  return Build(num_vertices, offsets, quad_vertices, out, namer);
}

Status MeshTopology::Build(Index num_vertices, const std::vector<Index>& face_offsets,
                           const std::vector<Index>& face_vertices, MeshTopology* out,
                           const ElementNamer* namer) {
  if (num_vertices < 0) return Status::InvalidInput("negative vertex count");
  if (face_offsets.empty() || face_offsets.front() != 0 ||
      static_cast<size_t>(face_offsets.back()) != face_vertices.size()) {
    return Status::InvalidInput("face offsets do not describe the face index array");
  }
  MeshTopology t;
  t.num_vertices_ = num_vertices;
  t.face_offsets_ = face_offsets;
  t.face_vertices_ = face_vertices;
  Status s = t.CheckFaces(namer);
  if (s.ok()) s = t.LinkTwins(namer);
  if (s.ok()) s = t.OrderRings(namer);
  if (!s.ok()) return s;
  t.FindComponents();
  *out = std::move(t);
  return Status::Ok();
}

// Per-face checks: size, range, repeated vertices.
Status MeshTopology::CheckFaces(const ElementNamer* namer) {
  const Index nf = num_faces();
  all_quads_ = nf > 0;
  halfedge_face_.assign(num_halfedges(), kInvalidIndex);
  // last_face[v]: the last face seen using v, so the repeated-vertex check is linear in the face
  // size (a 250,000-gon must not take n^2 steps).
  std::vector<Index> last_face(static_cast<size_t>(num_vertices_), kInvalidIndex);
  for (Index f = 0; f < nf; ++f) {
    const Index begin = face_offsets_[f], end = face_offsets_[f + 1];
    const Index n = end - begin;
    if (n < 3) {
      return Status::InvalidInput(FaceName(namer, f) + " has " + std::to_string(n) +
                                  " vertices (at least 3 needed)");
    }
    if (n != 4) all_quads_ = false;
    for (Index h = begin; h < end; ++h) {
      const Index v = face_vertices_[h];
      if (v < 0 || v >= num_vertices_) {
        return Status::InvalidInput(FaceName(namer, f) + " uses vertex index " + std::to_string(v) +
                                    ", out of range (mesh has " + std::to_string(num_vertices_) +
                                    " vertices)");
      }
      if (last_face[v] == f) {
        return Status::InvalidInput(FaceName(namer, f) + " uses " + VertexName(namer, v) +
                                    " more than once");
      }
      last_face[v] = f;
      halfedge_face_[h] = f;
    }
  }
  return Status::Ok();
}

// Directed edges: each must occur once; the twin is the reversed edge.
Status MeshTopology::LinkTwins(const ElementNamer* namer) {
  const Index num_he = num_halfedges();
  std::vector<DirectedEdge> edges(num_he);
  for (Index h = 0; h < num_he; ++h) edges[h] = {face_vertices_[h], halfedge_dest(h), h};
  std::sort(edges.begin(), edges.end());
  for (size_t i = 1; i < edges.size(); ++i) {
    if (edges[i].from == edges[i - 1].from && edges[i].to == edges[i - 1].to) {
      return Status::InvalidInput(
          FaceName(namer, halfedge_face_[edges[i - 1].halfedge]) + " and " +
          FaceName(namer, halfedge_face_[edges[i].halfedge]) + " both use the edge from " +
          VertexName(namer, edges[i].from) + " to " + VertexName(namer, edges[i].to) +
          " in the same direction (non-manifold edge or inconsistent face orientation)");
    }
  }
  twin_.assign(num_he, kInvalidIndex);
  for (Index h = 0; h < num_he; ++h) {
    const DirectedEdge key{halfedge_dest(h), face_vertices_[h], -1};
    auto it = std::lower_bound(edges.begin(), edges.end(), key);
    if (it != edges.end() && it->from == key.from && it->to == key.to) twin_[h] = it->halfedge;
  }
  halfedge_edge_.assign(num_he, kInvalidIndex);
  for (Index h = 0; h < num_he; ++h) {
    const Index tw = twin_[h];
    if (tw == kInvalidIndex || h < tw) {
      halfedge_edge_[h] = static_cast<Index>(edge_halfedge_.size());
      edge_halfedge_.push_back(h);
    } else {
      halfedge_edge_[h] = halfedge_edge_[tw];
    }
    if (tw == kInvalidIndex) has_boundary_ = true;
  }
  return Status::Ok();
}

// Outgoing half-edges per vertex (CSR), then one counter-clockwise walk per vertex.
Status MeshTopology::OrderRings(const ElementNamer* namer) {
  const Index num_he = num_halfedges();
  std::vector<Index> out_offsets(num_vertices_ + 1, 0);
  for (Index h = 0; h < num_he; ++h) ++out_offsets[face_vertices_[h] + 1];
  std::partial_sum(out_offsets.begin(), out_offsets.end(), out_offsets.begin());
  std::vector<Index> outgoing(num_he);
  {
    std::vector<Index> fill(out_offsets.begin(), out_offsets.end() - 1);
    for (Index h = 0; h < num_he; ++h) outgoing[fill[face_vertices_[h]]++] = h;
  }
  ring_offsets_ = out_offsets;
  ring_.assign(num_he, RingCorner{});
  halfedge_ring_index_.assign(num_he, -1);
  vertex_boundary_.assign(num_vertices_, 0);
  for (Index v = 0; v < num_vertices_; ++v) {
    const Index begin = out_offsets[v], end = out_offsets[v + 1];
    if (begin == end) continue;
    Index start = outgoing[begin];
    int boundary_starts = 0;
    for (Index i = begin; i < end; ++i) {
      if (twin_[outgoing[i]] == kInvalidIndex) {
        if (boundary_starts == 0) start = outgoing[i];
        ++boundary_starts;
      }
    }
    if (boundary_starts > 1) {
      return Status::InvalidInput(VertexName(namer, v) + " joins " +
                                  std::to_string(boundary_starts) +
                                  " separate fans of faces (non-manifold vertex)");
    }
    vertex_boundary_[v] = boundary_starts == 1 ? 1 : 0;
    Index h = start;
    int count = 0;
    while (true) {
      if (count >= end - begin) break;  // would loop forever on a broken ring
      const Index f = halfedge_face_[h];
      ring_[begin + count] = RingCorner{f, static_cast<int>(h - face_offsets_[f])};
      halfedge_ring_index_[h] = count;
      ++count;
      const Index nh = twin_[prev(h)];
      if (nh == kInvalidIndex || nh == start) break;
      h = nh;
    }
    if (count != end - begin) {
      return Status::InvalidInput(VertexName(namer, v) +
                                  " is shared by several separate fans of faces "
                                  "(non-manifold vertex)");
    }
  }
  return Status::Ok();
}

// Connected components over faces sharing a vertex (the one-rings of OrderRings()).
void MeshTopology::FindComponents() {
  const Index nf = num_faces();
  std::vector<Index> parent(nf);
  std::iota(parent.begin(), parent.end(), 0);
  for (Index v = 0; v < num_vertices_; ++v) {
    const Index begin = ring_offsets_[v], end = ring_offsets_[v + 1];
    for (Index i = begin + 1; i < end; ++i) {
      const Index a = FindRoot(parent, ring_[begin].face);
      const Index b = FindRoot(parent, ring_[i].face);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  }
  face_component_.assign(nf, 0);
  std::vector<Index> root_id(nf, kInvalidIndex);
  for (Index f = 0; f < nf; ++f) {
    const Index r = FindRoot(parent, f);
    if (root_id[r] == kInvalidIndex) root_id[r] = num_components_++;
    face_component_[f] = root_id[r];
  }
}

std::size_t MeshTopology::memory_bytes() const {
  return sizeof(Index) *
             (face_offsets_.capacity() + face_vertices_.capacity() + halfedge_face_.capacity() +
              twin_.capacity() + halfedge_edge_.capacity() + edge_halfedge_.capacity() +
              ring_offsets_.capacity() + face_component_.capacity()) +
         sizeof(int) * halfedge_ring_index_.capacity() + sizeof(RingCorner) * ring_.capacity() +
         vertex_boundary_.capacity();
}

}  // namespace dermis
