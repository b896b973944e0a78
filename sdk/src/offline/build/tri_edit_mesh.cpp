// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Editable manifold triangle mesh with edge split, collapse and flip (see tri_edit_mesh.h). The
// collapse test is the link condition of Dey et al. (the common neighbours of the two ends are
// exactly the vertices opposite the edge), plus the boundary rules that keep every boundary
// loop a loop (Hoppe et al. 1993, "Mesh optimization", legal moves).
#include "tri_edit_mesh.h"

#include <algorithm>

namespace dermis {
namespace remesh_detail {
namespace {

int Slot(const std::array<Index, 3>& f, Index v) {
  for (int k = 0; k < 3; ++k) {
    if (f[static_cast<std::size_t>(k)] == v) return k;
  }
  return -1;
}

Index At(const std::array<Index, 3>& f, int k) { return f[static_cast<std::size_t>((k + 3) % 3)]; }

}  // namespace

void TriEditMesh::Init(std::vector<Vec3> positions, const std::vector<std::uint32_t>& triangles) {
  position_ = std::move(positions);
  const std::size_t nv = position_.size();
  face_.clear();
  vfaces_.assign(nv, {});
  alive_v_.assign(nv, 1);
  for (std::size_t t = 0; t + 2 < triangles.size(); t += 3) {
    const Index f = static_cast<Index>(face_.size());
    face_.push_back({static_cast<Index>(triangles[t]), static_cast<Index>(triangles[t + 1]),
                     static_cast<Index>(triangles[t + 2])});
    for (int k = 0; k < 3; ++k) vfaces_[triangles[t + static_cast<std::size_t>(k)]].push_back(f);
  }
  alive_f_.assign(face_.size(), 1);
  live_faces_ = static_cast<Index>(face_.size());
  live_vertices_ = 0;
  for (std::size_t v = 0; v < nv; ++v) {
    if (vfaces_[v].empty()) {
      alive_v_[v] = 0;
    } else {
      ++live_vertices_;
    }
  }
  loop.assign(nv, -1);
  size.assign(nv, 0.0);
  feature.assign(nv, -1);
}

Index TriEditMesh::DirectedEdgeFace(Index a, Index b) const {
  for (Index f : vertex_faces(a)) {
    const std::array<Index, 3>& t = face(f);
    const int k = Slot(t, a);
    if (At(t, k + 1) == b) return f;
  }
  return kInvalidIndex;
}

Index TriEditMesh::Opposite(Index f, Index a, Index b) const {
  for (Index v : face(f)) {
    if (v != a && v != b) return v;
  }
  return kInvalidIndex;
}

bool TriEditMesh::HasEdge(Index a, Index b) const {
  for (Index f : vertex_faces(a)) {
    if (Slot(face(f), b) >= 0) return true;
  }
  return false;
}

bool TriEditMesh::IsBoundaryEdge(Index a, Index b) const {
  int n = 0;
  for (Index f : vertex_faces(a)) n += Slot(face(f), b) >= 0 ? 1 : 0;
  return n == 1;
}

bool TriEditMesh::IsBoundaryVertex(Index v) const {
  for (Index f : vertex_faces(v)) {
    const std::array<Index, 3>& t = face(f);
    const Index next = At(t, Slot(t, v) + 1);
    if (DirectedEdgeFace(next, v) == kInvalidIndex) return true;
  }
  return false;
}

void TriEditMesh::Neighbors(Index v, std::vector<Index>* out) const {
  out->clear();
  for (Index f : vertex_faces(v)) {
    for (Index w : face(f)) {
      if (w != v) out->push_back(w);
    }
  }
  std::sort(out->begin(), out->end());
  out->erase(std::unique(out->begin(), out->end()), out->end());
}

int TriEditMesh::Valence(Index v) const {
  std::vector<Index> n;
  Neighbors(v, &n);
  return static_cast<int>(n.size());
}

void TriEditMesh::BoundaryNeighbors(Index v, Index* prev, Index* next) const {
  *prev = *next = kInvalidIndex;
  for (Index f : vertex_faces(v)) {
    const std::array<Index, 3>& t = face(f);
    const int k = Slot(t, v);
    const Index n = At(t, k + 1), p = At(t, k - 1);
    if (DirectedEdgeFace(n, v) == kInvalidIndex) *next = n;
    if (DirectedEdgeFace(v, p) == kInvalidIndex) *prev = p;
  }
}

int TriEditMesh::BoundaryLoopLength(Index v) const {
  Index prev = kInvalidIndex, next = kInvalidIndex;
  BoundaryNeighbors(v, &prev, &next);
  if (next == kInvalidIndex) return 0;
  int n = 1;
  for (Index w = next; w != v && w != kInvalidIndex && n <= live_vertices_; ++n) {
    BoundaryNeighbors(w, &prev, &next);
    w = next;
  }
  return n;
}

void TriEditMesh::Edges(std::vector<std::array<Index, 2>>* out) const {
  out->clear();
  for (Index f = 0; f < num_face_slots(); ++f) {
    if (!face_alive(f)) continue;
    const std::array<Index, 3>& t = face(f);
    for (int k = 0; k < 3; ++k) {
      const Index a = At(t, k), b = At(t, k + 1);
      if (a < b || DirectedEdgeFace(b, a) == kInvalidIndex) out->push_back({a, b});
    }
  }
}

void TriEditMesh::RemoveFaceFrom(Index v, Index f) {
  std::vector<Index>& list = vfaces_[static_cast<std::size_t>(v)];
  list.erase(std::find(list.begin(), list.end(), f));
}

Index TriEditMesh::SplitEdge(Index a, Index b, const Vec3& p) {
  const Index f1 = DirectedEdgeFace(a, b), f2 = DirectedEdgeFace(b, a);
  const bool boundary = f1 == kInvalidIndex || f2 == kInvalidIndex;
  const Index m = num_vertex_slots();
  position_.push_back(p);
  vfaces_.emplace_back();
  alive_v_.push_back(1);
  ++live_vertices_;
  loop.push_back(boundary ? loop[static_cast<std::size_t>(a)] : -1);
  size.push_back(0.5 * (size[static_cast<std::size_t>(a)] + size[static_cast<std::size_t>(b)]));
  feature.push_back(-1);
  auto split = [&](Index f, Index x, Index y) {  // f holds x -> y
    if (f == kInvalidIndex) return;
    const Index c = Opposite(f, x, y);
    std::array<Index, 3>& t = face_[static_cast<std::size_t>(f)];
    t[static_cast<std::size_t>(Slot(t, y))] = m;  // (x, m, c)
    RemoveFaceFrom(y, f);
    vfaces_[static_cast<std::size_t>(m)].push_back(f);
    const Index g = num_face_slots();
    face_.push_back({m, y, c});
    alive_f_.push_back(1);
    ++live_faces_;
    for (Index v : {m, y, c}) vfaces_[static_cast<std::size_t>(v)].push_back(g);
  };
  split(f1, a, b);
  split(f2, b, a);
  return m;
}

bool TriEditMesh::CanCollapse(Index from, Index to) const {
  if (from == to || !vertex_alive(from) || !vertex_alive(to)) return false;
  std::vector<Index> shared, opposite;
  for (Index f : vertex_faces(from)) {
    if (Slot(face(f), to) >= 0) {
      shared.push_back(f);
      opposite.push_back(Opposite(f, from, to));
    }
  }
  if (shared.empty()) return false;
  const bool boundary_edge = shared.size() == 1;
  const bool from_boundary = IsBoundaryVertex(from), to_boundary = IsBoundaryVertex(to);
  // An interior edge between two boundary vertices would pinch the surface.
  if (from_boundary && to_boundary && !boundary_edge) return false;
  // Link condition.
  std::vector<Index> nf, nt, common;
  Neighbors(from, &nf);
  Neighbors(to, &nt);
  std::set_intersection(nf.begin(), nf.end(), nt.begin(), nt.end(), std::back_inserter(common));
  std::vector<Index> opp = opposite;
  std::sort(opp.begin(), opp.end());
  if (common != opp) return false;
  for (std::size_t i = 0; i < shared.size(); ++i) {
    const Index o = opposite[i];
    // A triangle whose other two edges are both boundary would be left dangling.
    if (IsBoundaryEdge(from, o) && IsBoundaryEdge(to, o)) return false;
    if (Valence(o) - 1 < (IsBoundaryVertex(o) ? 2 : 3)) return false;
  }
  const int merged = static_cast<int>(nf.size() + nt.size() - common.size()) - 2;
  if (merged < ((from_boundary || to_boundary) ? 2 : 3)) return false;
  if (boundary_edge && BoundaryLoopLength(from) <= 3) return false;
  return true;
}

void TriEditMesh::Collapse(Index from, Index to) {
  const std::vector<Index> faces = vertex_faces(from);
  for (Index f : faces) {
    std::array<Index, 3>& t = face_[static_cast<std::size_t>(f)];
    if (Slot(t, to) >= 0) {
      for (Index v : t) {
        if (v != from) RemoveFaceFrom(v, f);
      }
      alive_f_[static_cast<std::size_t>(f)] = 0;
      --live_faces_;
    } else {
      t[static_cast<std::size_t>(Slot(t, from))] = to;
      vfaces_[static_cast<std::size_t>(to)].push_back(f);
    }
  }
  vfaces_[static_cast<std::size_t>(from)].clear();
  alive_v_[static_cast<std::size_t>(from)] = 0;
  --live_vertices_;
}

bool TriEditMesh::CanFlip(Index a, Index b) const {
  const Index f1 = DirectedEdgeFace(a, b), f2 = DirectedEdgeFace(b, a);
  if (f1 == kInvalidIndex || f2 == kInvalidIndex) return false;
  const Index c = Opposite(f1, a, b), d = Opposite(f2, a, b);
  if (c == d || HasEdge(c, d)) return false;
  if (Valence(a) - 1 < (IsBoundaryVertex(a) ? 2 : 3)) return false;
  if (Valence(b) - 1 < (IsBoundaryVertex(b) ? 2 : 3)) return false;
  return true;
}

void TriEditMesh::Flip(Index a, Index b) {
  const Index f1 = DirectedEdgeFace(a, b), f2 = DirectedEdgeFace(b, a);
  const Index c = Opposite(f1, a, b), d = Opposite(f2, a, b);
  face_[static_cast<std::size_t>(f1)] = {a, d, c};
  face_[static_cast<std::size_t>(f2)] = {d, b, c};
  RemoveFaceFrom(b, f1);
  vfaces_[static_cast<std::size_t>(d)].push_back(f1);
  RemoveFaceFrom(a, f2);
  vfaces_[static_cast<std::size_t>(c)].push_back(f2);
}

void TriEditMesh::Compact(std::vector<Index>* old_to_new) {
  std::vector<Index> map(position_.size(), kInvalidIndex);
  Index n = 0;
  for (std::size_t v = 0; v < position_.size(); ++v) {
    if (alive_v_[v]) map[v] = n++;
  }
  std::vector<Vec3> pos(static_cast<std::size_t>(n));
  std::vector<int> lp(static_cast<std::size_t>(n));
  std::vector<double> sz(static_cast<std::size_t>(n));
  std::vector<int> ft(static_cast<std::size_t>(n));
  for (std::size_t v = 0; v < position_.size(); ++v) {
    if (map[v] == kInvalidIndex) continue;
    const std::size_t w = static_cast<std::size_t>(map[v]);
    pos[w] = position_[v], lp[w] = loop[v], sz[w] = size[v], ft[w] = feature[v];
  }
  std::vector<std::uint32_t> tris;
  for (std::size_t f = 0; f < face_.size(); ++f) {
    if (!alive_f_[f]) continue;
    for (Index v : face_[f])
      tris.push_back(static_cast<std::uint32_t>(map[static_cast<std::size_t>(v)]));
  }
  Init(std::move(pos), tris);
  loop = std::move(lp);
  size = std::move(sz);
  feature = std::move(ft);
  if (old_to_new) *old_to_new = std::move(map);
}

void TriEditMesh::Export(std::vector<Vec3>* positions,
                         std::vector<std::uint32_t>* triangles) const {
  *positions = position_;
  triangles->clear();
  for (std::size_t f = 0; f < face_.size(); ++f) {
    if (!alive_f_[f]) continue;
    for (Index v : face_[f]) triangles->push_back(static_cast<std::uint32_t>(v));
  }
}

}  // namespace remesh_detail
}  // namespace dermis
