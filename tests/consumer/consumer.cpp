// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Uses the installed Dermis package: builds the surface of a built-in control mesh (offline),
// evaluates it (runtime), deforms points (deform) and writes a glTF in memory (plugin).
// Prints "consumer ok" and exits 0 when everything worked.
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "dermis/asset/asset.h"
#include "dermis/deform/deformer.h"
#include "dermis/offline/build/domain_builder.h"
#include "dermis/offline/geometry/builtin_meshes.h"
#include "dermis/plugins/gltf.h"
#include "dermis/surface/surface_evaluator.h"

int main() {
  dermis::PolygonMesh mesh;
  if (!dermis::MakeBuiltinMesh("cube", &mesh).ok()) return 1;
  dermis::ControlSurface surface;
  if (!dermis::BuildControlSurface(mesh, dermis::DomainOptions{}, &surface).ok()) return 1;
  std::vector<dermis::LocalPatch> patches(surface.control.positions.size());
  surface.domain->FitPatches(surface.control.positions.data(), patches.data());
  dermis::SurfacePoint p;
  dermis::EvaluateSurface(*surface.domain, patches.data(), nullptr, 0, {0.5, 0.5}, &p);
  if (!std::isfinite(p.position.x) || !(glm::length(p.normal) > 0.5)) return 1;

  dermis::SkinRig rig;
  rig.parents = {-1};
  rig.bind = {glm::dmat4(1.0)};
  std::vector<dermis::Vec3> rest = {p.position};
  std::vector<dermis::VertexWeights> weights(1);
  weights[0].weights = glm::vec4(1.0f, 0.0f, 0.0f, 0.0f);
  std::unique_ptr<dermis::Deformer> lbs;
  if (!dermis::MakeLbsDeformer(rig, rest.data(), nullptr, weights.data(), 1, &lbs).ok()) return 1;
  glm::dmat4 moved(1.0);
  moved[3] = glm::dvec4(1.0, 2.0, 3.0, 1.0);
  if (!lbs->SetPose(&moved).ok()) return 1;
  dermis::Vec3 x;
  lbs->Deform(0, 1, &x, nullptr);
  if (glm::length(x - (p.position + dermis::Vec3(1, 2, 3))) > 1e-12) return 1;

  dermis::Asset asset;
  std::string bytes;
  const dermis::Status s = dermis::SerializeGltf(asset, dermis::GltfExportOptions{}, true, &bytes);
  if (!s.ok() || bytes.compare(0, 4, "glTF") != 0) {
    std::fprintf(stderr, "consumer: %s\n", s.message().c_str());
    return 1;
  }
  std::printf("consumer ok\n");
  return 0;
}
