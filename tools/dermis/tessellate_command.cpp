// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// dermis tessellate: polygon OBJ (or built-in mesh) -> manifold domain surface -> OBJ.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <string>

#include "commands.h"
#include "dermis/offline/builtin_meshes.h"
#include "dermis/offline/domain_builder.h"
#include "dermis/offline/obj_io.h"
#include "dermis/surface/tessellation.h"

namespace dermis::cli {
namespace {

struct TessellateArgs {
  std::string input;
  std::string builtin;
  std::string output;
  int level = 8;
  std::string chart = "characteristic";
  std::string blend = "cinf";
  double blend_lb = DomainOptions{}.blend_lb;
  bool quiet = false;
};

int Fail(const Status& s) {
  std::fprintf(stderr, "dermis tessellate: error: %s\n", s.message().c_str());
  return kExitFailure;
}

int RunTessellate(const TessellateArgs& a) {
  const auto t0 = std::chrono::steady_clock::now();
  if (a.input.empty() == a.builtin.empty()) {
    std::fprintf(stderr,
                 "dermis tessellate: error: give exactly one of INPUT or --builtin NAME\n"
                 "Run 'dermis tessellate --help' for usage.\n");
    return kExitUsage;
  }
  PolygonMesh mesh;
  Status s = a.builtin.empty() ? ReadObj(a.input, &mesh) : MakeBuiltinMesh(a.builtin, &mesh);
  if (!s.ok()) return Fail(s);
  const Index dropped = CompactUnusedVertices(&mesh);
  if (dropped > 0 && !a.quiet) {
    std::fprintf(stderr,
                 "dermis tessellate: warning: %s: %d vertices are used by no face and were "
                 "ignored\n",
                 mesh.source_name.c_str(), dropped);
  }
  DomainOptions options;
  options.chart_type = a.chart == "complex"       ? ChartType::kFullyComplex
                       : a.chart == "isodistance" ? ChartType::kIsodistance
                                                  : ChartType::kCharacteristicMap;
  options.blend_type = a.blend == "c2" ? BlendType::kC2 : BlendType::kCInfinity;
  options.blend_lb = a.blend_lb;
  ControlSurface surface;
  s = BuildControlSurface(mesh, options, &surface);
  if (!s.ok()) return Fail(s);
  TessellationPattern pattern;
  s = TessellationPattern::Build(surface.domain->topology(), a.level, &pattern);
  if (!s.ok()) return Fail(s);
  std::vector<Vec3> positions(pattern.samples.size()), normals(pattern.samples.size());
  if (!EvaluateSamples(*surface.domain, surface.patches.data(), nullptr, pattern.samples.data(),
                       pattern.samples.size(), positions.data(), normals.data())) {
    return Fail(Status::Internal("a tessellation sample could not be evaluated"));
  }
  const std::filesystem::path out_path(a.output);
  if (out_path.has_parent_path()) {
    std::error_code ec;
    std::filesystem::create_directories(out_path.parent_path(), ec);
  }
  s = WriteObj(a.output, positions, normals, pattern.triangles,
               "dermis tessellate " + mesh.source_name + " --level " + std::to_string(a.level));
  if (!s.ok()) return Fail(s);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!a.quiet) {
    std::fprintf(stderr,
                 "dermis tessellate: %s: %d input vertices, %d control vertices, %d control quads "
                 "-> %zu vertices, %zu triangles at level %d in %.2f s\nwrote %s\n",
                 mesh.source_name.c_str(), mesh.num_vertices(), surface.domain->num_vertices(),
                 surface.domain->num_faces(), positions.size(), pattern.triangles.size() / 3,
                 a.level, seconds, a.output.c_str());
  }
  return kExitOk;
}

}  // namespace

void AddTessellateCommand(CLI::App* app, std::function<int()>* run) {
  auto args = std::make_shared<TessellateArgs>();
  CLI::App* cmd = app->add_subcommand(
      "tessellate",
      "Build the manifold surface of a polygon control mesh and write it tessellated as OBJ.");
  cmd->add_option("INPUT", args->input, "Control mesh: a polygon OBJ (triangles, quads, n-gons)");
  std::string names;
  for (const std::string& n : BuiltinMeshNames()) names += (names.empty() ? "" : ", ") + n;
  cmd->add_option("--builtin", args->builtin, "Use a built-in control mesh instead: " + names);
  cmd->add_option("-o,--output", args->output, "Output OBJ (positions, vn normals, triangles)")
      ->required();
  cmd->add_option("-l,--level", args->level, "Segments per control-face edge (>= 1)")
      ->check(CLI::Range(1, 4096))
      ->capture_default_str();
  cmd->add_option("--chart", args->chart, "Chart radial exponent")
      ->check(CLI::IsMember({"characteristic", "complex", "isodistance"}))
      ->capture_default_str();
  cmd->add_option("--blend", args->blend, "Partition-of-unity step: cinf or c2")
      ->check(CLI::IsMember({"cinf", "c2"}))
      ->capture_default_str();
  cmd->add_option("--blend-lb", args->blend_lb, "Blending window start lb in (0, 0.5); ub = 1 - lb")
      ->check(CLI::Range(1e-6, 0.499999))
      ->capture_default_str();
  cmd->add_flag("-q,--quiet", args->quiet, "Print nothing but errors");
  cmd->callback([run, args]() { *run = [args]() { return RunTessellate(*args); }; });
}

}  // namespace dermis::cli
