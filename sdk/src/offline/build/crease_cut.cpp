// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// A control mesh cut open along its hard creases (docs/characters.md, "Hard edges cut open"),
// so that the domain surface (Yoon, section 3, Eq. 1) meets itself at the crease with the
// angle the source has instead of rounding it.
#include "dermis/offline/build/crease_cut.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "dermis/core/mesh_topology.h"
#include "union_find.h"

namespace dermis {

Status CutAlongCreases(const CreaseChains& chains, double tolerance, PolygonMesh* control,
                       CreaseCutResult* result) {
  CreaseCutResult res;
  if (!(tolerance >= 0.0) || !std::isfinite(tolerance)) {
    return Status::InvalidInput("crease cut: the tolerance must be finite and >= 0");
  }
  MeshTopology topo;
  Status s = MeshTopology::Build(control->num_vertices(), control->face_offsets,
                                 control->face_vertices, &topo);
  if (!s.ok()) return s.WithContext("crease cut");
  const std::vector<Vec3>& x = control->positions;
  const Index nv = control->num_vertices();
  // The chain each vertex lies on, per chain (a corner lies on several).
  std::vector<std::vector<int>> on(static_cast<std::size_t>(nv));
  for (int c = 0; c < chains.num_chains(); ++c) {
    for (Index v = 0; v < nv; ++v) {
      const Vec3& p = x[static_cast<std::size_t>(v)];
      if (glm::length(chains.Project(c, p) - p) <= tolerance)
        on[static_cast<std::size_t>(v)].push_back(c);
    }
  }
  // Cut edges: both ends on one chain, which runs close to the edge between them.
  const Index ne = topo.num_edges();
  std::vector<char> cut(static_cast<std::size_t>(ne), 0);
  std::vector<int> cut_count(static_cast<std::size_t>(nv), 0);
  for (Index e = 0; e < ne; ++e) {
    const Index h = topo.edge_halfedge(e);
    if (topo.twin(h) == kInvalidIndex) continue;  // a boundary edge is open already
    const Index a = topo.halfedge_origin(h), b = topo.halfedge_dest(h);
    const Vec3 &pa = x[static_cast<std::size_t>(a)], &pb = x[static_cast<std::size_t>(b)];
    for (int c : on[static_cast<std::size_t>(a)]) {
      const auto& ob = on[static_cast<std::size_t>(b)];
      if (std::find(ob.begin(), ob.end(), c) == ob.end()) continue;
      if (chains.ChordDeviation(c, pa, pb) <= 0.25 * glm::length(pb - pa) + tolerance) {
        cut[static_cast<std::size_t>(e)] = 1;
        ++cut_count[static_cast<std::size_t>(a)], ++cut_count[static_cast<std::size_t>(b)];
        break;
      }
    }
  }
  // A crease that ends inside the surface (a slit's end: one cut edge at a vertex off the
  // boundary) cannot be opened there: the two sides of the slit would meet in one chart's two
  // boundary rays, which no patch maps to one curve without folding. Such chains are left
  // closed, edge by edge back to a junction (three or more cut edges) or the boundary, and
  // stay rounded like any crease kept as control edges.
  {
    std::vector<Index> queue;
    for (Index v = 0; v < nv; ++v) {
      if (cut_count[static_cast<std::size_t>(v)] == 1 && !topo.is_boundary_vertex(v))
        queue.push_back(v);
    }
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const Index v = queue[q];
      if (cut_count[static_cast<std::size_t>(v)] != 1) continue;
      for (int i = 0; i < topo.valence(v); ++i) {
        const RingCorner rc = topo.ring(v, i);
        const Index h = topo.face_offset(rc.face) + rc.corner;  // leaves v
        const Index e = topo.halfedge_edge(h);
        if (!cut[static_cast<std::size_t>(e)]) continue;
        cut[static_cast<std::size_t>(e)] = 0;
        const Index w = topo.halfedge_dest(h);
        --cut_count[static_cast<std::size_t>(v)];
        if (--cut_count[static_cast<std::size_t>(w)] == 1 && !topo.is_boundary_vertex(w))
          queue.push_back(w);
        break;
      }
    }
  }
  // Corners of each face around a vertex (half-edges by origin) joined across the edges not
  // cut: union-find over half-edges.
  const Index nh = topo.num_halfedges();
  UnionFind corners(nh);
  auto find = [&](Index h) { return corners.Find(h); };
  auto unite = [&](Index a, Index b) { corners.Unite(a, b); };
  for (Index h = 0; h < nh; ++h) {
    const Index t = topo.twin(h);
    if (t == kInvalidIndex || t < h || cut[static_cast<std::size_t>(topo.halfedge_edge(h))])
      continue;
    unite(h, topo.next(t));  // the corner of h's origin in the twin's face
    unite(topo.next(h), t);  // the corner of h's destination
  }
  // One vertex per class: the first class of a vertex (in half-edge order) keeps its index.
  std::vector<Index> id(static_cast<std::size_t>(nh), kInvalidIndex);
  std::vector<char> taken(static_cast<std::size_t>(nv), 0);
  std::vector<Index> origin(static_cast<std::size_t>(nv));
  std::iota(origin.begin(), origin.end(), Index{0});
  std::vector<Vec3> positions = x;
  for (Index h = 0; h < nh; ++h) {
    const Index r = find(h);
    if (id[static_cast<std::size_t>(r)] != kInvalidIndex) continue;
    const Index v = topo.halfedge_origin(h);
    if (!taken[static_cast<std::size_t>(v)]) {
      taken[static_cast<std::size_t>(v)] = 1;
      id[static_cast<std::size_t>(r)] = v;
    } else {
      id[static_cast<std::size_t>(r)] = static_cast<Index>(positions.size());
      positions.push_back(x[static_cast<std::size_t>(v)]);
      origin.push_back(v);
    }
  }
  res.new_vertices = static_cast<int>(positions.size()) - nv;
  // The cut faces, checked before anything is written.
  std::vector<Index> faces(control->face_vertices.size());
  for (Index h = 0; h < nh; ++h) {
    faces[static_cast<std::size_t>(h)] = id[static_cast<std::size_t>(find(h))];
  }
  // A vertex on the cut that stayed on no boundary (a cut edge whose two ends both had one
  // fan, a one-edge slit: nothing opened there) is no seam vertex.
  MeshTopology after;
  s = MeshTopology::Build(static_cast<Index>(positions.size()), control->face_offsets, faces,
                          &after);
  if (!s.ok()) return Status::Internal("crease cut: the cut mesh is invalid: " + s.message());
  control->face_vertices = std::move(faces);
  control->positions = std::move(positions);
  if (!control->vertex_lines.empty()) control->vertex_lines.resize(control->positions.size(), 0);
  res.seam.resize(control->positions.size());
  for (std::size_t v = 0; v < res.seam.size(); ++v) {
    const Index o = origin[v];
    const int k = cut_count[static_cast<std::size_t>(o)];
    if (k > 0 && after.is_boundary_vertex(static_cast<Index>(v))) {
      res.seam[v] = k == 2 && !topo.is_boundary_vertex(o) ? 1 : 2;
    }
  }
  // The edges opened: their two faces name different copies of an end.
  res.cut_edges = 0;
  for (Index e = 0; e < ne; ++e) {
    if (!cut[static_cast<std::size_t>(e)]) continue;
    const Index h = topo.edge_halfedge(e), t = topo.twin(h);
    if (find(h) != find(topo.next(t)) || find(topo.next(h)) != find(t)) ++res.cut_edges;
  }
  if (result) *result = std::move(res);
  return Status::Ok();
}

}  // namespace dermis
