// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The automatic control mesh as a quad remesh (docs/fitting.md, "Control mesh"; Yoon section 4
// used a commercial remesher): a meshoptimizer seed, adaptive isotropic remeshing (Botsch &
// Kobbelt 2004) at the triangle count whose final split meets the target, Blossom-Quad pairing
// (Remacle et al. 2012), one Catmull-Clark style split and relaxation on the input surface.
#include "dermis/offline/build/quad_remesh.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <limits>
#include <numeric>

#include "dermis/core/mesh_topology.h"
#include "dermis/offline/build/crease_chains.h"
#include "dermis/offline/build/reference_surface.h"
#include "dermis/offline/geometry/quadrangulate.h"
#include "dermis/offline/geometry/triangle_distance.h"
#include "union_find.h"

namespace dermis {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Vertices of the all-quad mesh one split of `poly` gives: V + E + F.
int SplitCount(const PolygonMesh& poly) {
  std::vector<std::array<Index, 2>> edges;
  for (Index f = 0; f < poly.num_faces(); ++f) {
    const Index b = poly.face_offsets[static_cast<std::size_t>(f)], s = poly.face_size(f);
    for (Index k = 0; k < s; ++k) {
      const Index a = poly.face_vertices[static_cast<std::size_t>(b + k)];
      const Index c = poly.face_vertices[static_cast<std::size_t>(b + (k + 1) % s)];
      edges.push_back({std::min(a, c), std::max(a, c)});
    }
  }
  std::sort(edges.begin(), edges.end());
  const std::size_t e =
      static_cast<std::size_t>(std::unique(edges.begin(), edges.end()) - edges.begin());
  return poly.num_vertices() + static_cast<int>(e) + poly.num_faces();
}

// The seed: the input simplified to about `target` triangles with its borders locked, compacted
// in first-use order; empty if it does not keep the input's components and loops.
bool MakeSeed(const ReferenceSurface& ref, const std::vector<std::uint32_t>& triangles,
              std::size_t target, RemeshTriangles* seed, std::vector<Index>* seed_of = nullptr) {
  const std::vector<Vec3>& x = ref.positions();
  std::vector<std::uint32_t> simplified = triangles;
  if (target < triangles.size() / 3) {
    std::vector<float> xyz(3 * x.size());
    for (std::size_t v = 0; v < x.size(); ++v) {
      for (int c = 0; c < 3; ++c)
        xyz[3 * v + static_cast<std::size_t>(c)] = static_cast<float>(x[v][c]);
    }
    std::vector<std::uint32_t> out(triangles.size());
    const std::size_t n =
        meshopt_simplify(out.data(), triangles.data(), triangles.size(), xyz.data(), x.size(),
                         3 * sizeof(float), 3 * target, 1.0f, meshopt_SimplifyLockBorder, nullptr);
    out.resize(n);
    simplified.swap(out);
  }
  if (simplified.empty()) return false;
  std::vector<Index> map(x.size(), kInvalidIndex);
  RemeshTriangles s;
  for (std::uint32_t& v : simplified) {
    if (map[v] == kInvalidIndex) {
      map[v] = static_cast<Index>(s.positions.size());
      s.positions.push_back(x[v]);
      s.loop.push_back(ref.vertex_loop(static_cast<Index>(v)));
    }
    v = static_cast<std::uint32_t>(map[v]);
  }
  s.triangles = std::move(simplified);
  ReferenceSurface check;
  if (!check.Build(s.positions, s.triangles, "seed").ok()) return false;
  if (check.num_components() != ref.num_components() || check.num_loops() != ref.num_loops()) {
    return false;
  }
  *seed = std::move(s);
  if (seed_of) *seed_of = std::move(map);
  return true;
}

// Tags the seed (the input renumbered by `seed_of`) with the creases: each vertex's feature and
// the crease edges.
void TagCreases(const CreaseChains& creases, const std::vector<Index>& seed_of,
                RemeshTriangles* seed) {
  seed->feature.assign(seed->positions.size(), kNoFeature);
  for (std::size_t v = 0; v < seed_of.size(); ++v) {
    if (seed_of[v] != kInvalidIndex) {
      seed->feature[static_cast<std::size_t>(seed_of[v])] =
          creases.vertex_feature(static_cast<Index>(v));
    }
  }
  seed->crease_edges.clear();
  for (std::size_t e = 0; e < creases.edges().size(); ++e) {
    const Index a = seed_of[creases.edges()[e][0]], b = seed_of[creases.edges()[e][1]];
    if (a == kInvalidIndex || b == kInvalidIndex) continue;
    seed->crease_edges.push_back({static_cast<std::uint32_t>(std::min(a, b)),
                                  static_cast<std::uint32_t>(std::max(a, b)),
                                  static_cast<std::uint32_t>(creases.edge_chain()[e])});
  }
  std::sort(seed->crease_edges.begin(), seed->crease_edges.end());
}

// The crease edges as sorted (a, b) pairs.
std::vector<std::array<std::uint32_t, 2>> KeepEdges(const RemeshTriangles& mesh) {
  std::vector<std::array<std::uint32_t, 2>> keep;
  for (const auto& e : mesh.crease_edges) keep.push_back({e[0], e[1]});
  std::sort(keep.begin(), keep.end());
  return keep;
}

// Edge loops inserted into a quad-dominant mesh (quads and triangles) where it is much coarser
// than the remesh would be, and its triangles made quads: the edges fall into classes (the
// rungs of a quad strip: a quad's opposite edges; a triangle's three edges), and a class whose
// longest edge is more than `factor` times the remesh's control edge there (half the sizing
// field's triangle edge; factor <= 0: never) splits every one of its edges into k equal parts,
// k the smallest count that brings it within; a class with a triangle's edges splits into an
// even k >= 2. Each quad becomes the grid its two classes give; each triangle three quads
// (corner, edge midpoint, centre, edge midpoint), each a grid of k/2 x k/2. New points on the
// edges stay on them (the input's edges lie on its surface); the others are Coons points of
// their patch's sides projected onto the surface. New vertices inside quads have valence 4,
// triangle centres 3. *crease_edges counts the control edges on `crease_edges_in` (pairs of
// the mesh's vertex indices, a < b, sorted). False on a face that is neither a quad nor a
// triangle, or a mesh the topology refuses.
bool InsertEdgeLoops(const ReferenceSurface& ref, const SizingField& sizing,
                     const std::vector<std::array<std::uint32_t, 2>>& crease_edges_in,
                     double factor, PolygonMesh* mesh, int* crease_edges) {
  MeshTopology topo;
  if (!MeshTopology::Build(mesh->num_vertices(), mesh->face_offsets, mesh->face_vertices, &topo)
           .ok()) {
    return false;
  }
  const Index ne = topo.num_edges(), nf = topo.num_faces();
  for (Index f = 0; f < nf; ++f) {
    if (topo.face_size(f) != 3 && topo.face_size(f) != 4) return false;
  }
  const std::vector<Vec3>& x = mesh->positions;
  UnionFind classes(ne);
  auto find = [&](Index e) { return classes.Find(e); };
  auto unite = [&](Index a, Index b) { classes.Unite(a, b); };
  for (Index f = 0; f < nf; ++f) {
    const Index h = topo.face_offset(f);
    if (topo.face_size(f) == 4) {
      unite(topo.halfedge_edge(h), topo.halfedge_edge(h + 2));
      unite(topo.halfedge_edge(h + 1), topo.halfedge_edge(h + 3));
    } else {
      unite(topo.halfedge_edge(h), topo.halfedge_edge(h + 1));
      unite(topo.halfedge_edge(h), topo.halfedge_edge(h + 2));
    }
  }
  // Parts per class: the largest over its edges of ceil(length / (factor x local control
  // edge)); even and at least 2 where the class has a triangle's edges.
  std::vector<int> parts(static_cast<std::size_t>(ne), 1);
  std::vector<char> even(static_cast<std::size_t>(ne), 0);
  for (Index f = 0; f < nf; ++f) {
    if (topo.face_size(f) == 3)
      even[static_cast<std::size_t>(find(topo.halfedge_edge(topo.face_offset(f))))] = 1;
  }
  for (Index e = 0; e < ne; ++e) {
    if (!(factor > 0.0)) break;
    const Index h = topo.edge_halfedge(e);
    const Vec3 &a = x[static_cast<std::size_t>(topo.halfedge_origin(h))],
               &b = x[static_cast<std::size_t>(topo.halfedge_dest(h))];
    const double cap = factor * 0.5 * sizing.At(0.5 * (a + b), Vec3(0.0));
    if (!(cap > 0.0)) continue;
    const double k = std::ceil(glm::length(b - a) / cap - 1e-9);
    int& p = parts[static_cast<std::size_t>(find(e))];
    if (k > p) p = static_cast<int>(std::min(k, 64.0));
  }
  for (Index e = 0; e < ne; ++e) {
    if (find(e) != e || !even[static_cast<std::size_t>(e)]) continue;
    int& p = parts[static_cast<std::size_t>(e)];
    p = std::max(2, p + (p % 2));
  }
  auto k_of = [&](Index e) { return parts[static_cast<std::size_t>(find(e))]; };
  // New vertices: (k - 1) per edge, from its canonical half-edge's origin.
  std::vector<Index> edge_base(static_cast<std::size_t>(ne), kInvalidIndex);
  std::vector<Vec3> pos = x;
  *crease_edges = 0;
  for (Index e = 0; e < ne; ++e) {
    const int k = k_of(e);
    const Index h = topo.edge_halfedge(e);
    const Index a = topo.halfedge_origin(h), b = topo.halfedge_dest(h);
    if (std::binary_search(
            crease_edges_in.begin(), crease_edges_in.end(),
            std::array<std::uint32_t, 2>{static_cast<std::uint32_t>(std::min(a, b)),
                                         static_cast<std::uint32_t>(std::max(a, b))})) {
      *crease_edges += k;
    }
    if (k == 1) continue;
    edge_base[static_cast<std::size_t>(e)] = static_cast<Index>(pos.size());
    for (int i = 1; i < k; ++i) {
      const double t = static_cast<double>(i) / k;
      pos.push_back((1.0 - t) * x[static_cast<std::size_t>(a)] +
                    t * x[static_cast<std::size_t>(b)]);
    }
  }
  // The k + 1 points along half-edge h, from its origin to its destination.
  auto side = [&](Index h) {
    const int k = k_of(topo.halfedge_edge(h));
    std::vector<Index> out(static_cast<std::size_t>(k) + 1);
    const Index e = topo.halfedge_edge(h);
    const Index base = edge_base[static_cast<std::size_t>(e)];
    const bool forward = topo.edge_halfedge(e) == h;
    out.front() = topo.halfedge_origin(h);
    out.back() = topo.halfedge_dest(h);
    for (int i = 1; i < k; ++i)
      out[static_cast<std::size_t>(i)] = forward ? base + i - 1 : base + (k - i) - 1;
    return out;
  };
  auto project = [&](const Vec3& p, const Vec3& normal) {
    return ref.Project(p, normal, sizing.At(p, normal)).point;
  };
  PolygonMesh out;
  out.source_name = mesh->source_name;
  // A grid patch from its four sides, counter-clockwise from its first corner: bottom
  // (nu + 1 points, left to right), right (nv + 1, bottom to top), top (nu + 1, right to left),
  // left (nv + 1, top to bottom). Interior points: Coons, projected onto the surface.
  auto patch = [&](const std::vector<Index>& bottom, const std::vector<Index>& right,
                   const std::vector<Index>& top, const std::vector<Index>& left) {
    const int nu = static_cast<int>(bottom.size()) - 1, nv = static_cast<int>(right.size()) - 1;
    std::vector<Index> grid(static_cast<std::size_t>((nu + 1) * (nv + 1)));
    auto at = [&](int i, int j) -> Index& {
      return grid[static_cast<std::size_t>(j * (nu + 1) + i)];
    };
    for (int i = 0; i <= nu; ++i) {
      at(i, 0) = bottom[static_cast<std::size_t>(i)];
      at(nu - i, nv) = top[static_cast<std::size_t>(i)];
    }
    for (int j = 0; j <= nv; ++j) {
      at(nu, j) = right[static_cast<std::size_t>(j)];
      at(0, nv - j) = left[static_cast<std::size_t>(j)];
    }
    const Vec3 c00 = pos[static_cast<std::size_t>(at(0, 0))],
               c10 = pos[static_cast<std::size_t>(at(nu, 0))],
               c11 = pos[static_cast<std::size_t>(at(nu, nv))],
               c01 = pos[static_cast<std::size_t>(at(0, nv))];
    const Vec3 normal = glm::cross(c11 - c00, c01 - c10);
    for (int j = 1; j < nv; ++j) {
      for (int i = 1; i < nu; ++i) {
        const double u = static_cast<double>(i) / nu, v = static_cast<double>(j) / nv;
        const Vec3 b = pos[static_cast<std::size_t>(at(i, 0))],
                   t = pos[static_cast<std::size_t>(at(i, nv))],
                   l = pos[static_cast<std::size_t>(at(0, j))],
                   r = pos[static_cast<std::size_t>(at(nu, j))];
        const Vec3 p =
            (1 - v) * b + v * t + (1 - u) * l + u * r -
            ((1 - u) * (1 - v) * c00 + u * (1 - v) * c10 + u * v * c11 + (1 - u) * v * c01);
        at(i, j) = static_cast<Index>(pos.size());
        pos.push_back(project(p, normal));
      }
    }
    for (int j = 0; j < nv; ++j) {
      for (int i = 0; i < nu; ++i) {
        out.AddFace({at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
      }
    }
  };
  auto reversed = [](std::vector<Index> v) {
    std::reverse(v.begin(), v.end());
    return v;
  };
  for (Index f = 0; f < nf; ++f) {
    const Index h0 = topo.face_offset(f);
    if (topo.face_size(f) == 4) {
      patch(side(h0), side(h0 + 1), side(h0 + 2), side(h0 + 3));
      continue;
    }
    // A triangle: its centre and a spoke from each edge's midpoint to it (m = k / 2 segments).
    const int m = k_of(topo.halfedge_edge(h0)) / 2;
    std::array<std::vector<Index>, 3> sides, spokes;
    Vec3 centre(0.0);
    for (int c = 0; c < 3; ++c) {
      sides[static_cast<std::size_t>(c)] = side(h0 + c);
      centre += pos[static_cast<std::size_t>(topo.halfedge_origin(h0 + c))] / 3.0;
    }
    const Vec3 &a = pos[static_cast<std::size_t>(topo.halfedge_origin(h0))],
               &b = pos[static_cast<std::size_t>(topo.halfedge_origin(h0 + 1))],
               &c = pos[static_cast<std::size_t>(topo.halfedge_origin(h0 + 2))];
    const Vec3 normal = glm::cross(b - a, c - a);
    const Index g = static_cast<Index>(pos.size());
    pos.push_back(project(centre, normal));
    for (int e = 0; e < 3; ++e) {
      std::vector<Index>& sp = spokes[static_cast<std::size_t>(e)];
      const Index mid = sides[static_cast<std::size_t>(e)][static_cast<std::size_t>(m)];
      sp.push_back(mid);
      for (int i = 1; i < m; ++i) {
        const double t = static_cast<double>(i) / m;
        sp.push_back(static_cast<Index>(pos.size()));
        pos.push_back(project(
            (1 - t) * pos[static_cast<std::size_t>(mid)] + t * pos[static_cast<std::size_t>(g)],
            normal));
      }
      sp.push_back(g);
    }
    // Corner c: (corner, midpoint of side c, centre, midpoint of side c - 1).
    for (int cc = 0; cc < 3; ++cc) {
      const std::vector<Index>& s_in = sides[static_cast<std::size_t>(cc)];
      const std::vector<Index>& s_prev = sides[static_cast<std::size_t>((cc + 2) % 3)];
      std::vector<Index> bottom(s_in.begin(), s_in.begin() + m + 1);
      std::vector<Index> left(s_prev.begin() + m, s_prev.end());
      patch(bottom, spokes[static_cast<std::size_t>(cc)],
            reversed(spokes[static_cast<std::size_t>((cc + 2) % 3)]), left);
    }
  }
  out.positions = std::move(pos);
  *mesh = std::move(out);
  return true;
}

// Step 6 of QuadRemesh(): the input's triangles paired back into quads (its crease edges never a
// diagonal), compacted to the vertices they use, with edge loops and its leftover triangles made
// quads (InsertEdgeLoops; closer loops where the input's quads are coarser than `remesh`).
// True, with *own and *report (the remesh's report with the quad measures replaced), where the
// result is a valid mesh with the input's components and loops, at least as regular as `remesh`
// (share of valence-4 interior vertices) with no higher valence, and has between 1 and
// input_quads_max_ratio times its vertices.
bool InputQuads(const std::vector<Vec3>& positions, const std::vector<std::uint32_t>& triangles,
                const ReferenceSurface& ref, const SizingField& sizing, const CreaseChains& creases,
                const QuadRemeshOptions& options, const PolygonMesh& remesh, PolygonMesh* own,
                QuadRemeshReport* report) {
  QuadPairingStats stats;
  const std::vector<std::array<std::uint32_t, 2>>& keep = creases.edges();
  if (!PairTrianglesIntoQuads(positions, triangles, options.pairing, own, &stats,
                              keep.empty() ? nullptr : &keep)
           .ok()) {
    return false;
  }
  // The crease edges in the compacted mesh's vertex indices.
  std::vector<Index> old_to_new;
  CompactUnusedVertices(own, &old_to_new);
  std::vector<std::array<std::uint32_t, 2>> crease_edges;
  for (const auto& e : keep) {
    const Index a = old_to_new[e[0]], b = old_to_new[e[1]];
    if (a == kInvalidIndex || b == kInvalidIndex) continue;
    crease_edges.push_back(
        {static_cast<std::uint32_t>(std::min(a, b)), static_cast<std::uint32_t>(std::max(a, b))});
  }
  std::sort(crease_edges.begin(), crease_edges.end());
  int crease_control_edges = 0;
  const PolygonMesh paired = *own;
  if (!InsertEdgeLoops(ref, sizing, crease_edges, options.input_quads_edge_factor, own,
                       &crease_control_edges)) {
    return false;
  }
  const double n_remesh = static_cast<double>(remesh.positions.size());
  // Quads coarser than the remesh (a box-modelled figure, whose long limb spans are one quad
  // across): the loops come closer, down to a tenth of the factor, at the largest factor whose
  // mesh has at least the remesh's vertices (to a thousandth of the factor: the count only grows
  // as the factor falls), so every strip gets rows across as well as rings along.
  if (static_cast<double>(own->positions.size()) < n_remesh &&
      options.input_quads_edge_factor > 0.0) {
    auto loops = [&](double f, PolygonMesh* mesh, int* crease_count) {
      *mesh = paired;
      return InsertEdgeLoops(ref, sizing, crease_edges, f, mesh, crease_count);
    };
    // Down in steps of 0.8 to the first factor that reaches the count (no trial is more than
    // one step past the factor the count asks for, where the densest loops could be many times
    // the count), then bisection between it and the step before.
    const double factor = options.input_quads_edge_factor;
    double hi = factor, lo = factor;
    PolygonMesh dense;
    int dense_creases = 0;
    bool reached = false;
    while (!reached && lo > 0.1 * factor) {
      hi = lo;
      lo = std::max(0.1 * factor, 0.8 * lo);
      if (!loops(lo, &dense, &dense_creases)) return false;
      reached = static_cast<double>(dense.positions.size()) >= n_remesh;
    }
    if (reached) {
      while (hi - lo > 1e-3 * factor) {
        const double mid = 0.5 * (lo + hi);
        PolygonMesh trial;
        int trial_creases = 0;
        if (!loops(mid, &trial, &trial_creases)) return false;
        if (static_cast<double>(trial.positions.size()) >= n_remesh) {
          lo = mid;
          dense = std::move(trial);
          dense_creases = trial_creases;
        } else {
          hi = mid;
        }
      }
      *own = std::move(dense);
      crease_control_edges = dense_creases;
    }
  }
  const double n_own = static_cast<double>(own->positions.size());
  if (n_own < n_remesh || n_own > options.input_quads_max_ratio * n_remesh) return false;
  if (!ValidatePolygonMesh(*own).ok()) return false;
  QuadRemeshReport r = *report;
  MeasureQuadMesh(*own, &r);
  if (r.components != report->components || r.boundary_loops != report->boundary_loops ||
      r.valence4_share < report->valence4_share || r.max_valence > report->max_valence) {
    return false;
  }
  r.input_quads = true;
  r.remesh_vertices = report->vertices;
  r.seed_vertices = 0;
  r.triangle_vertices = static_cast<int>(own->positions.size());
  r.quads_paired = stats.quads;
  r.triangles_unpaired = stats.triangles;
  r.relax_rejected = 0;
  // Every crease edge of the input is an edge of its own quads.
  r.crease_edges_kept = r.crease_edges;
  r.control_crease_edges = crease_control_edges;
  own->source_name = remesh.source_name;
  *report = r;
  return true;
}

// Two-sided distance between the input and a triangle mesh on it, relative to the local
// target edge length: input vertices and triangle centroids to the mesh, the mesh's triangle
// centroids and edge midpoints to the input. Rounding a crease costs a fraction of an edge; a
// part the mesh lost (a leg, a tail) costs many.
double Deviation(const ReferenceSurface& ref, const SizingField& sizing,
                 const RemeshTriangles& mesh) {
  TriangleDistanceTree tree;
  tree.Build(mesh.positions, mesh.triangles);
  const std::vector<Vec3>& x = ref.positions();
  const std::vector<std::uint32_t>& t = ref.triangles();
  double d = 0.0;
  for (std::size_t i = 0; i < t.size(); i += 3) {
    const Vec3& n = ref.triangle_normal(static_cast<Index>(i / 3));
    const Vec3 c = (x[t[i]] + x[t[i + 1]] + x[t[i + 2]]) / 3.0;
    d = std::max(d, tree.Query(x[t[i]]).distance / sizing.At(x[t[i]], n));
    d = std::max(d, tree.Query(c).distance / sizing.At(c, n));
  }
  const std::vector<Vec3>& y = mesh.positions;
  const std::vector<std::uint32_t>& u = mesh.triangles;
  for (std::size_t i = 0; i < u.size(); i += 3) {
    const Vec3 n = glm::cross(y[u[i + 1]] - y[u[i]], y[u[i + 2]] - y[u[i]]);
    for (const Vec3& p :
         {(y[u[i]] + y[u[i + 1]] + y[u[i + 2]]) / 3.0, 0.5 * (y[u[i]] + y[u[i + 1]])}) {
      d = std::max(d, ref.Project(p, Vec3(0.0), 0.0).distance / sizing.At(p, n));
    }
  }
  return d;
}

// The crease part of the report: control edges on creases, and the input's crease edges kept
// (midpoint within a quarter of the local target edge length of a control crease edge).
void MeasureCreases(const CreaseChains& creases, const SizingField& sizing,
                    const PolygonMesh& quads, const QuadRelaxFeatures& features,
                    QuadRemeshReport* rep) {
  std::vector<std::array<Vec3, 2>> segments;
  for (std::size_t v = 0; v < features.neighbors.size(); ++v) {
    if (features.feature[v] < 0) continue;
    for (Index w : features.neighbors[v]) {
      if (w == kInvalidIndex) continue;
      // Each edge once: from its lower end, or from the crease vertex when the other end is a
      // corner (which has no neighbour list).
      if (features.feature[static_cast<std::size_t>(w)] >= 0 && static_cast<std::size_t>(w) < v) {
        continue;
      }
      segments.push_back({quads.positions[v], quads.positions[static_cast<std::size_t>(w)]});
    }
  }
  rep->control_crease_edges = static_cast<int>(segments.size());
  int kept = 0;
  const std::vector<Vec3>& x = creases.reference_positions();
  for (const auto& e : creases.edges()) {
    const Vec3 p = 0.5 * (x[e[0]] + x[e[1]]);
    double best = std::numeric_limits<double>::infinity();
    for (const auto& sg : segments) {
      const Vec3 d = sg[1] - sg[0];
      const double dd = glm::dot(d, d);
      const double u = dd > 0.0 ? std::clamp(glm::dot(p - sg[0], d) / dd, 0.0, 1.0) : 0.0;
      best = std::min(best, glm::length(p - (sg[0] + u * d)));
    }
    kept += best <= 0.25 * sizing.At(p, Vec3(0.0)) ? 1 : 0;
  }
  rep->crease_edges_kept = kept;
}

}  // namespace

void MeasureQuadMesh(const PolygonMesh& quads, QuadRemeshReport* report) {
  QuadRemeshReport& r = *report;
  r.vertices = quads.num_vertices();
  r.faces = quads.num_faces();
  MeshTopology topo;
  if (!MeshTopology::Build(quads.num_vertices(), quads.face_offsets, quads.face_vertices, &topo)
           .ok()) {
    return;
  }
  r.components = topo.num_components();
  r.boundary_loops = 0;
  std::vector<char> seen(static_cast<std::size_t>(topo.num_halfedges()), 0);
  for (Index h = 0; h < topo.num_halfedges(); ++h) {
    if (topo.twin(h) != kInvalidIndex || seen[static_cast<std::size_t>(h)]) continue;
    ++r.boundary_loops;
    // Along the boundary: the next boundary half-edge leaves the end of this one.
    for (Index cur = h; !seen[static_cast<std::size_t>(cur)];) {
      seen[static_cast<std::size_t>(cur)] = 1;
      Index next = topo.next(cur);
      while (topo.twin(next) != kInvalidIndex) next = topo.next(topo.twin(next));
      cur = next;
    }
  }
  r.interior_vertices = r.interior_valence4 = r.max_valence = 0;
  for (Index v = 0; v < topo.num_vertices(); ++v) {
    r.max_valence = std::max(r.max_valence, topo.valence(v));
    if (topo.is_boundary_vertex(v) || topo.valence(v) == 0) continue;
    ++r.interior_vertices;
    r.interior_valence4 += topo.valence(v) == 4 ? 1 : 0;
  }
  r.valence4_share = r.interior_vertices > 0
                         ? static_cast<double>(r.interior_valence4) / r.interior_vertices
                         : 1.0;
  double lo = 180.0, hi = 0.0;
  int good = 0, corners = 0;
  for (Index f = 0; f < quads.num_faces(); ++f) {
    const Index b = quads.face_offsets[static_cast<std::size_t>(f)], s = quads.face_size(f);
    for (Index k = 0; k < s; ++k) {
      auto at = [&](Index i) -> const Vec3& {
        return quads.positions[static_cast<std::size_t>(
            quads.face_vertices[static_cast<std::size_t>(b + (i + s) % s)])];
      };
      const Vec3 u = at(k + 1) - at(k), w = at(k - 1) - at(k);
      const double a = std::atan2(glm::length(glm::cross(u, w)), glm::dot(u, w)) * 180.0 / kPi;
      lo = std::min(lo, a), hi = std::max(hi, a);
      good += (a >= 60.0 && a <= 120.0) ? 1 : 0;
      ++corners;
    }
  }
  r.min_corner_angle_deg = lo;
  r.max_corner_angle_deg = hi;
  r.corners_60_120_share = corners > 0 ? static_cast<double>(good) / corners : 0.0;
}

Status QuadRemesh(const std::vector<Vec3>& positions, const std::vector<std::uint32_t>& triangles,
                  const std::string& name, const QuadRemeshOptions& options, PolygonMesh* out,
                  QuadRemeshReport* report) {
  QuadRemeshReport rep;
  rep.target_vertices = options.target_vertices;
  ReferenceSurface ref;
  Status s = ref.Build(positions, triangles, name);
  if (!s.ok()) return s;
  rep.components = ref.num_components();
  rep.boundary_loops = ref.num_loops();
  const int cap = options.max_vertices > 0 ? options.max_vertices : INT_MAX;
  const int target = std::min(options.target_vertices, cap);
  if (target < 8) {
    return Status::InvalidInput(name + ": target of " + std::to_string(target) +
                                " control vertices is below 8");
  }
  // Euler characteristic of the input: a closed triangle mesh of V vertices whose triangles
  // are all paired splits into V + E' + F' = 4 V - 3 chi quad vertices.
  double chi = 0.0;
  {
    std::vector<std::array<std::uint32_t, 2>> edges;
    std::vector<char> used(positions.size(), 0);
    for (std::size_t t = 0; t < triangles.size(); t += 3) {
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t a = triangles[t + static_cast<std::size_t>(k)];
        const std::uint32_t b = triangles[t + static_cast<std::size_t>((k + 1) % 3)];
        edges.push_back({std::min(a, b), std::max(a, b)});
        used[a] = 1;
      }
    }
    std::sort(edges.begin(), edges.end());
    const std::size_t edge_count =
        static_cast<std::size_t>(std::unique(edges.begin(), edges.end()) - edges.begin());
    std::size_t vertex_count = 0;
    for (char u : used) vertex_count += u ? 1 : 0;
    chi = static_cast<double>(vertex_count) - static_cast<double>(edge_count) +
          static_cast<double>(triangles.size() / 3);
  }
  // 1. Seed, for the largest target the growth below may reach.
  const std::size_t nt = triangles.size() / 3;
  const double v_first = std::max(4.0 * rep.components, (target + 3.0 * chi) / 4.0);
  std::size_t seed_target =
      std::max<std::size_t>(static_cast<std::size_t>(options.min_seed_triangles),
                            static_cast<std::size_t>(2.0 * options.seed_factor * v_first *
                                                     (options.max_deviation > 0.0 ? 2.0 : 1.0)));
  RemeshTriangles seed;
  CreaseChains creases;
  creases.Build(ref, options.crease_angle_deg, options.corner_turn_deg, options.smooth_edges);
  const CreaseChains* cr = creases.empty() ? nullptr : &creases;
  rep.crease_edges = static_cast<int>(creases.edges().size());
  rep.crease_chains = creases.num_chains();
  rep.crease_closed_chains = creases.num_closed();
  if (cr) seed_target = nt;  // every crease edge starts as an edge
  std::vector<Index> seed_of;
  for (;;) {
    if (seed_target >= nt) {
      if (!MakeSeed(ref, triangles, nt, &seed, &seed_of)) {
        return Status::Internal(name + ": the input is not a usable seed for remeshing");
      }
      break;
    }
    if (MakeSeed(ref, triangles, seed_target, &seed)) break;
    seed_target *= 2;
  }
  if (cr) TagCreases(creases, seed_of, &seed);
  rep.seed_vertices = static_cast<int>(seed.positions.size());
  std::vector<double> loop_length(seed.positions.size(), 0.0);
  for (std::size_t i = 0; i < loop_length.size(); ++i) {
    if (seed.loop[i] >= 0) loop_length[i] = ref.loop_length(seed.loop[i]);
  }
  // 2-4 at a target: sizing on the seed, isotropic remeshing with the scale corrected from the
  // count reached, pairing. With max_deviation, the target grows until the triangle mesh
  // follows the input that closely.
  RemeshTriangles mesh;
  PolygonMesh paired;
  QuadPairingStats pairing;
  SizingField sizing;
  int goal = target;
  for (int growth = 0;; ++growth) {
    const double v_tri = std::max(4.0 * rep.components, (goal + 3.0 * chi) / 4.0);
    SizingOptions so = options.sizing;
    if (!(so.curvature_radius > 0.0)) {
      // Half the edge of a uniform mesh with the target's vertex count.
      so.curvature_radius = 0.5 * std::sqrt(ref.area() / (0.5 * std::sqrt(3.0) * v_tri));
    }
    s = sizing.Build(seed.positions, seed.triangles, loop_length, so);
    if (!s.ok()) return s.WithContext(name);
    sizing.SetScaleForVertices(v_tri);
    mesh = seed;
    s = RemeshIsotropic(ref, sizing, options.isotropic, &mesh, nullptr, cr);
    if (!s.ok()) return s.WithContext(name);
    const int tolerance = std::max(4, static_cast<int>(std::lround(options.tolerance * goal)));
    IsotropicRemeshOptions again = options.isotropic;
    again.iterations = std::max(2, options.isotropic.iterations / 2);
    const int goal_cap = options.max_deviation > 0.0 ? INT_MAX : cap;
    for (int round = 0;; ++round) {
      const std::vector<std::array<std::uint32_t, 2>> keep = KeepEdges(mesh);
      s = PairTrianglesIntoQuads(mesh.positions, mesh.triangles, options.pairing, &paired, &pairing,
                                 cr ? &keep : nullptr);
      if (!s.ok()) return s.WithContext(name);
      const int count = SplitCount(paired);
      if ((std::abs(count - goal) <= tolerance && count <= goal_cap) || round >= 8) break;
      const double vertices = static_cast<double>(mesh.positions.size());
      if (round < 2) {
        // The count grows by about 4 per triangle-mesh vertex.
        const double wanted = std::max(4.0, vertices + (goal - count) / 4.0);
        sizing.SetScaleForVertices(sizing.PredictedVertices() * wanted / vertices);
        s = RemeshIsotropic(ref, sizing, again, &mesh, nullptr, cr);
        if (!s.ok()) return s.WithContext(name);
      } else if (options.max_deviation > 0.0 && count > goal) {
        break;  // a count needed by the sizing's max_turn is not forced down
      } else {
        int delta = static_cast<int>(std::lround((goal - count) / 4.0));
        if (delta == 0) delta = goal > count && count < goal_cap ? 1 : -1;
        if (AdjustVertexCount(ref, sizing, delta, options.isotropic, &mesh, cr) == 0) break;
      }
    }
    if (!(options.max_deviation > 0.0)) break;
    rep.deviation = Deviation(ref, sizing, mesh);
    if (rep.deviation <= options.max_deviation || growth >= options.max_growth_steps) break;
    goal = static_cast<int>(std::lround(goal * options.growth));
  }
  if (options.max_deviation > 0.0) rep.grown_target = goal;
  {
    rep.triangle_vertices = static_cast<int>(mesh.positions.size());
    rep.quads_paired = pairing.quads;
    rep.triangles_unpaired = pairing.triangles;
    // 5. Split once into quads; new points onto the surface.
    paired.source_name = name + " (paired)";
    QuadMesh quads;
    s = SplitIntoQuads(paired, &quads);
    if (!s.ok()) return s;
    MeshTopology topo;
    s = MeshTopology::Build(paired.num_vertices(), paired.face_offsets, paired.face_vertices,
                            &topo);
    if (!s.ok()) return s.WithContext(name);
    const Index nv = paired.num_vertices(), nf = paired.num_faces();
    std::vector<int> loop(quads.positions.size(), -1);
    for (Index v = 0; v < nv; ++v)
      loop[static_cast<std::size_t>(v)] = mesh.loop[static_cast<std::size_t>(v)];
    // Creases: a crease edge (a, b) becomes (a, m), (m, b) with m on its chain.
    QuadRelaxFeatures features;
    if (cr) {
      features.chains = cr;
      features.feature.assign(quads.positions.size(), kNoFeature);
      features.neighbors.assign(quads.positions.size(), {kInvalidIndex, kInvalidIndex});
      for (Index v = 0; v < nv; ++v) {
        features.feature[static_cast<std::size_t>(v)] = mesh.feature[static_cast<std::size_t>(v)];
      }
    }
    auto add_crease_neighbor = [&](Index v, Index w) {
      std::array<Index, 2>& q = features.neighbors[static_cast<std::size_t>(v)];
      (q[0] == kInvalidIndex ? q[0] : q[1]) = w;
    };
    std::vector<Vec3> face_normal(static_cast<std::size_t>(nf), Vec3(0.0));
    for (Index f = 0; f < nf; ++f) {
      const Index b = paired.face_offsets[static_cast<std::size_t>(f)], sz = paired.face_size(f);
      for (Index k = 0; k < sz; ++k) {
        face_normal[static_cast<std::size_t>(f)] +=
            glm::cross(paired.positions[static_cast<std::size_t>(
                           paired.face_vertices[static_cast<std::size_t>(b + k)])],
                       paired.positions[static_cast<std::size_t>(
                           paired.face_vertices[static_cast<std::size_t>(b + (k + 1) % sz)])]);
      }
    }
    for (Index f = 0; f < nf; ++f) {
      Vec3& p = quads.positions[static_cast<std::size_t>(nv + f)];
      const Vec3& n = face_normal[static_cast<std::size_t>(f)];
      p = ref.Project(p, n, sizing.At(p, n)).point;
    }
    for (Index e = 0; e < topo.num_edges(); ++e) {
      const Index h = topo.edge_halfedge(e);
      const Index a = topo.halfedge_origin(h), b = topo.halfedge_dest(h);
      const std::size_t v = static_cast<std::size_t>(nv + nf + e);
      Vec3& p = quads.positions[v];
      if (topo.twin(h) == kInvalidIndex) {
        loop[v] = mesh.loop[static_cast<std::size_t>(a)];
        p = ref.LoopBetween(loop[v], paired.positions[static_cast<std::size_t>(a)],
                            paired.positions[static_cast<std::size_t>(b)], 0.5);
        continue;
      }
      if (cr) {
        const std::array<std::uint32_t, 2> key{static_cast<std::uint32_t>(std::min(a, b)),
                                               static_cast<std::uint32_t>(std::max(a, b))};
        const auto it = std::lower_bound(
            mesh.crease_edges.begin(), mesh.crease_edges.end(), key,
            [](const std::array<std::uint32_t, 3>& x, const std::array<std::uint32_t, 2>& k) {
              return x[0] < k[0] || (x[0] == k[0] && x[1] < k[1]);
            });
        if (it != mesh.crease_edges.end() && (*it)[0] == key[0] && (*it)[1] == key[1]) {
          const int chain = static_cast<int>((*it)[2]);
          p = cr->Between(chain, paired.positions[static_cast<std::size_t>(a)],
                          paired.positions[static_cast<std::size_t>(b)], 0.5);
          const Index mid = static_cast<Index>(v);
          features.feature[v] = chain;
          features.neighbors[v] = {a, b};
          for (Index end : {a, b}) {
            if (features.feature[static_cast<std::size_t>(end)] >= 0) add_crease_neighbor(end, mid);
          }
          continue;
        }
      }
      const Vec3 n = face_normal[static_cast<std::size_t>(topo.halfedge_face(h))] +
                     face_normal[static_cast<std::size_t>(topo.halfedge_face(topo.twin(h)))];
      p = ref.Project(p, n, sizing.At(p, n)).point;
    }
    PolygonMesh result;
    result.source_name = name + " (control mesh)";
    result.positions = quads.positions;
    for (Index q = 0; q < quads.num_quads(); ++q) {
      const Index* f = quads.quads.data() + 4 * q;
      result.AddFace({f[0], f[1], f[2], f[3]});
    }
    s = RelaxQuadMesh(ref, sizing, loop, options.relax, &result, &rep.relax_rejected,
                      cr ? &features : nullptr);
    if (!s.ok()) return s.WithContext(name);
    // The result must be a valid control mesh with the input's components and loops.
    s = ValidatePolygonMesh(result);
    if (!s.ok()) return Status::Internal(name + ": the quad remesh is invalid: " + s.message());
    const int components = rep.components, loops = rep.boundary_loops;
    MeasureQuadMesh(result, &rep);
    if (cr) MeasureCreases(creases, sizing, result, features, &rep);
    if (rep.components != components || rep.boundary_loops != loops) {
      return Status::Internal(name + ": the quad remesh has " + std::to_string(rep.components) +
                              " components and " + std::to_string(rep.boundary_loops) +
                              " boundary loops where the input has " + std::to_string(components) +
                              " and " + std::to_string(loops));
    }
    // 6. The input's own quads, where they are at least as good a control mesh.
    if (options.input_quads_max_ratio >= 1.0) {
      PolygonMesh own;
      QuadRemeshReport own_rep = rep;
      if (InputQuads(positions, triangles, ref, sizing, creases, options, result, &own, &own_rep)) {
        result = std::move(own);
        rep = own_rep;
      }
    }
    *out = std::move(result);
  }
  if (report) *report = rep;
  return Status::Ok();
}

}  // namespace dermis
