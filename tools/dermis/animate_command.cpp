// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// dermis animate: a fitted character (.dsurf) posed at one time of one clip: the control
// vertices deformed (sweep, LBS or DQS), the patches refitted, the displaced surface evaluated at
// the bound vertices or a tessellation, written in world space as OBJ or as a static glTF.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "character_args.h"
#include "commands.h"
#include "dermis/core/path.h"
#include "dermis/offline/character/character_pose.h"
#include "dermis/offline/character/skin_transfer.h"
#include "dermis/offline/io/obj_io.h"
#include "dermis/plugins/gltf.h"
#include "progress_bar.h"

namespace dermis::cli {
namespace {

constexpr const char* kAnimateCommand = "animate";

struct AnimateArgs {
  std::string input;
  std::string output;
  std::string clip;  // name or index; empty: clip 0, or the rest pose without clips
  double time = 0.0;
  bool time_given = false;
  std::string deformer = "sweep";
  std::string mode = kDefaultMode;
  int level = kDefaultLevel;
  int displacement_levels = kAllDisplacementLevels;
  double fps = kDefaultPoseStepsPerSecond;
  int threads = 0;
  bool quiet = false;
  std::string format;  // of `-o -`: obj or glb (default glb)
};

/// Shortest decimal form that reads back to the same double.
std::string FormatSeconds(double t) {
  char buffer[64];
  const auto r = std::to_chars(buffer, buffer + sizeof(buffer), t);
  return std::string(buffer, r.ptr);
}

/// Every triangle of the posed primitives as one OBJ (points and lines are not written), to
/// `path` or stdout ("-").
Status WritePosedObj(const std::string& path, const CharacterPoser& poser,
                     const std::vector<PosedPrimitive>& posed, const std::string& header,
                     std::size_t* skipped) {
  std::vector<Vec3> positions, normals;
  std::vector<std::uint32_t> triangles;
  *skipped = 0;
  for (std::size_t d = 0; d < posed.size(); ++d) {
    const DrawnPrimitive& dp = poser.drawn()[d];
    const AssetPrimitive& prim = poser.asset()
                                     .meshes[static_cast<std::size_t>(dp.mesh)]
                                     .primitives[static_cast<std::size_t>(dp.primitive)];
    const std::vector<std::uint32_t> tris = PrimitiveTriangles(prim);
    if (tris.empty()) {
      ++*skipped;
      continue;
    }
    const auto base = static_cast<std::uint32_t>(positions.size());
    positions.insert(positions.end(), posed[d].positions.begin(), posed[d].positions.end());
    normals.insert(normals.end(), posed[d].normals.begin(), posed[d].normals.end());
    for (const std::uint32_t i : tris) triangles.push_back(base + i);
  }
  std::string text;
  const Status s = FormatObj(positions, normals, triangles, header, &text);
  if (!s.ok()) return s.WithContext(OutputName(path));
  return WriteOutput(path, text);
}

int RunAnimate(const AnimateArgs& a) {
  const bool to_stdout = IsStdout(a.output);
  if (!a.format.empty() && !to_stdout) {
    return Usage(kAnimateCommand,
                 "--format applies to '-o -' (stdout); a file's format is its extension");
  }
  const bool obj = to_stdout ? a.format == "obj" : LowerExtension(a.output) == ".obj";
  if (!to_stdout && !obj && !IsGltfPath(a.output)) {
    return Usage(kAnimateCommand,
                 a.output + ": the output must be .obj, .glb or .gltf (or - for stdout)");
  }
  Character ch;
  Status s = ReadCharacter(a.input, &ch);
  if (!s.ok()) return Fail(kAnimateCommand, s);
  int clip = -1;
  s = ResolveClip(ch.asset, a.input, a.clip, &clip);
  if (!s.ok()) return Fail(kAnimateCommand, s);
  if (clip < 0 && a.time_given && a.time != 0.0) {
    return Fail(
        kAnimateCommand,
        Status::InvalidInput(a.input + ": --time applies to a clip, not to the rest pose (" +
                             ClipList(ch.asset) + ")"));
  }
  CharacterPoseOptions options;
  s = MakePoseOptions(a.deformer, a.mode, a.level, a.displacement_levels, a.threads, &options);
  if (!s.ok()) return Fail(kAnimateCommand, s);
  // Progress: the rest evaluation and the output have no count (a stage and its time), the
  // clip's pose steps have one.
  ProgressBar progress(kAnimateCommand, a.quiet);
  const auto fail = [&progress](const Status& status) {
    progress.Clear();  // the message on a line of its own
    return Fail(kAnimateCommand, status);
  };
  progress.Update("evaluating the rest surface", 0, 0);
  CharacterPoser poser;
  s = CharacterPoser::Build(ch, options, &poser);
  if (!s.ok()) return fail(s);
  std::vector<PosedPrimitive> posed;
  s = poser.PoseClip(clip, a.time, a.fps, &posed, progress.Callback());
  if (!s.ok()) return fail(s);
  progress.Update(obj ? "writing the OBJ" : "writing the glTF", 0, 0);

  const std::string what = clip < 0 ? std::string("rest pose")
                                    : "clip " + std::to_string(clip) + " '" +
                                          ch.asset.animations[static_cast<std::size_t>(clip)].name +
                                          "' at " + FormatSeconds(a.time) + " s";
  std::size_t skipped = 0;
  if (obj) {
    const std::string header = "dermis animate " + a.input + ": " + what + ", " + a.deformer +
                               ", " + a.mode + " mode (world space)";
    s = WritePosedObj(a.output, poser, posed, header, &skipped);
  } else {
    Asset out;
    s = BuildPosedAsset(poser, posed, &out);
    if (s.ok()) {
      GltfExportOptions gltf;
      gltf.generator = std::string("Dermis ") + DERMIS_VERSION;
      if (to_stdout) {
        // The GLB on stdout, written once complete (nothing half-written).
        std::string glb;
        s = SerializeGltf(out, gltf, /*binary=*/true, &glb);
        if (s.ok()) s = WriteOutput(a.output, glb);
      } else {
        MakeParentFolder(a.output);
        s = ExportGltf(out, gltf, a.output);
      }
    }
  }
  progress.Clear();
  if (!s.ok()) return Fail(kAnimateCommand, s);
  if (!a.quiet) {
    std::size_t vertices = 0;
    for (const PosedPrimitive& p : posed) vertices += p.positions.size();
    // SetPose() calls: the clip played from its start (the sweep's history).
    const std::string steps =
        clip < 0 ? std::string()
                 : " (" + std::to_string(ClipStepTimes(a.time, a.fps).size()) + " pose steps)";
    if (skipped > 0) {
      std::fprintf(stderr, "dermis animate: note: %zu point or line primitives are not in an OBJ\n",
                   skipped);
    }
    std::fprintf(stderr,
                 "dermis animate: %s, %s deformer%s, %s mode: %zu primitives, %zu vertices\nwrote "
                 "%s\n",
                 what.c_str(), a.deformer.c_str(), steps.c_str(), a.mode.c_str(), posed.size(),
                 vertices, OutputName(a.output).c_str());
  }
  return kExitOk;
}

}  // namespace

void AddAnimateCommand(CLI::App* app, std::function<int()>* run) {
  auto args = std::make_shared<AnimateArgs>();
  CLI::App* cmd = app->add_subcommand(
      "animate",
      "Pose a fitted character (.dsurf) at one time of a clip: control vertices deformed, patches "
      "refitted, the displaced surface evaluated; world space, as .obj, .glb or .gltf.");
  cmd->add_option("INPUT", args->input, "Fitted character (.dsurf)")->required();
  cmd->add_option("-o,--output", args->output,
                  "Posed mesh: .obj (with normals), .glb or .gltf; - writes it to stdout "
                  "(--format)")
      ->required();
  cmd->add_option("--format", args->format, "Format of '-o -' (stdout): glb (default) or obj")
      ->check(CLI::IsMember({"glb", "obj"}));
  cmd->add_option("--clip", args->clip,
                  "Clip name or index (default: 0, or the rest pose when there are no clips; "
                  "'rest': the rest pose)");
  cmd->add_option("--time", args->time,
                  "Seconds from the clip's start (past its end: its last keyframe)")
      ->check(CLI::Validator(
          [](std::string& value) {
            double t = -1.0;
            const auto r = std::from_chars(value.data(), value.data() + value.size(), t);
            const bool ok = r.ec == std::errc() && r.ptr == value.data() + value.size() &&
                            std::isfinite(t) && t >= 0.0;
            return ok ? std::string() : "'" + value + "' is not a number of seconds >= 0";
          },
          "SECONDS", "seconds"))
      ->capture_default_str();
  AddDeformerOption(cmd, "--deformer", "Deformer of the control vertices", &args->deformer)
      ->capture_default_str();
  AddEvaluationOptions(cmd, "the original vertices on the posed surface", &args->mode, &args->level,
                       &args->displacement_levels);
  cmd->add_option("--fps", args->fps,
                  "Steps per second at which the clip is played from its start to --time (the "
                  "sweep's twist unwrapping follows the motion; same steps as export --bake-sweep)")
      ->check(CLI::Range(0.001, 1000.0))
      ->capture_default_str();
  AddThreadsOption(cmd, &args->threads);
  AddQuietFlag(cmd, &args->quiet);
  CLI::Option* time = cmd->get_option("--time");
  SetRunWithOutputs(
      cmd, run, kAnimateCommand, [args] { return std::vector<std::string>{args->output}; },
      [args] { return RunAnimate(*args); }, [args, time] { args->time_given = time->count() > 0; },
      /*stdout_ok=*/true);
}

}  // namespace dermis::cli
