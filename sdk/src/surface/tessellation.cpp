// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Uniform n x n tessellation with shared edge and vertex samples (watertight by construction).
#include "dermis/surface/tessellation.h"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <string>

#include "dermis/core/limits.h"
#include "dermis/surface/surface_evaluator.h"

#if defined(__unix__) || defined(__APPLE__)
#include <sys/resource.h>
#include <unistd.h>
#endif

namespace dermis {

namespace {

// The most bytes one tessellation may take: limits::kMaxTessellationBytes, half the physical
// memory and half the address-space limit of the process (ulimit -v), whichever is least.
std::uint64_t TessellationMemoryBudget() {
  std::uint64_t budget = limits::kMaxTessellationBytes;
#if defined(__unix__) || defined(__APPLE__)
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
  if (pages > 0 && page > 0) {
    budget =
        std::min(budget, static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page) / 2);
  }
  struct rlimit rl;
  if (::getrlimit(RLIMIT_AS, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY) {
    budget = std::min(budget, static_cast<std::uint64_t>(rl.rlim_cur) / 2);
  }
#endif
  return budget;
}

// Where the samples of a level-n pattern lie: vertices first, then n - 1 per edge, then
// (n - 1)^2 per face.
struct SampleLayout {
  long long n = 0;
  std::uint32_t edge_base = 0, face_base = 0;
};

// Vertex samples, owned by ring face 0.
void VertexSamples(const MeshTopology& topo, std::vector<SampleLocation>* samples) {
  static const double kCornerU[4] = {0, 1, 1, 0}, kCornerV[4] = {0, 0, 1, 1};
  for (Index v = 0; v < topo.num_vertices(); ++v) {
    if (topo.valence(v) == 0) {
      (*samples)[v] = SampleLocation{kInvalidIndex, 0, 0};
      continue;
    }
    const RingCorner rc = topo.ring(v, 0);
    (*samples)[v] = SampleLocation{rc.face, kCornerU[rc.corner], kCornerV[rc.corner]};
  }
}

// Edge samples, owned by the face of the canonical half-edge.
void EdgeSamples(const MeshTopology& topo, const SampleLayout& l,
                 std::vector<SampleLocation>* samples) {
  const long long n = l.n;
  const double inv = 1.0 / static_cast<double>(n);
  for (Index e = 0; e < topo.num_edges(); ++e) {
    const Index h = topo.edge_halfedge(e);
    const Index f = topo.halfedge_face(h);
    const int k = static_cast<int>(h - topo.face_offset(f));
    for (long long t = 1; t < n; ++t) {
      // Exactly the grid values (i/n, j/n) that the owning face uses for this point.
      const double a = static_cast<double>(t) * inv, b = static_cast<double>(n - t) * inv;
      const double u = k == 0 ? a : k == 1 ? 1.0 : k == 2 ? b : 0.0;
      const double v = k == 0 ? 0.0 : k == 1 ? a : k == 2 ? 1.0 : b;
      (*samples)[l.edge_base + e * (n - 1) + (t - 1)] = SampleLocation{f, u, v};
    }
  }
}

// Grid point (i, j) of face f to a global sample index.
std::uint32_t GridIndex(const MeshTopology& topo, const SampleLayout& l, Index f, long long i,
                        long long j) {
  const long long n = l.n;
  if ((i == 0 || i == n) && (j == 0 || j == n)) {
    const int corner = i == 0 ? (j == 0 ? 0 : 3) : (j == 0 ? 1 : 2);
    return static_cast<std::uint32_t>(topo.face_vertex(f, corner));
  }
  if (i > 0 && i < n && j > 0 && j < n) {
    return static_cast<std::uint32_t>(l.face_base + (f * (n - 1) + (j - 1)) * (n - 1) + (i - 1));
  }
  int k;
  long long t;  // steps from the half-edge's origin
  if (j == 0) {
    k = 0;
    t = i;
  } else if (i == n) {
    k = 1;
    t = j;
  } else if (j == n) {
    k = 2;
    t = n - i;
  } else {
    k = 3;
    t = n - j;
  }
  const Index h = topo.face_offset(f) + k;
  const Index e = topo.halfedge_edge(h);
  if (topo.edge_halfedge(e) != h) t = n - t;
  return static_cast<std::uint32_t>(l.edge_base + e * (n - 1) + (t - 1));
}

// Face samples and the two triangles of every grid cell, split along the diagonal towards the
// cell's nearest face corner.
void FaceSamplesAndTriangles(const MeshTopology& topo, const SampleLayout& l,
                             TessellationPattern* p) {
  const long long n = l.n;
  const double inv = 1.0 / static_cast<double>(n);
  for (Index f = 0; f < topo.num_faces(); ++f) {
    for (long long j = 1; j < n; ++j)
      for (long long i = 1; i < n; ++i)
        p->samples[l.face_base + (f * (n - 1) + (j - 1)) * (n - 1) + (i - 1)] =
            SampleLocation{f, static_cast<double>(i) * inv, static_cast<double>(j) * inv};
    for (long long j = 0; j < n; ++j) {
      for (long long i = 0; i < n; ++i) {
        const std::uint32_t p00 = GridIndex(topo, l, f, i, j);
        const std::uint32_t p10 = GridIndex(topo, l, f, i + 1, j);
        const std::uint32_t p11 = GridIndex(topo, l, f, i + 1, j + 1);
        const std::uint32_t p01 = GridIndex(topo, l, f, i, j + 1);
        // Diagonal towards the nearest face corner: corners 0 and 2 -> p00-p11, 1 and 3 -> p10-p01.
        const bool left = 2 * i + 1 < n, bottom = 2 * j + 1 < n;
        const bool main_diagonal = left == bottom;
        if (main_diagonal) {
          p->triangles.insert(p->triangles.end(), {p00, p10, p11, p00, p11, p01});
        } else {
          p->triangles.insert(p->triangles.end(), {p00, p10, p01, p10, p11, p01});
        }
      }
    }
  }
}

}  // namespace

Status TessellationPattern::Build(const MeshTopology& topo, int level, TessellationPattern* out) {
  if (level < 1)
    return Status::InvalidInput("tessellation level " + std::to_string(level) +
                                " must be at least 1");
  if (level > 4096)
    return Status::InvalidInput("tessellation level " + std::to_string(level) +
                                " is too large (at most 4096)");
  if (!topo.is_all_quads()) return Status::InvalidInput("tessellation needs an all-quad mesh");
  const long long n = level;
  const long long nv = topo.num_vertices(), ne = topo.num_edges(), nf = topo.num_faces();
  const long long num_samples = nv + ne * (n - 1) + nf * (n - 1) * (n - 1);
  const long long num_tris = nf * n * n * 2;
  if (num_samples > std::numeric_limits<std::uint32_t>::max() ||
      num_tris * 3 > static_cast<long long>(std::numeric_limits<std::int32_t>::max())) {
    return Status::InvalidInput("tessellation at level " + std::to_string(level) + " would have " +
                                std::to_string(num_samples) + " samples: too many");
  }
  // Memory before allocation: the pattern (a location per sample, three indices per triangle)
  // and what a caller evaluates into it (position and normal in double, Vec3 each, and the float
  // copies written out), against the fixed limit and half of what this process may have.
  const std::uint64_t bytes =
      static_cast<std::uint64_t>(num_samples) * (sizeof(SampleLocation) + 2 * sizeof(Vec3) + 24) +
      static_cast<std::uint64_t>(num_tris) * 3 * sizeof(std::uint32_t) * 2;
  const std::uint64_t budget = TessellationMemoryBudget();
  if (bytes > budget) {
    return Status::InvalidInput(
        "tessellation at level " + std::to_string(level) + " of " + std::to_string(nf) +
        " faces needs about " + std::to_string(bytes >> 20) + " MiB, more than the " +
        std::to_string(budget >> 20) + " MiB allowed (half the memory available, at most " +
        std::to_string(limits::kMaxTessellationBytes >> 20) + " MiB): lower --level");
  }
  TessellationPattern p;
  p.level = level;
  p.samples.resize(static_cast<size_t>(num_samples));
  SampleLayout layout;
  layout.n = n;
  layout.edge_base = static_cast<std::uint32_t>(nv);
  layout.face_base = static_cast<std::uint32_t>(nv + ne * (n - 1));
  VertexSamples(topo, &p.samples);
  EdgeSamples(topo, layout, &p.samples);
  p.triangles.reserve(static_cast<size_t>(num_tris * 3));
  FaceSamplesAndTriangles(topo, layout, &p);
  *out = std::move(p);
  return Status::Ok();
}

bool EvaluateSamples(const ManifoldDomain& domain, const LocalPatch* patches,
                     const Displacement* displacement, const SampleLocation* samples,
                     std::size_t count, Vec3* positions, Vec3* normals) {
  bool ok = true;
  for (std::size_t i = 0; i < count; ++i) {
    SurfacePoint sp;
    if (!EvaluateSurface(domain, patches, displacement, samples[i].face,
                         Vec2(samples[i].u, samples[i].v), &sp)) {
      ok = false;
      positions[i] = Vec3(0.0);
      if (normals) normals[i] = Vec3(0.0, 0.0, 1.0);
      continue;
    }
    positions[i] = sp.position;
    if (normals) normals[i] = sp.normal;
  }
  return ok;
}

}  // namespace dermis
