// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief The manifold domain: an all-quad control topology with one chart per vertex, the
/// partition of unity and the precomputed local-patch fit operators (paper section 3, Eq. 1-2).
///
/// The domain depends only on topology (and, for boundary charts, the rest-pose corner angles
/// chosen when it was built). Control-vertex positions are pushed separately through
/// FitPatches(), so a deforming control mesh refits its patches each frame with one small matrix
/// product per vertex and no allocation (OpenSubdiv's "topology once, positions per frame").
#pragma once

#include <memory>
#include <vector>

#include "dermis/core/mesh_topology.h"
#include "dermis/core/status.h"
#include "dermis/surface/blend.h"
#include "dermis/surface/chart.h"
#include "dermis/surface/local_patch.h"

namespace dermis {

/// Global settings of the manifold construction.
struct DomainOptions {
  ChartType chart_type = ChartType::kCharacteristicMap;
  BlendType blend_type = BlendType::kCInfinity;
  /// Lower end of the blending window; ub = 1 - lb. Must lie in (0, 1/2): lb > 0 keeps the
  /// partition of unity smooth at extraordinary vertices (docs/notes/manifold.md section 7).
  /// Ying-Zorin use 1/8; a wide window (small lb) spreads the transition between disagreeing
  /// patches over the whole face and avoids folds on irregular control meshes (docs/math.md), hence
  /// 0.01.
  double blend_lb = 0.01;
};

/// Everything a ManifoldDomain is made of. Filled by the offline builder
/// (dermis/offline/build/domain_builder.h) or by a file reader, then validated by Create().
struct DomainData {
  MeshTopology topology;  ///< All quads, every vertex used by a face.
  DomainOptions options;
  std::vector<VertexKind> vertex_kind;  ///< One per vertex; kInterior exactly for interior ones.
  /// Patch-fit operators, stored once per distinct (valence, kind) and shared.
  /// Operator o has 8 rows (kPatchMonomials order) and ring_size columns, row-major, at
  /// operator_values[operator_offsets[o] ..]; its column count is given by the ring of any
  /// vertex that uses it.
  std::vector<Index> operator_offsets;  ///< Size = number of operators + 1.
  std::vector<double> operator_values;
  std::vector<Index> vertex_operator;  ///< One per vertex.
};

/// Immutable, thread-shareable manifold domain over an all-quad control mesh.
class ManifoldDomain {
 public:
  /// Validates `data` and builds the domain. Returns null and sets *status on failure.
  static std::unique_ptr<ManifoldDomain> Create(DomainData data, Status* status);

  const MeshTopology& topology() const { return data_.topology; }
  const DomainOptions& options() const { return data_.options; }
  Index num_vertices() const { return data_.topology.num_vertices(); }
  Index num_faces() const { return data_.topology.num_faces(); }
  const ChartParams& chart(Index v) const { return charts_[v]; }
  VertexKind vertex_kind(Index v) const { return data_.vertex_kind[v]; }
  const DomainData& data() const { return data_; }
  /// Bytes held by the domain (topology, operators, charts, patch rings).
  std::size_t memory_bytes() const;

  /// The control vertices whose positions determine vertex v's patch, in operator column
  /// order: for each ring face i the edge neighbour at the end of its c-axis, then its diagonal
  /// neighbour; on a boundary the last entry is the far end of the last face's d-axis.
  /// Ring size is 2K inside and 2K + 1 on a boundary.
  const Index* patch_ring(Index v) const { return ring_vertices_.data() + ring_offsets_[v]; }
  int patch_ring_size(Index v) const { return ring_offsets_[v + 1] - ring_offsets_[v]; }
  /// Row-major 8 x patch_ring_size(v) fit operator of vertex v.
  const double* patch_operator(Index v) const {
    return data_.operator_values.data() + data_.operator_offsets[data_.vertex_operator[v]];
  }

  /// Fits every local patch to the control positions (paper Eq. 2): coeff[0][0] = x[v] and the
  /// other 8 coefficients = operator * (x[ring] - x[v]).
  /// \param positions  num_vertices() control positions (caller-owned).
  /// \param patches    num_vertices() patches, written (caller-owned). Does not allocate.
  void FitPatches(const Vec3* positions, LocalPatch* patches) const;
  /// Fits the patch of one vertex.
  void FitPatch(Index v, const Vec3* positions, LocalPatch* patch) const;

  /// Chart coordinates of corner `corner` of `face` at face coordinates uv.
  Vec2 FaceToChart(Index face, int corner, Vec2 uv) const;
  /// Face and face coordinates of point z of vertex v's chart. Returns false if z lies outside
  /// the chart's star (a boundary sector, or beyond the incident faces).
  bool ChartToFace(Index v, Vec2 z, Index* face, Vec2* uv) const;
  /// Transition map theta_{ij} (docs/notes/manifold.md section 3): chart point z of vertex i
  /// expressed in the chart of vertex j. Returns false when j is not a corner of the face that
  /// contains z.
  bool Transition(Index i, Vec2 z, Index j, Vec2* zj) const;

 private:
  ManifoldDomain() = default;
  DomainData data_;
  std::vector<ChartParams> charts_;
  std::vector<Index> ring_offsets_;
  std::vector<Index> ring_vertices_;
};

}  // namespace dermis
