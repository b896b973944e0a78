// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Sample: build the manifold surface of a built-in control mesh, move one control vertex,
// refit the patches (one small matrix product per vertex) and evaluate a few surface points.
#include <cstdio>
#include <vector>

#include "dermis/offline/build/domain_builder.h"
#include "dermis/offline/geometry/builtin_meshes.h"
#include "dermis/surface/surface_evaluator.h"

int main() {
  dermis::PolygonMesh mesh;
  dermis::Status s = dermis::MakeBuiltinMesh("house", &mesh);
  dermis::ControlSurface surface;
  if (s.ok()) s = dermis::BuildControlSurface(mesh, dermis::DomainOptions{}, &surface);
  if (!s.ok()) {
    std::fprintf(stderr, "error: %s\n", s.message().c_str());
    return 1;
  }
  const dermis::ManifoldDomain& domain = *surface.domain;
  std::printf("control mesh: %d vertices, %d quads\n", domain.num_vertices(), domain.num_faces());

  // Per frame: push new control positions, refit, evaluate.
  std::vector<dermis::Vec3> positions = surface.control.positions;
  positions[8] += dermis::Vec3(0.3, 0.0, 0.2);  // move the roof apex
  std::vector<dermis::LocalPatch> patches(positions.size());
  domain.FitPatches(positions.data(), patches.data());
  for (dermis::Index face = 0; face < 3; ++face) {
    dermis::SurfacePoint p;
    if (!dermis::EvaluateSurface(domain, patches.data(), nullptr, face, {0.3, 0.6}, &p)) return 1;
    std::printf("face %d (0.3, 0.6): position (%.6f, %.6f, %.6f) normal (%.6f, %.6f, %.6f)\n", face,
                p.position.x, p.position.y, p.position.z, p.normal.x, p.normal.y, p.normal.z);
  }
  return 0;
}
