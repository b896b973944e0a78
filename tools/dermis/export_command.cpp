// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// dermis export: a fitted character (.dsurf) -> skinned glTF, either the original topology
// evaluated on the displaced surface (bound) or the tessellated surface (lod); with
// --bake-sweep, every clip posed by a deformer of the control vertices and baked into morph
// targets of a static mesh.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "character_args.h"
#include "commands.h"
#include "dermis/offline/character/character_export.h"
#include "dermis/offline/character/character_pose.h"
#include "dermis/plugins/gltf.h"
#include "dermis/runtime/character.h"
#include "progress_bar.h"

namespace dermis::cli {
namespace {

constexpr const char* kExportCommand = "export";

struct ExportArgs {
  std::string input;
  std::string output;
  std::string mode = kDefaultMode;
  int level = kDefaultLevel;
  int displacement_levels = kAllDisplacementLevels;
  bool embed = false;
  int max_influences = 4;
  bool bake = false;
  double fps = kDefaultPoseStepsPerSecond;
  std::string deformer = "sweep";
  int threads = 0;
  bool quiet = false;
  bool quantize = false;
  bool compress = false;
};

/// One stderr line on what --quantize / --compress did (docs/gltf-compression.md).
void PrintPacking(const GltfExportReport& r) {
  if (r.quantized) {
    std::fprintf(stderr,
                 "dermis export: quantized (KHR_mesh_quantization): positions %d bits (step %.3g, "
                 "max error %.3g), normals max %.3g deg, weights max %.2g, uv max %.2g",
                 r.position_bits, r.position_step, r.max_position_error, r.max_normal_error_degrees,
                 r.max_weight_error, r.max_texcoord_error);
    if (r.float_target_accessors > 0) {
      std::fprintf(stderr, ", %zu morph normal accessors kept float32 (deltas beyond [-1, 1])",
                   r.float_target_accessors);
    }
    std::fprintf(stderr, "\n");
  }
  if (r.compressed) {
    std::fprintf(stderr,
                 "dermis export: compressed (EXT_meshopt_compression, required): %zu -> %zu "
                 "bytes of vertex, index and animation data",
                 r.bytes_before_compression, r.bytes_after_compression);
    if (r.filtered_target_accessors > 0) {
      std::fprintf(stderr, ", %zu float morph normal accessors filtered (max error %.2g)",
                   r.filtered_target_accessors, r.max_filtered_target_error);
    }
    std::fprintf(stderr, "\n");
  }
}

/// Vertex-frames above which the bake warns (24 bytes each: about 400 MB).
constexpr std::uint64_t kLargeBake = std::uint64_t{1} << 24;

/// The posed and baked asset of --bake-sweep.
Status Bake(const ExportArgs& a, const Character& ch, Asset* out, CharacterBakeReport* report) {
  CharacterPoseOptions options;
  Status s =
      MakePoseOptions(a.deformer, a.mode, a.level, a.displacement_levels, a.threads, &options);
  if (!s.ok()) return s;
  CharacterPoser poser;
  s = CharacterPoser::Build(ch, options, &poser);
  if (!s.ok()) return s;
  if (!a.quiet) {
    std::uint64_t frames = 0, vertices = 0;
    for (const AssetAnimation& clip : poser.asset().animations) {
      frames += ClipStepTimes(clip.Duration(), a.fps).size();
    }
    for (const DrawnPrimitive& d : poser.drawn()) {
      vertices += poser.asset()
                      .meshes[static_cast<std::size_t>(d.mesh)]
                      .primitives[static_cast<std::size_t>(d.primitive)]
                      .positions.size();
    }
    if (frames * vertices > kLargeBake) {
      std::fprintf(stderr,
                   "dermis export: warning: baking %llu frames of %llu vertices: about %.0f MB "
                   "of morph targets (lower --fps, or use --mode lod with a small --level)\n",
                   static_cast<unsigned long long>(frames),
                   static_cast<unsigned long long>(vertices),
                   24.0 * static_cast<double>(frames * vertices) / 1e6);
    }
  }
  ProgressBar bar(kExportCommand, a.quiet);
  return BuildBakedAsset(&poser, a.fps, out, report, bar.Callback());
}

int RunExport(const ExportArgs& a) {
  const bool to_stdout = a.output == "-";
  if (!to_stdout && !IsGltfPath(a.output)) {
    return Usage(kExportCommand,
                 a.output + ": the output must be .glb or .gltf (or - for a GLB on stdout)");
  }
  std::string bytes;
  Character ch;
  Status s = ReadCharacter(a.input, &ch, nullptr, &bytes);
  if (!s.ok()) return Fail(kExportCommand, s);
  CharacterExportOptions options;
  options.level = a.level;
  options.displacement_levels = a.displacement_levels;
  Asset out;
  std::vector<std::string> notes;
  CharacterBakeReport baked;
  if (a.bake) {
    s = Bake(a, ch, &out, &baked);
  } else if (a.mode == "bound") {
    s = BuildBoundAsset(ch, options, &out);
  } else {
    s = BuildLodAsset(ch, options, &out, &notes);
  }
  if (!s.ok()) return Fail(kExportCommand, s);
  GltfExportOptions gltf;
  gltf.max_influences = a.max_influences;
  gltf.generator = std::string("Dermis ") + DERMIS_VERSION;
  if (a.embed) gltf.dsurf_bytes = bytes;
  gltf.quantize = a.quantize;
  gltf.compress = a.compress;
  GltfExportReport packing;
  if (to_stdout) {
    // `-o -`: the GLB on stdout, written only once it is complete (nothing half-written).
    std::string glb;
    s = SerializeGltf(out, gltf, /*binary=*/true, &glb, &packing);
    if (!s.ok()) return Fail(kExportCommand, s);
    if (std::fwrite(glb.data(), 1, glb.size(), stdout) != glb.size() || std::fflush(stdout) != 0) {
      return Fail(kExportCommand, Status::IoError("<stdout>: write failed"));
    }
  } else {
    MakeParentFolder(a.output);
    s = ExportGltf(out, gltf, a.output, &packing);
    if (!s.ok()) return Fail(kExportCommand, s);
  }
  if (!a.quiet) {
    for (const std::string& n : notes) std::fprintf(stderr, "dermis export: note: %s\n", n.c_str());
    PrintPacking(packing);
    std::size_t vertices = 0;
    for (const AssetMesh& m : out.meshes) {
      for (const AssetPrimitive& p : m.primitives) vertices += p.positions.size();
    }
    if (a.bake) {
      std::string frames;
      for (std::size_t c = 0; c < baked.frames.size(); ++c) {
        frames += (c ? ", " : "") + std::to_string(baked.frames[c]);
      }
      std::fprintf(stderr,
                   "dermis export: %s mode baked with the %s deformer at %g fps: %zu clips (%s "
                   "frames), %zu morph targets on %zu meshes of %zu vertices, no skin%s\nwrote "
                   "%s\n",
                   a.mode.c_str(), a.deformer.c_str(), a.fps, out.animations.size(), frames.c_str(),
                   baked.targets, out.meshes.size(), vertices, a.embed ? ", .dsurf embedded" : "",
                   a.output.c_str());
    } else {
      std::fprintf(
          stderr,
          "dermis export: %s mode, %zu meshes, %zu vertices, %zu skins, %zu clips%s\nwrote %s\n",
          a.mode.c_str(), out.meshes.size(), vertices, out.skins.size(), out.animations.size(),
          a.embed ? ", .dsurf embedded" : "", a.output.c_str());
    }
  }
  return kExitOk;
}

}  // namespace

void AddExportCommand(CLI::App* app, std::function<int()>* run) {
  auto args = std::make_shared<ExportArgs>();
  CLI::App* cmd = app->add_subcommand(
      "export", "Export a fitted character (.dsurf) as a skinned glTF (.glb or .gltf).");
  cmd->add_option("INPUT", args->input, "Fitted character or surface (.dsurf)")->required();
  cmd->add_option("-o,--output", args->output, "Output .glb or .gltf; - writes the GLB to stdout")
      ->required();
  AddEvaluationOptions(cmd, "original topology, UVs and materials on the displaced surface",
                       &args->mode, &args->level, &args->displacement_levels);
  cmd->add_option("--max-influences", args->max_influences,
                  "Joint influences per vertex written (4 or 8; more are dropped, smallest first)")
      ->check(CLI::IsMember({4, 8}))
      ->capture_default_str();
  cmd->add_flag("--embed", args->embed,
                "Store the .dsurf in the glTF (extension DERMIS_displaced_surface) so that "
                "'dermis fit' reads it back losslessly");
  cmd->add_flag("--bake-sweep", args->bake,
                "Pose every clip with --deformer at --fps and bake the motion into morph targets "
                "of static meshes in world space (no skin; one weights animation per clip), so "
                "that any glTF viewer plays exactly the deformer's motion");
  cmd->add_option("--fps", args->fps, "--bake-sweep: frames per second of the bake")
      ->check(CLI::Range(0.001, 1000.0))
      ->capture_default_str();
  AddDeformerOption(cmd, "--deformer", "--bake-sweep: deformer of the control vertices",
                    &args->deformer)
      ->capture_default_str();
  cmd->add_flag("--quantize", args->quantize,
                "Store attributes as integers (KHR_mesh_quantization, required): positions on a "
                "grid chosen from the model (error reported), normals/tangents as 16-bit "
                "normalised, UVs/colours/weights as 16-bit normalised");
  cmd->add_flag("--compress", args->compress,
                "Encode vertex, index and animation data with meshoptimizer "
                "(EXT_meshopt_compression, required; three.js, Babylon.js and gltfpack read it, "
                "Assimp 5.2 does not)");
  AddThreadsOption(cmd, &args->threads, "--bake-sweep: ");
  AddQuietFlag(cmd, &args->quiet);
  SetRunWithOutputs(
      cmd, run, kExportCommand, [args] { return std::vector<std::string>{args->output}; },
      [args] { return RunExport(*args); }, nullptr, /*stdout_ok=*/true);
}

}  // namespace dermis::cli
