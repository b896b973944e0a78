// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Measures the tessellated domain surface: watertightness, interpolation of the input vertices,
// the largest dihedral angle at two levels (it halves on a C1 surface) and the time taken.
// Usage: bench_tessellation [--levels 8,16] [OBJ ...]   (default: builtin cube and the
// 1,839-vertex bunny from ../shared/data/scans when present).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "dermis/offline/build/domain_builder.h"
#include "dermis/offline/geometry/builtin_meshes.h"
#include "dermis/offline/geometry/mesh_metrics.h"
#include "dermis/offline/io/obj_io.h"
#include "dermis/surface/tessellation.h"

using namespace dermis;

int main(int argc, char** argv) {
  std::vector<int> levels = {8, 16};
  std::vector<std::string> inputs;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--levels") == 0 && i + 1 < argc) {
      levels.clear();
      std::stringstream ss(argv[++i]);
      std::string item;
      while (std::getline(ss, item, ',')) levels.push_back(std::stoi(item));
    } else {
      inputs.push_back(argv[i]);
    }
  }
  if (inputs.empty()) {
    inputs.push_back("builtin:cube");
    const char* bunny = "../shared/data/scans/bunny-npm-1839v.obj";
    if (std::filesystem::exists(bunny)) {
      inputs.push_back(bunny);
    } else {
      std::printf("note: %s not found (run from the repository root); bunny skipped\n", bunny);
    }
  }
  std::printf("%-44s %5s %9s %9s %10s %8s %12s %10s %8s\n", "input", "level", "vertices",
              "triangles", "watertight", "boundary", "max|v-S(v)|", "dihedral", "seconds");
  int status = 0;
  for (const std::string& in : inputs) {
    PolygonMesh mesh;
    Status s =
        in.rfind("builtin:", 0) == 0 ? MakeBuiltinMesh(in.substr(8), &mesh) : ReadObj(in, &mesh);
    if (s.ok()) CompactUnusedVertices(&mesh);
    ControlSurface cs;
    if (s.ok()) s = BuildControlSurface(mesh, DomainOptions{}, &cs);
    if (!s.ok()) {
      std::printf("%s: %s\n", in.c_str(), s.message().c_str());
      status = 1;
      continue;
    }
    const double diag = BoundingBoxDiagonal(mesh.positions);
    double previous = 0.0;
    for (int level : levels) {
      const auto t0 = std::chrono::steady_clock::now();
      TessellationPattern pattern;
      TessellationPattern::Build(cs.domain->topology(), level, &pattern);
      std::vector<Vec3> pos(pattern.samples.size()), nrm(pattern.samples.size());
      EvaluateSamples(*cs.domain, cs.patches.data(), nullptr, pattern.samples.data(),
                      pattern.samples.size(), pos.data(), nrm.data());
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const TriangleMeshMetrics m = ComputeTriangleMeshMetrics(pos, pattern.triangles);
      double worst = 0.0;
      for (Index v = 0; v < mesh.num_vertices(); ++v) {
        worst = std::max(worst, glm::length(pos[v] - mesh.positions[v]) / diag);
      }
      std::printf("%-44s %5d %9zu %9zu %10s %8zu %12.3g %7.3f deg %8.3f", in.c_str(), level,
                  m.vertices, m.triangles, m.watertight() ? "yes" : "NO", m.boundary_edges, worst,
                  m.max_dihedral * 180.0 / M_PI, seconds);
      if (previous > 0.0) std::printf("   ratio to previous level %.3f", m.max_dihedral / previous);
      std::printf("\n");
      previous = m.max_dihedral;
    }
  }
  return status;
}
