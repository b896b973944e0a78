// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Offline assembly of the manifold domain: chart kinds, shared patch-fit operators, patches.
#include "dermis/offline/build/domain_builder.h"

#include <array>
#include <cmath>
#include <map>
#include <utility>

#include "dermis/offline/build/patch_fit_operator.h"

namespace dermis {
namespace {
constexpr double kPi = 3.14159265358979323846;

double Angle(Vec3 a, Vec3 b) {
  const double c = glm::length(glm::cross(a, b));
  const double d = glm::dot(a, b);
  return std::atan2(c, d);
}
// Sum of the corner angles of boundary vertex v's ring faces at rest (pi on a flat boundary).
double CornerAngleSum(const MeshTopology& topo, const std::vector<Vec3>& positions, Index v) {
  double sum = 0.0;
  for (int i = 0; i < topo.valence(v); ++i) {
    const RingCorner rc = topo.ring(v, i);
    const Index n = topo.face_vertex(rc.face, (rc.corner + 1) % topo.face_size(rc.face));
    const Index p = topo.face_vertex(
        rc.face, (rc.corner + topo.face_size(rc.face) - 1) % topo.face_size(rc.face));
    sum += Angle(positions[n] - positions[v], positions[p] - positions[v]);
  }
  return sum;
}
}  // namespace

std::vector<VertexKind> ClassifyVertices(const MeshTopology& topo,
                                         const std::vector<Vec3>& positions) {
  std::vector<VertexKind> kinds(topo.num_vertices(), VertexKind::kInterior);
  for (Index v = 0; v < topo.num_vertices(); ++v) {
    if (!topo.is_boundary_vertex(v)) continue;
    const int k = topo.valence(v);
    if (k == 1) {
      kinds[v] = VertexKind::kConvexCorner;
      continue;
    }
    const double sum = CornerAngleSum(topo, positions, v);
    if (sum < 0.75 * kPi) {
      kinds[v] = VertexKind::kConvexCorner;
    } else if (sum > 1.25 * kPi) {
      kinds[v] = VertexKind::kConcaveCorner;
    } else {
      kinds[v] = VertexKind::kCrease;
    }
  }
  return kinds;
}

Status BuildManifoldDomain(const MeshTopology& topology, const std::vector<Vec3>& positions,
                           const DomainOptions& options, std::unique_ptr<ManifoldDomain>* out,
                           const std::vector<std::uint8_t>* seam) {
  if (positions.size() != static_cast<size_t>(topology.num_vertices())) {
    return Status::InvalidInput("position count does not match the topology");
  }
  DomainData data;
  data.topology = topology;
  data.options = options;
  data.vertex_kind = ClassifyVertices(topology, positions);
  data.vertex_operator.assign(topology.num_vertices(), kInvalidIndex);
  data.operator_offsets.assign(1, 0);
  // Seam vertices (a cut crease's boundary, CutAlongCreases): the chart and the operator follow
  // the side's boundary at the vertex. A side inside a chain (mark 1) whose two boundary edges
  // run nearly straight on (more than 150 degrees apart) gets a half-disk chart whose boundary
  // restriction is the parabola through the two neighbours (kSmooth), never a corner chart,
  // whose two rays at right angles would have to open to a straight line (a patch with a
  // singular Jacobian, a flap). A sharper turn, a junction or the boundary (mark 2) is a
  // corner, convex or concave by the sum of its corner angles, with straight lines to the
  // neighbours (kCorner): the only restriction every side at a junction can share, even where
  // one side's boundary runs straight on (docs/math.md, "Seam patches").
  if (seam && seam->size() != static_cast<std::size_t>(topology.num_vertices())) {
    return Status::InvalidInput("seam marks: " + std::to_string(seam->size()) + " for " +
                                std::to_string(topology.num_vertices()) + " vertices");
  }
  if (seam && options.chart_type == ChartType::kFullyComplex) {
    // p = q on a boundary chart: two sides of a cut with different valences would map the
    // cut edge differently, and the sides would not meet.
    for (std::uint8_t m : *seam) {
      if (m != 0) {
        return Status::InvalidInput(
            "seam marks need a chart type with p = 1 on boundaries, not "
            "the fully complex one");
      }
    }
  }
  std::vector<SeamMode> modes(static_cast<std::size_t>(topology.num_vertices()), SeamMode::kNone);
  for (Index v = 0; seam && v < topology.num_vertices(); ++v) {
    if ((*seam)[static_cast<std::size_t>(v)] == 0) continue;
    if (!topology.is_boundary_vertex(v)) {
      return Status::InvalidInput("vertex " + std::to_string(v) +
                                  " is on a seam but not on a boundary");
    }
    const int k = topology.valence(v);
    const RingCorner first = topology.ring(v, 0), last = topology.ring(v, k - 1);
    const Index n1 = topology.face_vertex(first.face, (first.corner + 1) % 4);
    const Index n2 = topology.face_vertex(last.face, (last.corner + 3) % 4);
    const double turn = Angle(positions[n1] - positions[v], positions[n2] - positions[v]);
    VertexKind& kind = data.vertex_kind[static_cast<std::size_t>(v)];
    if ((*seam)[static_cast<std::size_t>(v)] == 1 && turn > 150.0 / 180.0 * kPi) {
      kind = VertexKind::kCrease;
      modes[static_cast<std::size_t>(v)] = SeamMode::kSmooth;
    } else {
      kind = CornerAngleSum(topology, positions, v) < kPi ? VertexKind::kConvexCorner
                                                          : VertexKind::kConcaveCorner;
      modes[static_cast<std::size_t>(v)] = SeamMode::kCorner;
    }
  }

  std::map<std::array<int, 3>, Index> cache;
  for (Index v = 0; v < topology.num_vertices(); ++v) {
    const int k = topology.valence(v);
    if (k == 0) return Status::InvalidInput("vertex " + std::to_string(v) + " is used by no face");
    const SeamMode mode = modes[static_cast<std::size_t>(v)];
    const std::array<int, 3> key = {k, static_cast<int>(data.vertex_kind[v]),
                                    static_cast<int>(mode)};
    auto it = cache.find(key);
    if (it == cache.end()) {
      if (!topology.is_boundary_vertex(v) && k < 3) {
        return Status::InvalidInput("interior vertex " + std::to_string(v) + " has valence " +
                                    std::to_string(k) + " (at least 3 needed)");
      }
      std::vector<double> op;
      Status s = ComputeSeamPatchFitOperator(
          MakeChartParams(k, data.vertex_kind[v], options.chart_type), mode, &op);
      if (!s.ok()) return s.WithContext("vertex " + std::to_string(v));
      const Index id = static_cast<Index>(data.operator_offsets.size()) - 1;
      data.operator_values.insert(data.operator_values.end(), op.begin(), op.end());
      data.operator_offsets.push_back(static_cast<Index>(data.operator_values.size()));
      it = cache.emplace(key, id).first;
    }
    data.vertex_operator[v] = it->second;
  }
  Status status;
  auto domain = ManifoldDomain::Create(std::move(data), &status);
  if (!domain) return status;
  *out = std::move(domain);
  return Status::Ok();
}

Status BuildControlSurface(const PolygonMesh& mesh, const DomainOptions& options,
                           ControlSurface* out, const std::vector<std::uint8_t>* seam) {
  Status s = ValidatePolygonMesh(mesh);
  if (s.ok()) s = CheckCoordinateRange(mesh);
  if (!s.ok()) return s;
  if (seam) {
    // The marks name the mesh's vertices; a quadrangulation would add unmarked vertices on the
    // cut.
    if (seam->size() != mesh.positions.size()) {
      return Status::InvalidInput(mesh.source_name + ": " + std::to_string(seam->size()) +
                                  " seam marks for " + std::to_string(mesh.positions.size()) +
                                  " vertices");
    }
    for (Index f = 0; f < mesh.num_faces(); ++f) {
      if (mesh.face_size(f) != 4) {
        return Status::InvalidInput(mesh.source_name + ": a mesh with seam marks must be all " +
                                    "quads; " + mesh.FaceName(f) + " has " +
                                    std::to_string(mesh.face_size(f)) + " sides");
      }
    }
  }
  ControlSurface cs;
  s = Quadrangulate(mesh, &cs.control);
  if (!s.ok()) return s;
  ElementNamer namer;
  namer.face = [&](Index f) {
    return "quad " + std::to_string(f) + " of " + mesh.FaceName(cs.control.quad_source_face[f]);
  };
  MeshTopology topo;
  s = MeshTopology::BuildQuads(static_cast<Index>(cs.control.positions.size()), cs.control.quads,
                               &topo, &namer);
  if (!s.ok()) return s.WithContext(mesh.source_name.empty() ? "mesh" : mesh.source_name);
  s = BuildManifoldDomain(topo, cs.control.positions, options, &cs.domain, seam);
  if (!s.ok()) return s.WithContext(mesh.source_name.empty() ? "mesh" : mesh.source_name);
  cs.patches.resize(cs.control.positions.size());
  cs.domain->FitPatches(cs.control.positions.data(), cs.patches.data());
  *out = std::move(cs);
  return Status::Ok();
}

}  // namespace dermis
