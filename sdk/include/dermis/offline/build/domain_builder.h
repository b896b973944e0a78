// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Offline construction of a manifold domain from a polygon control mesh.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "dermis/core/status.h"
#include "dermis/offline/geometry/polygon_mesh.h"
#include "dermis/offline/geometry/quadrangulate.h"
#include "dermis/surface/local_patch.h"
#include "dermis/surface/manifold_domain.h"

namespace dermis {

/// A control mesh with its manifold domain and the patches fitted to its rest positions.
struct ControlSurface {
  QuadMesh control;                        ///< The all-quad control mesh (rest positions).
  std::unique_ptr<ManifoldDomain> domain;  ///< Charts, blending and patch operators.
  std::vector<LocalPatch> patches;         ///< Fitted to control.positions.
};

/// Chooses the chart kind of every vertex of an all-quad topology: interior vertices get full
/// charts; a boundary vertex with one face is a convex corner; with more faces the sum of its
/// corner angles at rest decides: < 3pi/4 convex corner, > 5pi/4 concave corner, else crease.
std::vector<VertexKind> ClassifyVertices(const MeshTopology& topology,
                                         const std::vector<Vec3>& positions);

/// Builds the domain of an all-quad topology: chart kinds from the rest positions, one patch-fit
/// operator per distinct (valence, kind, seam mode). `seam` (optional, per vertex, missing
/// entries 0; CutAlongCreases() gives it): a non-zero vertex is a side of a cut crease and gets
/// a seam operator (ComputeSeamPatchFitOperator), so the two sides of the cut meet exactly: a
/// 1 (inside a chain) whose two boundary edges are more than 150 degrees apart a half-disk
/// chart (kCrease) with kSmooth, any other a corner chart (convex where its corner angles sum
/// to less than pi, else concave) with kCorner. InvalidInput for a non-zero entry on an interior
/// vertex, marks of another count than the vertices, or marks with ChartType::kFullyComplex
/// (p = q on boundaries: the sides of a cut would not meet).
Status BuildManifoldDomain(const MeshTopology& topology, const std::vector<Vec3>& positions,
                           const DomainOptions& options, std::unique_ptr<ManifoldDomain>* out,
                           const std::vector<std::uint8_t>* seam = nullptr);

/// The whole chain: validate, quadrangulate, build topology and domain, fit patches.
/// Errors name the mesh's source, element and line. `seam`: as BuildManifoldDomain's, one per
/// vertex of `mesh`, which must then be all quads (a quadrangulation would put unmarked
/// vertices on the cut): InvalidInput otherwise.
Status BuildControlSurface(const PolygonMesh& mesh, const DomainOptions& options,
                           ControlSurface* out, const std::vector<std::uint8_t>* seam = nullptr);

}  // namespace dermis
