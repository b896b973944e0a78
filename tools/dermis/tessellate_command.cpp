// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// dermis tessellate: polygon OBJ (or built-in mesh) -> manifold domain surface -> OBJ.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "character_args.h"
#include "commands.h"
#include "dermis/core/file_io.h"
#include "dermis/core/path.h"
#include "dermis/dsurf/dsurf.h"
#include "dermis/offline/build/domain_builder.h"
#include "dermis/offline/geometry/builtin_meshes.h"
#include "dermis/offline/io/obj_io.h"
#include "dermis/offline/io/ply_io.h"
#include "dermis/surface/tessellation.h"
#include "progress_bar.h"

namespace dermis::cli {
namespace {

constexpr const char* kTessellateCommand = "tessellate";

struct TessellateArgs {
  std::string input;
  std::string builtin;
  std::string output;
  int level = kDefaultLevel;
  std::string chart = "characteristic";
  std::string blend = "cinf";
  double blend_lb = DomainOptions{}.blend_lb;
  int displacement_levels = -1;
  bool quiet = false;
  // --chart, --blend and --blend-lb as given on the command line (set at parse time): a .dsurf
  // carries its own, so they are refused there rather than ignored.
  std::vector<std::string> domain_options;
  bool displacement_levels_given = false;  // refused without a .dsurf
};

bool IsDsurf(const std::string& path) { return LowerExtension(path) == ".dsurf"; }

Status WriteTessellation(const TessellateArgs& a, const ManifoldDomain& domain,
                         const LocalPatch* patches, const Displacement* displacement,
                         const std::string& header, std::size_t* vertices, std::size_t* triangles) {
  TessellationPattern pattern;
  Status s = TessellationPattern::Build(domain.topology(), a.level, &pattern);
  if (!s.ok()) return s;
  const std::size_t n = pattern.samples.size();
  std::vector<Vec3> positions(n), normals(n);
  // Progress (docs/cli.md, "Conventions"): the samples evaluated in 64 runs (each sample on
  // its own, so the result is the same), then the output as a stage and its time.
  ProgressBar progress(kTessellateCommand, a.quiet);
  const std::size_t run = std::max<std::size_t>(1, (n + 63) / 64);
  for (std::size_t begin = 0; begin < n; begin += run) {
    progress.Update("evaluating samples", begin, n);
    const std::size_t count = std::min(run, n - begin);
    if (!EvaluateSamples(domain, patches, displacement, pattern.samples.data() + begin, count,
                         positions.data() + begin, normals.data() + begin)) {
      progress.Clear();
      return Status::Internal("a tessellation sample could not be evaluated");
    }
  }
  progress.Update("writing the OBJ", 0, 0);
  *vertices = positions.size();
  *triangles = pattern.triangles.size() / 3;
  std::string text;
  s = FormatObj(positions, normals, pattern.triangles, header, &text);
  if (s.ok()) s = WriteOutput(a.output, text);
  progress.Clear();
  return s;
}

int RunTessellateDsurf(const TessellateArgs& a, std::chrono::steady_clock::time_point t0) {
  DisplacedSurface surface;
  Status s = ReadDsurf(a.input, &surface);
  if (!s.ok()) return Fail(kTessellateCommand, s);
  std::vector<LocalPatch> patches(surface.rest_positions.size());
  surface.domain->FitPatches(surface.rest_positions.data(), patches.data());
  const int available = surface.displacement ? surface.displacement->max_levels() : 0;
  const int levels = a.displacement_levels < 0 ? available : a.displacement_levels;
  std::unique_ptr<TruncatedDisplacement> truncated;
  if (surface.displacement) {
    truncated = std::make_unique<TruncatedDisplacement>(surface.displacement.get(), levels);
  }
  std::size_t nv = 0, nt = 0;
  s = WriteTessellation(a, *surface.domain, patches.data(), truncated.get(),
                        "dermis tessellate " + a.input + " --level " + std::to_string(a.level) +
                            " --displacement-levels " + std::to_string(levels),
                        &nv, &nt);
  if (!s.ok()) return Fail(kTessellateCommand, s);
  if (!a.quiet) {
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::fprintf(stderr,
                 "dermis tessellate: %s: %d control vertices, %d control quads, displacement "
                 "levels %d of %d -> %zu vertices, %zu triangles at level %d in %.2f s\nwrote %s\n",
                 a.input.c_str(), surface.domain->num_vertices(), surface.domain->num_faces(),
                 std::min(levels, available), available, nv, nt, a.level, seconds,
                 OutputName(a.output).c_str());
  }
  return kExitOk;
}

int RunTessellate(const TessellateArgs& a) {
  const auto t0 = std::chrono::steady_clock::now();
  if (a.input.empty() == a.builtin.empty()) {
    return Usage(kTessellateCommand, "give exactly one of INPUT or --builtin NAME");
  }
  if (IsDsurf(a.input)) {
    if (!a.domain_options.empty()) {
      std::string list;
      for (const std::string& o : a.domain_options) list += (list.empty() ? "" : ", ") + o;
      return Usage(kTessellateCommand, list + ": " + a.input +
                                           " carries its own charts and blending; these options "
                                           "apply to a control mesh (.obj, .ply, --builtin)");
    }
    return RunTessellateDsurf(a, t0);
  }
  if (a.displacement_levels_given) {
    return Usage(kTessellateCommand,
                 "--displacement-levels applies to a fitted surface (.dsurf); a control mesh "
                 "has no displacement");
  }
  PolygonMesh mesh;
  Status s;
  if (!a.builtin.empty()) {
    s = MakeBuiltinMesh(a.builtin, &mesh);
  } else if (const std::string ext = LowerExtension(a.input); ext == ".obj") {
    s = ReadObj(a.input, &mesh);
  } else if (ext == ".ply") {
    s = ReadPly(a.input, &mesh);
    if (s.ok() && mesh.num_faces() == 0) {
      s = Status::InvalidInput(a.input + ": no faces (a control mesh needs polygons)");
    }
  } else if (std::string probe; !(s = ReadFileBytes(a.input, "a control mesh", &probe)).ok()) {
    // missing, a directory, a device: the reader's message says which
  } else {
    s = Status::Unsupported(a.input + ": tessellate reads a control mesh (.obj, .ply) or a " +
                            ".dsurf, not '" + ext +
                            "' files (fit a glTF or other asset first: dermis fit)");
  }
  if (!s.ok()) return Fail(kTessellateCommand, s);
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
  if (!s.ok()) return Fail(kTessellateCommand, s);
  std::size_t nv = 0, nt = 0;
  s = WriteTessellation(
      a, *surface.domain, surface.patches.data(), nullptr,
      "dermis tessellate " + mesh.source_name + " --level " + std::to_string(a.level), &nv, &nt);
  if (!s.ok()) return Fail(kTessellateCommand, s);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!a.quiet) {
    std::fprintf(stderr,
                 "dermis tessellate: %s: %d input vertices, %d control vertices, %d control quads "
                 "-> %zu vertices, %zu triangles at level %d in %.2f s\nwrote %s\n",
                 mesh.source_name.c_str(), mesh.num_vertices(), surface.domain->num_vertices(),
                 surface.domain->num_faces(), nv, nt, a.level, seconds,
                 OutputName(a.output).c_str());
  }
  return kExitOk;
}

}  // namespace

void AddTessellateCommand(CLI::App* app, std::function<int()>* run) {
  auto args = std::make_shared<TessellateArgs>();
  CLI::App* cmd = app->add_subcommand(
      "tessellate",
      "Build the manifold surface of a polygon control mesh and write it tessellated as OBJ.");
  cmd->add_option("INPUT", args->input,
                  "Control mesh: a polygon OBJ or PLY (triangles, quads, n-gons), or a fitted "
                  "surface .dsurf (version 1 or 3; its charts and blending come from the file)");
  std::string names;
  for (const std::string& n : BuiltinMeshNames()) names += (names.empty() ? "" : ", ") + n;
  cmd->add_option("--builtin", args->builtin, "Use a built-in control mesh instead: " + names);
  cmd->add_option("-o,--output", args->output,
                  "Output OBJ (positions, vn normals, triangles); - writes it to stdout")
      ->required();
  AddLevelOption(cmd, &args->level, /*short_name=*/true);
  cmd->add_option("--chart", args->chart, "Chart radial exponent")
      ->check(CLI::IsMember({"characteristic", "complex", "isodistance"}))
      ->capture_default_str();
  cmd->add_option("--blend", args->blend, "Partition-of-unity step: cinf or c2")
      ->check(CLI::IsMember({"cinf", "c2"}))
      ->capture_default_str();
  cmd->add_option("--blend-lb", args->blend_lb, "Blending window start lb in (0, 0.5); ub = 1 - lb")
      ->check(CLI::Range(1e-6, 0.499999))
      ->capture_default_str();
  AddDisplacementLevelsOption(cmd, &args->displacement_levels);
  AddQuietFlag(cmd, &args->quiet);
  SetRunWithOutputs(
      cmd, run, kTessellateCommand, [args] { return std::vector<std::string>{args->output}; },
      [args] { return RunTessellate(*args); },
      [args, cmd] {
        args->domain_options.clear();
        for (const char* name : {"--chart", "--blend", "--blend-lb"}) {
          if (cmd->count(name) > 0) args->domain_options.push_back(name);
        }
        args->displacement_levels_given = cmd->count("--displacement-levels") > 0;
      },
      /*stdout_ok=*/true);
}

}  // namespace dermis::cli
