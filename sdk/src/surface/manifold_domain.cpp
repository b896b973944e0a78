// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Manifold domain: charts per vertex, transitions through face coordinates (docs/notes/manifold.md
// section 3) and the local-patch refit of Yoon Eq. 2 as one precomputed linear operator.
#include "dermis/surface/manifold_domain.h"

#include <cmath>
#include <cstdint>
#include <string>

namespace dermis {
namespace {

Vec3 SafeNormalize(Vec3 n, Vec3 fallback) {
  const double len = std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
  if (len > 0.0 && std::isfinite(len)) return n / len;
  return fallback;
}

}  // namespace

std::unique_ptr<ManifoldDomain> ManifoldDomain::Create(DomainData data, Status* status) {
  auto fail = [&](const std::string& message) -> std::unique_ptr<ManifoldDomain> {
    if (status) *status = Status::InvalidInput("manifold domain: " + message);
    return nullptr;
  };
  const MeshTopology& topo = data.topology;
  const Index nv = topo.num_vertices();
  if (topo.num_faces() == 0) return fail("the control mesh has no faces");
  if (!topo.is_all_quads()) return fail("the control mesh is not all quads");
  const double lb = data.options.blend_lb;
  if (!(lb > 0.0 && lb < 0.5)) {
    return fail("blend_lb = " + std::to_string(lb) + " must lie in (0, 0.5)");
  }
  if (data.vertex_kind.size() != static_cast<size_t>(nv) ||
      data.vertex_operator.size() != static_cast<size_t>(nv)) {
    return fail("per-vertex arrays do not match the vertex count");
  }
  if (data.operator_offsets.empty() || data.operator_offsets.front() != 0 ||
      static_cast<size_t>(data.operator_offsets.back()) != data.operator_values.size()) {
    return fail("operator offsets do not describe the operator values");
  }
  // Every offset is dereferenced by patch_operator(): each must lie inside the value array and the
  // sequence must not decrease (checked in 64 bits, so no difference can overflow).
  for (size_t i = 0; i + 1 < data.operator_offsets.size(); ++i) {
    const std::int64_t begin = data.operator_offsets[i];
    const std::int64_t end = data.operator_offsets[i + 1];
    if (begin < 0 || end < begin || static_cast<std::uint64_t>(end) > data.operator_values.size()) {
      return fail("operator offset " + std::to_string(i + 1) + " is " + std::to_string(end) +
                  ": outside the operator values (0.." +
                  std::to_string(data.operator_values.size()) + ") or below offset " +
                  std::to_string(i) + " (" + std::to_string(begin) + ")");
    }
  }
  for (double x : data.operator_values) {
    if (!std::isfinite(x)) return fail("a patch-fit operator has a non-finite entry");
  }
  std::unique_ptr<ManifoldDomain> d(new ManifoldDomain());
  d->charts_.resize(nv);
  d->ring_offsets_.assign(nv + 1, 0);
  const Index num_ops = static_cast<Index>(data.operator_offsets.size()) - 1;
  for (Index v = 0; v < nv; ++v) {
    const int k = topo.valence(v);
    const bool boundary = topo.is_boundary_vertex(v);
    const VertexKind kind = data.vertex_kind[v];
    if (k == 0) return fail("vertex " + std::to_string(v) + " is used by no face");
    if (boundary != (kind != VertexKind::kInterior)) {
      return fail("vertex " + std::to_string(v) + " has a chart kind that does not match " +
                  (boundary ? "its boundary" : "its interior") + " position");
    }
    if (!boundary && k < 3) {
      return fail("interior vertex " + std::to_string(v) + " has valence " + std::to_string(k) +
                  " (at least 3 needed)");
    }
    d->charts_[v] = MakeChartParams(k, kind, data.options.chart_type);
    const int ring = 2 * k + (boundary ? 1 : 0);
    d->ring_offsets_[v + 1] = d->ring_offsets_[v] + ring;
    const Index op = data.vertex_operator[v];
    if (op < 0 || op >= num_ops) return fail("vertex " + std::to_string(v) + " has no operator");
    if (static_cast<std::int64_t>(data.operator_offsets[op + 1]) - data.operator_offsets[op] !=
        static_cast<std::int64_t>(8) * ring) {
      return fail("the operator of vertex " + std::to_string(v) + " does not fit its ring size");
    }
  }
  d->ring_vertices_.resize(d->ring_offsets_[nv]);
  for (Index v = 0; v < nv; ++v) {
    Index* out = d->ring_vertices_.data() + d->ring_offsets_[v];
    const int k = topo.valence(v);
    for (int i = 0; i < k; ++i) {
      const RingCorner rc = topo.ring(v, i);
      *out++ = topo.face_vertex(rc.face, (rc.corner + 1) & 3);
      *out++ = topo.face_vertex(rc.face, (rc.corner + 2) & 3);
    }
    if (topo.is_boundary_vertex(v)) {
      const RingCorner rc = topo.ring(v, k - 1);
      *out++ = topo.face_vertex(rc.face, (rc.corner + 3) & 3);
    }
  }
  d->data_ = std::move(data);
  if (status) *status = Status::Ok();
  return d;
}

void ManifoldDomain::FitPatch(Index v, const Vec3* positions, LocalPatch* patch) const {
  const Vec3 center = positions[v];
  const int n = patch_ring_size(v);
  const Index* ring = patch_ring(v);
  const double* op = patch_operator(v);
  Vec3 coeff[8];
  for (int row = 0; row < 8; ++row) coeff[row] = Vec3(0.0);
  for (int col = 0; col < n; ++col) {
    const Vec3 delta = positions[ring[col]] - center;
    for (int row = 0; row < 8; ++row) coeff[row] += op[row * n + col] * delta;
  }
  for (int m = 0; m < 3; ++m)
    for (int k = 0; k < 3; ++k) patch->coeff[m][k] = Vec3(0.0);
  patch->coeff[0][0] = center;
  for (int row = 0; row < 8; ++row) {
    patch->coeff[kPatchMonomials[row][0]][kPatchMonomials[row][1]] = coeff[row];
  }
  // One-ring normal of the control mesh: sum of the corner cross products of the ring faces.
  Vec3 normal(0.0);
  const int k = topology().valence(v);
  for (int i = 0; i < k; ++i) {
    const RingCorner rc = topology().ring(v, i);
    const Vec3 a = positions[topology().face_vertex(rc.face, (rc.corner + 1) & 3)] - center;
    const Vec3 b = positions[topology().face_vertex(rc.face, (rc.corner + 3) & 3)] - center;
    normal += glm::cross(a, b);
  }
  const Vec3 tangent_normal = glm::cross(patch->coeff[1][0], patch->coeff[0][1]);
  patch->fallback_normal = SafeNormalize(normal, SafeNormalize(tangent_normal, Vec3(0, 0, 1)));
}

void ManifoldDomain::FitPatches(const Vec3* positions, LocalPatch* patches) const {
  const Index nv = num_vertices();
  for (Index v = 0; v < nv; ++v) FitPatch(v, positions, patches + v);
}

Vec2 ManifoldDomain::FaceToChart(Index face, int corner, Vec2 uv) const {
  const MeshTopology& topo = topology();
  const Index h = topo.face_offset(face) + corner;
  const Index v = topo.halfedge_origin(h);
  Vec2 z;
  ChartMap(charts_[v], topo.halfedge_ring_index(h), FaceToCorner(corner, uv), &z);
  return z;
}

bool ManifoldDomain::ChartToFace(Index v, Vec2 z, Index* face, Vec2* uv) const {
  int f = 0;
  Vec2 w;
  if (!ChartMapInverse(charts_[v], z, &f, &w)) return false;
  const double tol = 1e-12;
  if (w.x > 1.0 + tol || w.y > 1.0 + tol) return false;
  w = glm::clamp(w, Vec2(0.0), Vec2(1.0));
  const RingCorner rc = topology().ring(v, f);
  *face = rc.face;
  *uv = CornerToFace(rc.corner, w);
  return true;
}

bool ManifoldDomain::Transition(Index i, Vec2 z, Index j, Vec2* zj) const {
  Index face = kInvalidIndex;
  Vec2 uv;
  if (!ChartToFace(i, z, &face, &uv)) return false;
  for (int b = 0; b < 4; ++b) {
    if (topology().face_vertex(face, b) == j) {
      *zj = FaceToChart(face, b, uv);
      return true;
    }
  }
  return false;
}

std::size_t ManifoldDomain::memory_bytes() const {
  return sizeof(ManifoldDomain) + data_.topology.memory_bytes() +
         data_.vertex_kind.capacity() * sizeof(VertexKind) +
         (data_.operator_offsets.capacity() + data_.vertex_operator.capacity() +
          ring_offsets_.capacity() + ring_vertices_.capacity()) *
             sizeof(Index) +
         data_.operator_values.capacity() * sizeof(double) +
         charts_.capacity() * sizeof(ChartParams);
}

}  // namespace dermis
