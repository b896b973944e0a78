// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// One Catmull-Clark style topological split (face points and edge points) turning any polygon
// mesh into quads (docs/notes/manifold.md section 1, "(inferred)"); linear positions keep input
// vertices.
#include "dermis/offline/geometry/quadrangulate.h"

#include "dermis/core/mesh_topology.h"

namespace dermis {

namespace {

Status Split(const PolygonMesh& mesh, bool keep_quads, QuadMesh* out) {
  MeshTopology topo;
  Status s = MeshTopology::Build(mesh.num_vertices(), mesh.face_offsets, mesh.face_vertices, &topo);
  if (!s.ok()) return s.WithContext(mesh.source_name.empty() ? "mesh" : mesh.source_name);
  QuadMesh q;
  q.num_input_vertices = mesh.num_vertices();
  q.positions = mesh.positions;
  if (keep_quads && topo.is_all_quads()) {
    q.quads = mesh.face_vertices;
    q.quad_source_face.resize(mesh.num_faces());
    for (Index f = 0; f < mesh.num_faces(); ++f) q.quad_source_face[f] = f;
    *out = std::move(q);
    return Status::Ok();
  }
  const Index nv = mesh.num_vertices();
  const Index nf = mesh.num_faces();
  // Face points [nv, nv + nf), edge points [nv + nf, nv + nf + ne).
  for (Index f = 0; f < nf; ++f) {
    Vec3 c(0.0);
    const Index n = mesh.face_size(f);
    for (Index h = mesh.face_offsets[f]; h < mesh.face_offsets[f + 1]; ++h) {
      c += mesh.positions[mesh.face_vertices[h]];
    }
    q.positions.push_back(c / static_cast<double>(n));
  }
  for (Index e = 0; e < topo.num_edges(); ++e) {
    const Index h = topo.edge_halfedge(e);
    q.positions.push_back(
        0.5 * (mesh.positions[topo.halfedge_origin(h)] + mesh.positions[topo.halfedge_dest(h)]));
  }
  const Index edge_base = nv + nf;
  for (Index f = 0; f < nf; ++f) {
    const Index begin = mesh.face_offsets[f], end = mesh.face_offsets[f + 1];
    for (Index h = begin; h < end; ++h) {
      const Index hp = topo.prev(h);
      q.quads.insert(q.quads.end(), {topo.halfedge_origin(h), edge_base + topo.halfedge_edge(h),
                                     nv + f, edge_base + topo.halfedge_edge(hp)});
      q.quad_source_face.push_back(f);
    }
  }
  *out = std::move(q);
  return Status::Ok();
}

}  // namespace

Status Quadrangulate(const PolygonMesh& mesh, QuadMesh* out) { return Split(mesh, true, out); }

Status SplitIntoQuads(const PolygonMesh& mesh, QuadMesh* out) { return Split(mesh, false, out); }

}  // namespace dermis
