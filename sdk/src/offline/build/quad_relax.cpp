// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Quad-mesh relaxation on the reference surface: the tangential smoothing step of Botsch &
// Kobbelt 2004 (section 3) applied to polygon faces, with back-projection and the boundary kept
// on its loops (docs/fitting.md, "Control mesh").
#include "dermis/offline/build/quad_relax.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace dermis {
namespace {

// Newell's normal of face f: its direction is the face's, its length twice the area.
Vec3 FaceNormal(const PolygonMesh& m, Index f) {
  Vec3 n(0.0);
  const Index b = m.face_offsets[static_cast<std::size_t>(f)];
  const Index s = m.face_size(f);
  for (Index k = 0; k < s; ++k) {
    const Vec3& p =
        m.positions[static_cast<std::size_t>(m.face_vertices[static_cast<std::size_t>(b + k)])];
    const Vec3& q = m.positions[static_cast<std::size_t>(
        m.face_vertices[static_cast<std::size_t>(b + (k + 1) % s)])];
    n += glm::cross(p, q);
  }
  return n;
}

// Whether every corner of face f turns the same way as `n` (the face is convex).
bool Convex(const PolygonMesh& m, Index f, const Vec3& n) {
  const Index b = m.face_offsets[static_cast<std::size_t>(f)];
  const Index s = m.face_size(f);
  auto at = [&](Index k) -> const Vec3& {
    return m.positions[static_cast<std::size_t>(
        m.face_vertices[static_cast<std::size_t>(b + (k + s) % s)])];
  };
  for (Index k = 0; k < s; ++k) {
    if (!(glm::dot(glm::cross(at(k + 1) - at(k), at(k - 1) - at(k)), n) > 0.0)) return false;
  }
  return true;
}

Vec3 FaceCentroid(const PolygonMesh& m, Index f) {
  Vec3 c(0.0);
  const Index b = m.face_offsets[static_cast<std::size_t>(f)];
  const Index s = m.face_size(f);
  for (Index k = 0; k < s; ++k) {
    c += m.positions[static_cast<std::size_t>(m.face_vertices[static_cast<std::size_t>(b + k)])];
  }
  return c / static_cast<double>(s);
}

}  // namespace

Status RelaxQuadMesh(const ReferenceSurface& reference, const SizingField& sizing,
                     const std::vector<int>& loop, const QuadRelaxOptions& options,
                     PolygonMesh* mesh, int* rejected, const QuadRelaxFeatures* features) {
  PolygonMesh& m = *mesh;
  const std::size_t nv = m.positions.size();
  if (loop.size() != nv) return Status::InvalidInput("quad relaxation: loop ids do not match");
  if (features &&
      (!features->chains || features->feature.size() != nv || features->neighbors.size() != nv)) {
    return Status::InvalidInput("quad relaxation: feature tags do not match");
  }
  auto feature = [&](std::size_t v) { return features ? features->feature[v] : kNoFeature; };
  // Where crease vertex v goes along its chain (t < 0: in proportion to the sizes).
  auto crease_target = [&](std::size_t v, const std::vector<double>& sz, double t) {
    const std::array<Index, 2>& q = features->neighbors[v];
    if (q[0] == kInvalidIndex || q[1] == kInvalidIndex) return m.positions[v];
    const std::size_t a = static_cast<std::size_t>(q[0]), c = static_cast<std::size_t>(q[1]);
    if (t < 0.0) {
      const double hp = 0.5 * (sz[a] + sz[v]), hn = 0.5 * (sz[v] + sz[c]);
      t = hp / (hp + hn);
    }
    return features->chains->Between(feature(v), m.positions[a], m.positions[c], t);
  };
  const double cos_max = std::cos(options.max_normal_change_deg * 3.14159265358979323846 / 180.0);
  std::vector<std::vector<Index>> faces_of(nv);
  std::vector<std::array<Index, 3>> directed;  // (a, b, face)
  for (Index f = 0; f < m.num_faces(); ++f) {
    const Index b = m.face_offsets[static_cast<std::size_t>(f)];
    const Index s = m.face_size(f);
    for (Index k = 0; k < s; ++k) {
      const Index v = m.face_vertices[static_cast<std::size_t>(b + k)];
      const Index w = m.face_vertices[static_cast<std::size_t>(b + (k + 1) % s)];
      faces_of[static_cast<std::size_t>(v)].push_back(f);
      directed.push_back({v, w, f});
    }
  }
  std::sort(directed.begin(), directed.end());
  auto has = [&](Index a, Index b) {
    auto it = std::lower_bound(directed.begin(), directed.end(), std::array<Index, 3>{a, b, -1});
    return it != directed.end() && (*it)[0] == a && (*it)[1] == b;
  };
  // Boundary neighbours: prev -> v -> next along the faces' orientation.
  std::vector<Index> prev(nv, kInvalidIndex), next(nv, kInvalidIndex);
  for (const auto& d : directed) {
    if (!has(d[1], d[0])) {
      next[static_cast<std::size_t>(d[0])] = d[1];
      prev[static_cast<std::size_t>(d[1])] = d[0];
    }
  }
  std::vector<double> size(nv, 0.0);
  std::vector<Vec3> target(nv);
  int undone = 0;
  for (int it = 0; it < options.iterations; ++it) {
    std::vector<Vec3> vertex_normal(nv, Vec3(0.0));
    for (Index f = 0; f < m.num_faces(); ++f) {
      const Vec3 n = FaceNormal(m, f);
      const Index b = m.face_offsets[static_cast<std::size_t>(f)];
      for (Index k = 0; k < m.face_size(f); ++k) {
        vertex_normal[static_cast<std::size_t>(m.face_vertices[static_cast<std::size_t>(b + k)])] +=
            n;
      }
    }
    for (std::size_t v = 0; v < nv; ++v) {
      const double l = glm::length(vertex_normal[v]);
      if (l > 0.0) vertex_normal[v] /= l;
      size[v] = sizing.At(m.positions[v], vertex_normal[v]);
    }
    for (std::size_t v = 0; v < nv; ++v) {
      const Vec3 p = m.positions[v];
      target[v] = p;
      if (faces_of[v].empty() || feature(v) == kCornerFeature) continue;
      if (feature(v) >= 0) {
        target[v] = crease_target(v, size, -1.0);
        continue;
      }
      if (next[v] != kInvalidIndex) {
        if (prev[v] == kInvalidIndex || loop[v] < 0) continue;
        const std::size_t a = static_cast<std::size_t>(prev[v]),
                          c = static_cast<std::size_t>(next[v]);
        const double hp = 0.5 * (size[a] + size[v]), hn = 0.5 * (size[v] + size[c]);
        target[v] = reference.LoopBetween(loop[v], m.positions[a], m.positions[c], hp / (hp + hn));
        continue;
      }
      Vec3 c(0.0);
      double w = 0.0;
      for (Index f : faces_of[v]) {
        const Index b = m.face_offsets[static_cast<std::size_t>(f)];
        double h = 0.0;
        for (Index k = 0; k < m.face_size(f); ++k) {
          h += size[static_cast<std::size_t>(m.face_vertices[static_cast<std::size_t>(b + k)])];
        }
        h /= static_cast<double>(m.face_size(f));
        const double a = glm::length(FaceNormal(m, f)) / (h * h);
        c += a * FaceCentroid(m, f);
        w += a;
      }
      if (!(w > 0.0)) continue;
      c /= w;
      const Vec3& n = vertex_normal[v];
      const Vec3 d = (c - p) - n * glm::dot(c - p, n);
      target[v] = reference.Project(p + d, n, size[v]).point;
    }
    for (std::size_t v = 0; v < nv; ++v) {
      const Vec3 old = m.positions[v];
      if (target[v] == old) continue;
      std::vector<Vec3> before;
      std::vector<char> convex;
      for (Index f : faces_of[v]) {
        before.push_back(FaceNormal(m, f));
        convex.push_back(Convex(m, f, before.back()) ? 1 : 0);
      }
      m.positions[v] = target[v];
      bool ok = true;
      for (std::size_t i = 0; i < before.size() && ok; ++i) {
        const Index f = faces_of[v][i];
        const Vec3 n = FaceNormal(m, f);
        const double ln = glm::length(n), lo = glm::length(before[i]);
        ok = ln > 1e-10 * size[v] * size[v] &&
             !(lo > 0.0 && glm::dot(n, before[i]) < cos_max * ln * lo) &&
             (!convex[i] || Convex(m, f, n));
      }
      if (!ok) {
        m.positions[v] = old;
        ++undone;
      }
    }
  }
  // Untangling: a face that is not convex or faces against all its neighbours moves its corners
  // to better places, projected back (at most 30 rounds).
  std::vector<std::vector<Index>> ring(nv);
  for (const auto& d : directed) {
    ring[static_cast<std::size_t>(d[0])].push_back(d[1]);
    ring[static_cast<std::size_t>(d[1])].push_back(d[0]);
  }
  for (auto& r : ring) {
    std::sort(r.begin(), r.end());
    r.erase(std::unique(r.begin(), r.end()), r.end());
  }
  for (int round = 0; round < 30; ++round) {
    std::vector<Vec3> normal(static_cast<std::size_t>(m.num_faces()));
    for (Index f = 0; f < m.num_faces(); ++f)
      normal[static_cast<std::size_t>(f)] = FaceNormal(m, f);
    std::vector<char> marked(nv, 0);
    int folds = 0;
    for (Index f = 0; f < m.num_faces(); ++f) {
      const Vec3& n = normal[static_cast<std::size_t>(f)];
      int against = 0, neighbours = 0;
      const Index b = m.face_offsets[static_cast<std::size_t>(f)], sz = m.face_size(f);
      for (Index k = 0; k < sz; ++k) {
        const Index v = m.face_vertices[static_cast<std::size_t>(b + k)];
        const Index w = m.face_vertices[static_cast<std::size_t>(b + (k + 1) % sz)];
        auto it =
            std::lower_bound(directed.begin(), directed.end(), std::array<Index, 3>{w, v, -1});
        if (it != directed.end() && (*it)[0] == w && (*it)[1] == v) {
          ++neighbours;
          against += glm::dot(n, normal[static_cast<std::size_t>((*it)[2])]) < 0.0 ? 1 : 0;
        }
      }
      // Not convex, or turned over (against every neighbour; on a thin part a face may face
      // away from those across the rim).
      if (Convex(m, f, n) && (neighbours == 0 || against < neighbours)) continue;
      ++folds;
      for (Index k = 0; k < sz; ++k) {
        marked[static_cast<std::size_t>(m.face_vertices[static_cast<std::size_t>(b + k)])] = 1;
      }
    }
    if (folds == 0) break;
    std::vector<Vec3> vn(nv, Vec3(0.0));
    for (Index f = 0; f < m.num_faces(); ++f) {
      const Index b = m.face_offsets[static_cast<std::size_t>(f)];
      for (Index k = 0; k < m.face_size(f); ++k) {
        vn[static_cast<std::size_t>(m.face_vertices[static_cast<std::size_t>(b + k)])] +=
            normal[static_cast<std::size_t>(f)];
      }
    }
    // Non-convex faces around v with v at `p`.
    auto bad_around = [&](std::size_t v, const Vec3& p) {
      const Vec3 keep = m.positions[v];
      m.positions[v] = p;
      int bad = 0;
      for (Index f : faces_of[v]) bad += Convex(m, f, FaceNormal(m, f)) ? 0 : 1;
      m.positions[v] = keep;
      return bad;
    };
    for (std::size_t v = 0; v < nv; ++v) {
      if (!marked[v] || feature(v) == kCornerFeature) continue;
      if (feature(v) >= 0) {
        m.positions[v] = crease_target(v, size, 0.5);
        continue;
      }
      // Candidates: the mean of the edge neighbours (or half way along the loop for a boundary
      // vertex), and for every face where v's corner is reflex the point that makes that face a
      // parallelogram; each projected back. The one leaving fewest non-convex faces wins (the
      // mean on ties, and the mean if none improves, so the smoothing still progresses).
      std::vector<Vec3> candidates;
      const bool on_boundary = next[v] != kInvalidIndex;
      if (on_boundary) {
        if (prev[v] == kInvalidIndex || loop[v] < 0) continue;
        candidates.push_back(
            reference.LoopBetween(loop[v], m.positions[static_cast<std::size_t>(prev[v])],
                                  m.positions[static_cast<std::size_t>(next[v])], 0.5));
      } else {
        Vec3 c(0.0), n(0.0);
        for (Index w : ring[v]) {
          c += m.positions[static_cast<std::size_t>(w)], n += vn[static_cast<std::size_t>(w)];
        }
        c /= static_cast<double>(std::max<std::size_t>(ring[v].size(), 1));
        const double l = glm::length(n);
        const Vec3 nu = l > 0.0 ? n / l : n;
        candidates.push_back(reference.Project(c, nu, size[v]).point);
        for (Index f : faces_of[v]) {
          const Index b = m.face_offsets[static_cast<std::size_t>(f)], sz = m.face_size(f);
          if (sz != 4) continue;
          Index k = 0;
          while (m.face_vertices[static_cast<std::size_t>(b + k)] != static_cast<Index>(v)) ++k;
          auto at = [&](Index i) -> const Vec3& {
            return m.positions[static_cast<std::size_t>(
                m.face_vertices[static_cast<std::size_t>(b + (i + sz) % sz)])];
          };
          candidates.push_back(
              reference.Project(at(k - 1) + at(k + 1) - at(k + 2), nu, size[v]).point);
        }
      }
      const int now = bad_around(v, m.positions[v]);
      std::size_t best = 0;
      int best_bad = bad_around(v, candidates[0]);
      for (std::size_t i = 1; i < candidates.size(); ++i) {
        const int b = bad_around(v, candidates[i]);
        if (b < best_bad) best = i, best_bad = b;
      }
      if (best_bad <= now || best == 0) m.positions[v] = candidates[best];
    }
  }
  if (rejected) *rejected = undone;
  return Status::Ok();
}

}  // namespace dermis
