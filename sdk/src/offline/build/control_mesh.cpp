// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Automatic control mesh (Yoon section 4, "Control mesh", which used a commercial tool): weld
// with meshoptimizer's vertex remap, simplify with meshopt_simplify, even out valences with
// edge flips, then one Catmull-Clark style split to all quads (quadrangulate.cpp).
#include "dermis/offline/build/control_mesh.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "dermis/offline/build/quad_pairing.h"
#include "dermis/offline/geometry/quadrangulate.h"
#include "dermis/offline/geometry/triangle_distance.h"

namespace dermis {
namespace {

using Edge = std::pair<std::uint32_t, std::uint32_t>;

// Vertex count of the quad mesh that one split of a triangle mesh gives: V + E + F.
int SplitVertexCount(const std::vector<std::uint32_t>& tris) {
  std::vector<std::uint32_t> used(tris);
  std::sort(used.begin(), used.end());
  const std::size_t vertices =
      static_cast<std::size_t>(std::unique(used.begin(), used.end()) - used.begin());
  std::vector<Edge> edges;
  edges.reserve(tris.size());
  for (std::size_t t = 0; t < tris.size(); t += 3) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = tris[t + k], b = tris[t + (k + 1) % 3];
      edges.push_back({std::min(a, b), std::max(a, b)});
    }
  }
  std::sort(edges.begin(), edges.end());
  const std::size_t unique_edges =
      static_cast<std::size_t>(std::unique(edges.begin(), edges.end()) - edges.begin());
  return static_cast<int>(vertices + unique_edges + tris.size() / 3);
}

Vec3 TriangleNormal(const std::vector<Vec3>& x, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  return glm::cross(x[b] - x[a], x[c] - x[a]);
}

// Edge flips that reduce sum (valence - ideal)^2 (ideal 6 inside, 4 on the boundary) without
// turning a triangle over or making it much thinner. Deterministic (fixed sweep order).
int FlipToEvenValences(const std::vector<Vec3>& x, std::vector<std::uint32_t>* tris) {
  std::vector<std::uint32_t>& t = *tris;
  const std::size_t nt = t.size() / 3;
  std::map<Edge, std::size_t> directed;  // (a, b) -> triangle holding the directed edge
  std::map<std::uint32_t, int> valence;
  std::set<std::uint32_t> boundary;
  for (std::size_t f = 0; f < nt; ++f) {
    for (int k = 0; k < 3; ++k) directed[{t[3 * f + k], t[3 * f + (k + 1) % 3]}] = f;
  }
  std::set<Edge> undirected;
  for (const auto& e : directed) {
    undirected.insert(
        {std::min(e.first.first, e.first.second), std::max(e.first.first, e.first.second)});
    if (!directed.count({e.first.second, e.first.first})) {
      boundary.insert(e.first.first);
      boundary.insert(e.first.second);
    }
  }
  for (const Edge& e : undirected) ++valence[e.first], ++valence[e.second];
  auto ideal = [&](std::uint32_t v) { return boundary.count(v) ? 4 : 6; };
  auto third = [&](std::size_t f, std::uint32_t a, std::uint32_t b) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = t[3 * f + k];
      if (v != a && v != b) return v;
    }
    return a;
  };
  auto min_angle_cos = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    double worst = -1.0;  // largest cosine = smallest angle
    const std::uint32_t v[3] = {a, b, c};
    for (int k = 0; k < 3; ++k) {
      const Vec3 e1 = x[v[(k + 1) % 3]] - x[v[k]], e2 = x[v[(k + 2) % 3]] - x[v[k]];
      const double l = std::sqrt(glm::dot(e1, e1) * glm::dot(e2, e2));
      worst = std::max(worst, l > 0.0 ? glm::dot(e1, e2) / l : 1.0);
    }
    return worst;
  };
  int flips = 0;
  for (int pass = 0; pass < 8; ++pass) {
    int pass_flips = 0;
    const std::vector<Edge> edges(undirected.begin(), undirected.end());
    for (const Edge& e : edges) {
      const std::uint32_t a = e.first, b = e.second;
      auto i1 = directed.find({a, b}), i2 = directed.find({b, a});
      if (i1 == directed.end() || i2 == directed.end()) continue;
      const std::size_t f1 = i1->second, f2 = i2->second;
      const std::uint32_t c = third(f1, a, b), d = third(f2, a, b);
      if (c == d || directed.count({c, d}) || directed.count({d, c})) continue;
      if (valence[a] <= 3 || valence[b] <= 3) continue;
      auto cost = [&](std::uint32_t v, int val) {
        const int dv = val - ideal(v);
        return dv * dv;
      };
      const int before =
          cost(a, valence[a]) + cost(b, valence[b]) + cost(c, valence[c]) + cost(d, valence[d]);
      const int after = cost(a, valence[a] - 1) + cost(b, valence[b] - 1) +
                        cost(c, valence[c] + 1) + cost(d, valence[d] + 1);
      if (after >= before) continue;
      // Triangles (a, b, c) and (b, a, d) become (a, d, c) and (d, b, c).
      const Vec3 n_old = TriangleNormal(x, a, b, c) + TriangleNormal(x, b, a, d);
      const Vec3 n1 = TriangleNormal(x, a, d, c), n2 = TriangleNormal(x, d, b, c);
      if (glm::dot(n1, n_old) <= 0.0 || glm::dot(n2, n_old) <= 0.0 || glm::dot(n1, n2) <= 0.0) {
        continue;
      }
      const double old_quality = std::max(min_angle_cos(a, b, c), min_angle_cos(b, a, d));
      const double new_quality = std::max(min_angle_cos(a, d, c), min_angle_cos(d, b, c));
      if (new_quality > std::max(old_quality, std::cos(0.2))) continue;  // min angle 11.5 deg
      for (int k = 0; k < 3; ++k) {
        directed.erase({t[3 * f1 + k], t[3 * f1 + (k + 1) % 3]});
        directed.erase({t[3 * f2 + k], t[3 * f2 + (k + 1) % 3]});
      }
      t[3 * f1] = a, t[3 * f1 + 1] = d, t[3 * f1 + 2] = c;
      t[3 * f2] = d, t[3 * f2 + 1] = b, t[3 * f2 + 2] = c;
      for (int k = 0; k < 3; ++k) {
        directed[{t[3 * f1 + k], t[3 * f1 + (k + 1) % 3]}] = f1;
        directed[{t[3 * f2 + k], t[3 * f2 + (k + 1) % 3]}] = f2;
      }
      undirected.erase(e);
      undirected.insert({std::min(c, d), std::max(c, d)});
      --valence[a], --valence[b], ++valence[c], ++valence[d];
      ++pass_flips;
    }
    flips += pass_flips;
    if (pass_flips == 0) break;
  }
  return flips;
}

}  // namespace

Status BuildControlMesh(const PolygonMesh& mesh, const ControlMeshOptions& requested,
                        PolygonMesh* control, ControlMeshInfo* info) {
  const std::string where = mesh.source_name.empty() ? "mesh" : mesh.source_name;
  ControlMeshInfo local;
  ControlMeshInfo& inf = info ? *info : local;
  inf = ControlMeshInfo();
  if (mesh.num_faces() <= 0)
    return Status::InvalidInput(where + ": no faces to build a control mesh from");
  if (requested.target_vertices < 8) {
    return Status::InvalidInput("control mesh: target vertex count " +
                                std::to_string(requested.target_vertices) + " is below 8");
  }
  // Fan triangles and float positions for meshoptimizer.
  std::vector<std::uint32_t> tris;
  for (Index f = 0; f < mesh.num_faces(); ++f) {
    const Index o = mesh.face_offsets[f];
    for (Index k = 1; k + 1 < mesh.face_size(f); ++k) {
      tris.insert(tris.end(), {static_cast<std::uint32_t>(mesh.face_vertices[o]),
                               static_cast<std::uint32_t>(mesh.face_vertices[o + k]),
                               static_cast<std::uint32_t>(mesh.face_vertices[o + k + 1])});
    }
  }
  const std::size_t nv = mesh.positions.size();
  std::vector<float> xyz(3 * nv);
  for (std::size_t v = 0; v < nv; ++v) {
    for (int c = 0; c < 3; ++c) xyz[3 * v + c] = static_cast<float>(mesh.positions[v][c]);
  }
  // Weld identical positions.
  std::vector<unsigned int> remap(nv);
  const std::size_t unique = meshopt_generateVertexRemap(remap.data(), tris.data(), tris.size(),
                                                         xyz.data(), nv, 3 * sizeof(float));
  std::vector<Vec3> x(unique);
  std::vector<float> wxyz(3 * unique);
  for (std::size_t v = 0; v < nv; ++v) {
    if (remap[v] == ~0u) continue;
    x[remap[v]] = mesh.positions[v];
    for (int c = 0; c < 3; ++c) wxyz[3 * remap[v] + c] = xyz[3 * v + c];
  }
  std::vector<std::uint32_t> welded;
  for (std::size_t t = 0; t < tris.size(); t += 3) {
    const std::uint32_t a = remap[tris[t]], b = remap[tris[t + 1]], c = remap[tris[t + 2]];
    const Vec3 n = TriangleNormal(x, a, b, c);
    if (a == b || b == c || a == c || glm::dot(n, n) == 0.0) {
      ++inf.degenerate_triangles;
      continue;
    }
    welded.insert(welded.end(), {a, b, c});
  }
  std::vector<std::uint32_t> used_before(welded);
  std::sort(used_before.begin(), used_before.end());
  used_before.erase(std::unique(used_before.begin(), used_before.end()), used_before.end());
  std::size_t used_count_input = 0;
  {
    std::vector<char> used(nv, 0);
    for (std::uint32_t i : tris) used[i] = 1;
    for (char u : used) used_count_input += u ? 1 : 0;
  }
  inf.welded_vertices = static_cast<int>(used_count_input - used_before.size());
  if (used_before.size() < 4 || welded.size() < 6) {
    return Status::InvalidInput(where + ": too few usable triangles for a control mesh");
  }
  const int full = SplitVertexCount(welded);
  ControlMeshOptions options = requested;
  if (options.clamp_to_full_split)
    options.target_vertices = std::min(options.target_vertices, full);
  if (options.target_vertices > full) {
    return Status::InvalidInput(
        where + ": target of " + std::to_string(options.target_vertices) +
        " control vertices is more than the " + std::to_string(full) +
        " that splitting the whole mesh gives; use a smaller --control-vertices");
  }
  // An all-quad input at the target count is already a control mesh: kept as it is (a regular
  // grid stays regular), if its quads are convex and not degenerate.
  if (options.method == ControlMeshMethod::kRemesh &&
      mesh.face_vertices.size() == 4u * static_cast<std::size_t>(mesh.num_faces()) &&
      std::abs(mesh.num_vertices() - options.target_vertices) <=
          std::max(4, static_cast<int>(
                          std::lround(options.remesh.tolerance * options.target_vertices))) &&
      ValidatePolygonMesh(mesh).ok()) {
    QuadRemeshReport q;
    q.target_vertices = options.target_vertices;
    MeasureQuadMesh(mesh, &q);
    bool convex = true;
    for (Index f = 0; f < mesh.num_faces() && convex; ++f) {
      const Index* v = mesh.face_vertices.data() + mesh.face_offsets[f];
      convex = QuadQuality(mesh.positions[v[0]], mesh.positions[v[1]], mesh.positions[v[2]],
                           mesh.positions[v[3]]) > 0.0;
    }
    if (convex && q.vertices == mesh.num_vertices() && q.min_corner_angle_deg > 20.0) {
      inf.method = "given quads";
      inf.quality = q;
      inf.max_valence = q.max_valence;
      *control = mesh;
      CompactUnusedVertices(control);
      return Status::Ok();
    }
  }
  if (options.method == ControlMeshMethod::kRemesh) {
    QuadRemeshOptions ro = options.remesh;
    ro.target_vertices = options.target_vertices;
    // The smooth edges in the welded numbering (an index out of range, or an edge the weld
    // collapsed, names no edge of the welded mesh and is dropped).
    ro.smooth_edges.clear();
    for (const auto& e : options.remesh.smooth_edges) {
      if (e[0] >= nv || e[1] >= nv) continue;
      const std::uint32_t a = remap[e[0]], b = remap[e[1]];
      if (a != ~0u && b != ~0u && a != b) ro.smooth_edges.push_back({a, b});
    }
    PolygonMesh remeshed;
    QuadRemeshReport rr;
    const Status rs = QuadRemesh(x, welded, where, ro, &remeshed, &rr);
    if (rs.ok()) {
      inf.method = "remesh";
      inf.quality = rr;
      inf.max_valence = rr.max_valence;
      *control = std::move(remeshed);
      return Status::Ok();
    }
    inf.fallback = rs.message();
  }
  inf.method = "simplify";
  // Find the triangle count whose split is closest to the target (V + E + F ~ 3 F), among
  // simplifications that stay manifold and consistently oriented after the valence flips
  // (meshopt_simplify can pinch thin parts of low-poly meshes into non-manifold edges).
  auto manifold_after_flips = [&](std::vector<std::uint32_t>* candidate, int* flips) {
    *flips = FlipToEvenValences(x, candidate);
    std::map<std::uint32_t, Index> ids;
    PolygonMesh m;
    for (std::uint32_t i : *candidate) {
      if (ids.emplace(i, static_cast<Index>(ids.size())).second) m.positions.push_back(x[i]);
    }
    for (std::size_t t = 0; t + 2 < candidate->size(); t += 3) {
      m.AddFace({ids[(*candidate)[t]], ids[(*candidate)[t + 1]], ids[(*candidate)[t + 2]]});
    }
    return ValidatePolygonMesh(m).ok();
  };
  std::vector<std::uint32_t> best, simplified(welded.size());
  int best_count = -1, best_flips = 0;
  double target_tris = options.target_vertices / 3.0;
  for (int attempt = 0; attempt < 6; ++attempt) {
    // meshopt_simplify requires a target no larger than the input; at or above it, the
    // candidate is the whole mesh.
    const std::size_t target_index =
        std::min(welded.size(),
                 std::max<std::size_t>(
                     6, 3 * static_cast<std::size_t>(std::llround(std::max(target_tris, 2.0)))));
    std::size_t n = welded.size();
    if (target_index < welded.size()) {
      n = meshopt_simplify(simplified.data(), welded.data(), welded.size(), wxyz.data(), unique,
                           3 * sizeof(float), target_index, 1.0f, 0, nullptr);
    } else {
      std::copy(welded.begin(), welded.end(), simplified.begin());
    }
    std::vector<std::uint32_t> candidate(simplified.begin(),
                                         simplified.begin() + static_cast<std::ptrdiff_t>(n));
    const int count = SplitVertexCount(candidate);
    int flips = 0;
    if (n >= 6 && manifold_after_flips(&candidate, &flips) &&
        (best_count < 0 || std::abs(count - options.target_vertices) <
                               std::abs(best_count - options.target_vertices))) {
      best = candidate;
      best_count = count;
      best_flips = flips;
    }
    if (count == options.target_vertices || n == 0) break;
    target_tris *= static_cast<double>(options.target_vertices) / std::max(count, 1);
  }
  // No manifold simplification near the target: keep more triangles, up to the whole mesh.
  for (double grow = 1.3; best.empty(); grow *= 1.3) {
    const std::size_t target_index =
        std::min(welded.size(),
                 3 * static_cast<std::size_t>(std::llround(grow * options.target_vertices / 3.0)));
    std::vector<std::uint32_t> candidate = welded;
    if (target_index < welded.size()) {
      const std::size_t n =
          meshopt_simplify(simplified.data(), welded.data(), welded.size(), wxyz.data(), unique,
                           3 * sizeof(float), target_index, 1.0f, 0, nullptr);
      candidate.assign(simplified.begin(), simplified.begin() + static_cast<std::ptrdiff_t>(n));
    }
    int flips = 0;
    if (candidate.size() >= 6 && manifold_after_flips(&candidate, &flips)) {
      best = candidate;
      best_flips = flips;
    } else if (target_index >= welded.size()) {
      break;
    }
  }
  if (best.size() < 6) {
    return Status::InvalidInput(where +
                                ": no simplification of the mesh is manifold with at least 2 "
                                "triangles (is the input itself manifold and consistently "
                                "oriented?)");
  }
  inf.edge_flips = best_flips;
  // Compact to the used vertices, in first-use order.
  std::map<std::uint32_t, Index> new_index;
  PolygonMesh tri_mesh;
  tri_mesh.source_name = where + " (simplified)";
  for (std::uint32_t& i : best) {
    auto it = new_index.find(i);
    if (it == new_index.end()) {
      it = new_index.emplace(i, static_cast<Index>(tri_mesh.positions.size())).first;
      tri_mesh.positions.push_back(x[i]);
    }
  }
  for (std::size_t t = 0; t < best.size(); t += 3) {
    tri_mesh.AddFace({new_index[best[t]], new_index[best[t + 1]], new_index[best[t + 2]]});
  }
  inf.simplified_vertices = tri_mesh.num_vertices();
  inf.simplified_triangles = tri_mesh.num_faces();
  Status s = ValidatePolygonMesh(tri_mesh);
  if (!s.ok())
    return Status::InvalidInput("control mesh: simplification of " + where +
                                " gave an invalid mesh (" + s.message() + ")");
  QuadMesh quads;
  s = Quadrangulate(tri_mesh, &quads);
  if (!s.ok()) return s;
  // Move the new edge and face points onto the input surface when it is close by (at most a
  // quarter of the local edge length away), so the control mesh samples the data.
  TriangleDistanceTree tree;
  tree.Build(x, welded);
  std::vector<double> reach(quads.positions.size(), 0.0);
  for (Index q = 0; q < quads.num_quads(); ++q) {
    for (int k = 0; k < 4; ++k) {
      const Index a = quads.quads[4 * q + k], b = quads.quads[4 * q + (k + 1) % 4];
      const Vec3 d = quads.positions[a] - quads.positions[b];
      const double l = std::sqrt(glm::dot(d, d));
      reach[a] = std::max(reach[a], l), reach[b] = std::max(reach[b], l);
    }
  }
  // The control-mesh normal at each new point (sum over its quads), to reject a closest point on
  // the far side of a thin part (an ear's back for a point on its front).
  std::vector<Vec3> normal(quads.positions.size(), Vec3(0.0));
  for (Index q = 0; q < quads.num_quads(); ++q) {
    const Index* f = quads.quads.data() + 4 * q;
    const Vec3 n = glm::cross(quads.positions[f[2]] - quads.positions[f[0]],
                              quads.positions[f[3]] - quads.positions[f[1]]);
    for (int k = 0; k < 4; ++k) normal[f[k]] += n;
  }
  for (std::size_t v = static_cast<std::size_t>(quads.num_input_vertices);
       v < quads.positions.size(); ++v) {
    const ClosestPoint cp = tree.Query(quads.positions[v]);
    if (cp.triangle == kInvalidIndex || cp.distance > 0.25 * reach[v]) continue;
    const std::size_t t = 3 * static_cast<std::size_t>(cp.triangle);
    const Vec3 nt = TriangleNormal(x, welded[t], welded[t + 1], welded[t + 2]);
    const double c = glm::dot(nt, normal[v]);
    if (c > 0.5 * std::sqrt(glm::dot(nt, nt) * glm::dot(normal[v], normal[v]))) {
      quads.positions[v] = cp.point;
    }
  }
  PolygonMesh out;
  out.source_name = where + " (control mesh)";
  out.positions = quads.positions;
  for (Index q = 0; q < quads.num_quads(); ++q) {
    out.AddFace({quads.quads[4 * q], quads.quads[4 * q + 1], quads.quads[4 * q + 2],
                 quads.quads[4 * q + 3]});
  }
  // No degenerate quads: every quad must keep a positive area on both diagonals' triangles.
  for (Index q = 0; q < out.num_faces(); ++q) {
    const Index* f = out.face_vertices.data() + out.face_offsets[q];
    const Vec3 n1 = glm::cross(out.positions[f[1]] - out.positions[f[0]],
                               out.positions[f[2]] - out.positions[f[0]]);
    const Vec3 n2 = glm::cross(out.positions[f[2]] - out.positions[f[0]],
                               out.positions[f[3]] - out.positions[f[0]]);
    if (!(glm::dot(n1, n1) > 0.0) || !(glm::dot(n2, n2) > 0.0)) {
      return Status::Internal("control mesh: quad " + std::to_string(q) + " of " + where +
                              " is degenerate");
    }
  }
  s = ValidatePolygonMesh(out);
  if (!s.ok()) return s;
  inf.quality.target_vertices = options.target_vertices;
  MeasureQuadMesh(out, &inf.quality);
  inf.max_valence = inf.quality.max_valence;
  *control = std::move(out);
  return Status::Ok();
}

}  // namespace dermis
