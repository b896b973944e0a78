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
  auto face_name = [namer](Index f) {
    return namer && namer->face ? namer->face(f) : "face " + std::to_string(f);
  };
  auto vertex_name = [namer](Index v) {
    return namer && namer->vertex ? namer->vertex(v) : "vertex " + std::to_string(v);
  };
  if (num_vertices < 0) return Status::InvalidInput("negative vertex count");
  if (face_offsets.empty() || face_offsets.front() != 0 ||
      static_cast<size_t>(face_offsets.back()) != face_vertices.size()) {
    return Status::InvalidInput("face offsets do not describe the face index array");
  }
  MeshTopology t;
  t.num_vertices_ = num_vertices;
  t.face_offsets_ = face_offsets;
  t.face_vertices_ = face_vertices;
  const Index num_faces = t.num_faces();
  const Index num_he = t.num_halfedges();
  t.all_quads_ = num_faces > 0;

  // Per-face checks: size, range, repeated vertices.
  t.halfedge_face_.assign(num_he, kInvalidIndex);
  for (Index f = 0; f < num_faces; ++f) {
    const Index begin = face_offsets[f], end = face_offsets[f + 1];
    const Index n = end - begin;
    if (n < 3) {
      return Status::InvalidInput(face_name(f) + " has " + std::to_string(n) +
                                  " vertices (at least 3 needed)");
    }
    if (n != 4) t.all_quads_ = false;
    for (Index h = begin; h < end; ++h) {
      const Index v = face_vertices[h];
      if (v < 0 || v >= num_vertices) {
        return Status::InvalidInput(face_name(f) + " uses vertex index " + std::to_string(v) +
                                    ", out of range (mesh has " + std::to_string(num_vertices) +
                                    " vertices)");
      }
      for (Index g = begin; g < h; ++g) {
        if (face_vertices[g] == v) {
          return Status::InvalidInput(face_name(f) + " uses " + vertex_name(v) + " more than once");
        }
      }
      t.halfedge_face_[h] = f;
    }
  }

  // Directed edges: each must occur once; the twin is the reversed edge.
  std::vector<DirectedEdge> edges(num_he);
  for (Index h = 0; h < num_he; ++h) edges[h] = {face_vertices[h], t.halfedge_dest(h), h};
  std::sort(edges.begin(), edges.end());
  for (size_t i = 1; i < edges.size(); ++i) {
    if (edges[i].from == edges[i - 1].from && edges[i].to == edges[i - 1].to) {
      return Status::InvalidInput(
          face_name(t.halfedge_face_[edges[i - 1].halfedge]) + " and " +
          face_name(t.halfedge_face_[edges[i].halfedge]) + " both use the edge from " +
          vertex_name(edges[i].from) + " to " + vertex_name(edges[i].to) +
          " in the same direction (non-manifold edge or inconsistent face orientation)");
    }
  }
  t.twin_.assign(num_he, kInvalidIndex);
  for (Index h = 0; h < num_he; ++h) {
    const DirectedEdge key{t.halfedge_dest(h), face_vertices[h], -1};
    auto it = std::lower_bound(edges.begin(), edges.end(), key);
    if (it != edges.end() && it->from == key.from && it->to == key.to) t.twin_[h] = it->halfedge;
  }
  t.halfedge_edge_.assign(num_he, kInvalidIndex);
  for (Index h = 0; h < num_he; ++h) {
    const Index tw = t.twin_[h];
    if (tw == kInvalidIndex || h < tw) {
      t.halfedge_edge_[h] = static_cast<Index>(t.edge_halfedge_.size());
      t.edge_halfedge_.push_back(h);
    } else {
      t.halfedge_edge_[h] = t.halfedge_edge_[tw];
    }
    if (tw == kInvalidIndex) t.has_boundary_ = true;
  }

  // Outgoing half-edges per vertex (CSR), then one counter-clockwise walk per vertex.
  std::vector<Index> out_offsets(num_vertices + 1, 0);
  for (Index h = 0; h < num_he; ++h) ++out_offsets[face_vertices[h] + 1];
  std::partial_sum(out_offsets.begin(), out_offsets.end(), out_offsets.begin());
  std::vector<Index> outgoing(num_he);
  {
    std::vector<Index> fill(out_offsets.begin(), out_offsets.end() - 1);
    for (Index h = 0; h < num_he; ++h) outgoing[fill[face_vertices[h]]++] = h;
  }
  t.ring_offsets_ = out_offsets;
  t.ring_.assign(num_he, RingCorner{});
  t.halfedge_ring_index_.assign(num_he, -1);
  t.vertex_boundary_.assign(num_vertices, 0);
  for (Index v = 0; v < num_vertices; ++v) {
    const Index begin = out_offsets[v], end = out_offsets[v + 1];
    if (begin == end) continue;
    Index start = outgoing[begin];
    int boundary_starts = 0;
    for (Index i = begin; i < end; ++i) {
      if (t.twin_[outgoing[i]] == kInvalidIndex) {
        if (boundary_starts == 0) start = outgoing[i];
        ++boundary_starts;
      }
    }
    if (boundary_starts > 1) {
      return Status::InvalidInput(vertex_name(v) + " joins " + std::to_string(boundary_starts) +
                                  " separate fans of faces (non-manifold vertex)");
    }
    t.vertex_boundary_[v] = boundary_starts == 1 ? 1 : 0;
    Index h = start;
    int count = 0;
    while (true) {
      if (count >= end - begin) break;  // would loop forever on a broken ring
      const Index f = t.halfedge_face_[h];
      t.ring_[begin + count] = RingCorner{f, static_cast<int>(h - t.face_offsets_[f])};
      t.halfedge_ring_index_[h] = count;
      ++count;
      const Index nh = t.twin_[t.prev(h)];
      if (nh == kInvalidIndex || nh == start) break;
      h = nh;
    }
    if (count != end - begin) {
      return Status::InvalidInput(vertex_name(v) +
                                  " is shared by several separate fans of faces "
                                  "(non-manifold vertex)");
    }
  }

  // Connected components over faces sharing a vertex.
  std::vector<Index> parent(num_faces);
  std::iota(parent.begin(), parent.end(), 0);
  for (Index v = 0; v < num_vertices; ++v) {
    const Index begin = out_offsets[v], end = out_offsets[v + 1];
    for (Index i = begin + 1; i < end; ++i) {
      const Index a = FindRoot(parent, t.halfedge_face_[outgoing[begin]]);
      const Index b = FindRoot(parent, t.halfedge_face_[outgoing[i]]);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  }
  t.face_component_.assign(num_faces, 0);
  std::vector<Index> root_id(num_faces, kInvalidIndex);
  for (Index f = 0; f < num_faces; ++f) {
    const Index r = FindRoot(parent, f);
    if (root_id[r] == kInvalidIndex) root_id[r] = t.num_components_++;
    t.face_component_[f] = root_id[r];
  }

  *out = std::move(t);
  return Status::Ok();
}

}  // namespace dermis
