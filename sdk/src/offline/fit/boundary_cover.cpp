// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The domain surface's boundary curve (Yoon Eq. 4 with d = 0 on the control mesh's boundary
// edges) pushed out to cover the data's boundary vertices (docs/fitting.md, "Covering the
// data's boundary"). The closest point of the curve comes from a TriangleDistanceTree over the
// curve sampled 16 times per edge (degenerate triangles (a, b, b), one per segment), refined by
// golden sections on the surface itself.
#include "dermis/offline/fit/boundary_cover.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "dermis/core/parallel.h"
#include "dermis/offline/fit/surface_projection.h"
#include "dermis/offline/geometry/polygon_mesh.h"
#include "dermis/offline/geometry/triangle_distance.h"
#include "dermis/surface/chart.h"
#include "dermis/surface/local_patch.h"
#include "dermis/surface/manifold_domain.h"
#include "dermis/surface/surface_evaluator.h"

namespace dermis {
namespace {

// Samples per boundary edge of the curve the data boundary vertices search first.
constexpr int kSearchSamples = 16;

bool Finite(const Vec3& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

// The domain surface at parameter t of boundary half-edge h; false if it cannot be evaluated.
// The half-edge runs from corner e of its face to corner e + 1 (e = h - face offset), which is
// corner e's first axis: face point CornerToFace(e, (t, 0)).
bool CurvePoint(const ManifoldDomain& domain, const LocalPatch* patches, Index h, double t,
                SurfacePoint* out) {
  const MeshTopology& topo = domain.topology();
  const Index f = topo.halfedge_face(h);
  return EvaluateSurface(domain, patches, nullptr, f,
                         CornerToFace(static_cast<int>(h - topo.face_offset(f)), Vec2(t, 0.0)),
                         out) &&
         Finite(out->position);
}

}  // namespace

std::vector<std::pair<Vec3, Vec3>> BoundaryEdges(const PolygonMesh& mesh,
                                                 std::vector<Index>* first) {
  const Index nv = mesh.num_vertices();
  // Directed edges in face order, and their undirected keys sorted: an edge is a boundary edge
  // when its undirected key occurs once (it appears once, its reverse never).
  std::vector<std::array<Index, 2>> directed;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keys;
  for (Index f = 0; f < mesh.num_faces(); ++f) {
    const Index b = mesh.face_offsets[static_cast<std::size_t>(f)], n = mesh.face_size(f);
    for (Index k = 0; k < n; ++k) {
      const Index a = mesh.face_vertices[static_cast<std::size_t>(b + k)];
      const Index c = mesh.face_vertices[static_cast<std::size_t>(b + (k + 1) % n)];
      if (a < 0 || a >= nv || c < 0 || c >= nv || a == c) continue;
      const std::uint64_t lo = static_cast<std::uint64_t>(std::min(a, c));
      const std::uint64_t hi = static_cast<std::uint64_t>(std::max(a, c));
      keys.emplace_back((lo << 32) | hi, static_cast<std::uint32_t>(directed.size()));
      directed.push_back({a, c});
    }
  }
  std::sort(keys.begin(), keys.end());
  std::vector<std::uint32_t> once;
  for (std::size_t i = 0; i < keys.size();) {
    std::size_t j = i + 1;
    while (j < keys.size() && keys[j].first == keys[i].first) ++j;
    if (j == i + 1) once.push_back(keys[i].second);
    i = j;
  }
  std::sort(once.begin(), once.end());
  std::vector<std::pair<Vec3, Vec3>> out;
  out.reserve(once.size());
  if (first) first->clear();
  for (std::uint32_t e : once) {
    if (first) first->push_back(directed[e][0]);
    out.emplace_back(mesh.positions[static_cast<std::size_t>(directed[e][0])],
                     mesh.positions[static_cast<std::size_t>(directed[e][1])]);
  }
  return out;
}

BoundaryCoverReport CoverDataBoundary(const ManifoldDomain& domain,
                                      const std::vector<std::pair<Vec3, Vec3>>& edges,
                                      const BoundaryCoverOptions& options,
                                      std::vector<Vec3>* positions) {
  BoundaryCoverReport report;
  const MeshTopology& topo = domain.topology();
  const Index nv = domain.num_vertices();
  if (static_cast<Index>(positions->size()) != nv || edges.empty()) return report;
  // The boundary half-edges (the domain is all quads), and each boundary vertex's outgoing and
  // incoming one.
  std::vector<Index> boundary;
  std::vector<Index> outgoing(static_cast<std::size_t>(nv), kInvalidIndex);
  std::vector<Index> incoming(static_cast<std::size_t>(nv), kInvalidIndex);
  for (Index h = 0; h < topo.num_halfedges(); ++h) {
    if (topo.twin(h) != kInvalidIndex) continue;
    boundary.push_back(h);
    outgoing[static_cast<std::size_t>(topo.halfedge_origin(h))] = h;
    incoming[static_cast<std::size_t>(topo.halfedge_dest(h))] = h;
  }
  if (boundary.empty()) return report;
  const int threads = ResolveThreadCount(options.threads);
  std::vector<LocalPatch> patches(static_cast<std::size_t>(nv));
  domain.FitPatches(positions->data(), patches.data());
  // The curve, sampled; each edge's chord.
  constexpr int ks = kSearchSamples;
  const std::size_t nb = boundary.size();
  std::vector<Vec3> curve(nb * (ks + 1));
  std::vector<char> curve_ok(curve.size(), 0);
  ParallelFor(threads, nb, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      for (int k = 0; k <= ks; ++k) {
        SurfacePoint sp;
        const std::size_t s = i * (ks + 1) + static_cast<std::size_t>(k);
        curve_ok[s] =
            CurvePoint(domain, patches.data(), boundary[i], static_cast<double>(k) / ks, &sp);
        curve[s] = sp.position;
      }
    }
  });
  std::vector<double> reach(nb, 0.0);
  std::vector<Vec3> seg_positions;
  std::vector<std::uint32_t> seg_triangles;
  std::vector<std::size_t> seg_code;  // segment -> boundary edge i and sample k: i ks + k
  for (std::size_t i = 0; i < nb; ++i) {
    const std::size_t s = i * (ks + 1);
    if (curve_ok[s] && curve_ok[s + ks]) {
      reach[i] = options.max_distance_edges * glm::length(curve[s + ks] - curve[s]);
    }
    for (int k = 0; k < ks; ++k) {
      const std::size_t a = s + static_cast<std::size_t>(k);
      if (!curve_ok[a] || !curve_ok[a + 1]) continue;
      const std::uint32_t first = static_cast<std::uint32_t>(seg_positions.size());
      seg_positions.push_back(curve[a]);
      seg_positions.push_back(curve[a + 1]);
      seg_triangles.insert(seg_triangles.end(), {first, first + 1, first + 1});
      seg_code.push_back(i * ks + static_cast<std::size_t>(k));
    }
  }
  TriangleDistanceTree tree;
  if (seg_code.empty() || !tree.Build(seg_positions, seg_triangles)) return report;
  // Each data boundary vertex: its excess beyond the curve, and where on the curve.
  const std::size_t nd = edges.size();
  std::vector<double> excess(nd, 0.0), at(nd, 0.0);
  std::vector<std::size_t> edge_of(nd, 0);
  ParallelFor(threads, nd, [&](std::size_t b, std::size_t e) {
    for (std::size_t j = b; j < e; ++j) {
      const Vec3& p = edges[j].first;
      if (!Finite(p)) continue;
      const ClosestPoint c = tree.Query(p);
      if (c.triangle == kInvalidIndex) continue;
      const std::size_t code = seg_code[static_cast<std::size_t>(c.triangle)];
      const std::size_t i = code / ks;
      const int k = static_cast<int>(code % ks);
      if (!(c.distance <= reach[i])) continue;
      const Index h = boundary[i];
      // Golden sections over the closest segment and its two neighbours.
      double t = 0.0;
      ClosestPointOnBoundaryEdge(domain, patches.data(), nullptr, p, h,
                                 std::max(0.0, (k - 1.0) / ks), std::min(1.0, (k + 2.0) / ks), &t);
      SurfacePoint sp, ahead, behind;
      const double step = 1e-4;
      if (!CurvePoint(domain, patches.data(), h, t, &sp) ||
          !CurvePoint(domain, patches.data(), h, std::min(1.0, t + step), &ahead) ||
          !CurvePoint(domain, patches.data(), h, std::max(0.0, t - step), &behind)) {
        continue;
      }
      // The face lies to the left of its half-edge (counter-clockwise about the normal), so
      // outward along the surface is (curve direction) x normal.
      Vec3 out = glm::cross(ahead.position - behind.position, sp.normal);
      const double len2 = glm::dot(out, out);
      if (!(len2 > 0.0) || !std::isfinite(len2)) continue;
      excess[j] = glm::dot(p - sp.position, out) / std::sqrt(len2);
      at[j] = t;
      edge_of[j] = i;
    }
  });
  // Each boundary vertex is asked for the largest share of an excess beside it.
  std::vector<double> push(static_cast<std::size_t>(nv), 0.0);
  for (std::size_t j = 0; j < nd; ++j) {
    if (!(excess[j] > options.tolerance)) continue;
    ++report.data_vertices_beyond;
    report.largest_excess = std::max(report.largest_excess, excess[j]);
    const Index h = boundary[edge_of[j]];
    const std::size_t a = static_cast<std::size_t>(topo.halfedge_origin(h));
    const std::size_t b = static_cast<std::size_t>(topo.halfedge_dest(h));
    push[a] = std::max(push[a], excess[j] * std::min(1.0, 2.0 * (1.0 - at[j])));
    push[b] = std::max(push[b], excess[j] * std::min(1.0, 2.0 * at[j]));
  }
  std::vector<Vec3> moved = *positions;
  for (Index v = 0; v < nv; ++v) {
    const std::size_t sv = static_cast<std::size_t>(v);
    if (!(push[sv] > 0.0) || outgoing[sv] == kInvalidIndex || incoming[sv] == kInvalidIndex) {
      continue;
    }
    const Vec3& next = (*positions)[static_cast<std::size_t>(topo.halfedge_dest(outgoing[sv]))];
    const Vec3& prev = (*positions)[static_cast<std::size_t>(topo.halfedge_origin(incoming[sv]))];
    const Vec3& x = (*positions)[sv];
    Vec3 out = glm::cross(next - prev, patches[sv].fallback_normal);
    const double len2 = glm::dot(out, out);
    if (!(len2 > 0.0) || !std::isfinite(len2)) continue;
    const double cap =
        options.max_move_edges * 0.5 * (glm::length(next - x) + glm::length(x - prev));
    if (!std::isfinite(cap)) continue;
    moved[sv] = x + (std::min(push[sv], cap) / std::sqrt(len2)) * out;
    ++report.vertices_moved;
  }
  *positions = std::move(moved);
  return report;
}

}  // namespace dermis
