// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// dermis export: a fitted character (.dsurf) -> skinned glTF, either the original topology
// evaluated on the displaced surface (bound) or the tessellated surface (lod).
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "commands.h"
#include "dermis/core/file_bytes.h"
#include "dermis/offline/character.h"
#include "dermis/offline/character_export.h"
#include "dermis/plugins/gltf.h"
#include "dermis/plugins/import.h"

namespace dermis::cli {
namespace {

struct ExportArgs {
  std::string input;
  std::string output;
  std::string mode = "bound";
  int level = 4;
  int displacement_levels = -1;
  bool embed = false;
  int max_influences = 4;
  bool quiet = false;
};

int Fail(const Status& s) {
  std::fprintf(stderr, "dermis export: error: %s\n", s.message().c_str());
  return kExitFailure;
}

int RunExport(const ExportArgs& a) {
  if (!IsGltfPath(a.output)) {
    std::fprintf(stderr, "dermis export: error: %s: the output must be .glb or .gltf\n",
                 a.output.c_str());
    return kExitUsage;
  }
  std::string bytes;
  Status s = ReadFileBytes(a.input, "a .dsurf file", &bytes);
  if (!s.ok()) return Fail(s);
  Character ch;
  const std::uint32_t version = DsurfFileVersion(bytes);
  if (version == 1) {
    s = ReadCharacter(a.input, &ch);
  } else {
    s = ParseCharacter(bytes, a.input, &ch);
  }
  if (!s.ok()) return Fail(s);
  CharacterExportOptions options;
  options.level = a.level;
  options.displacement_levels = a.displacement_levels;
  Asset out;
  std::vector<std::string> notes;
  if (a.mode == "bound") {
    s = BuildBoundAsset(ch, options, &out);
  } else {
    s = BuildLodAsset(ch, options, &out, &notes);
  }
  if (!s.ok()) return Fail(s);
  GltfExportOptions gltf;
  gltf.max_influences = a.max_influences;
  gltf.generator = std::string("Dermis ") + DERMIS_VERSION;
  if (a.embed) gltf.dsurf_bytes = bytes;
  const std::filesystem::path parent = std::filesystem::path(a.output).parent_path();
  if (!parent.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(parent, ec);
  }
  s = ExportGltf(out, gltf, a.output);
  if (!s.ok()) return Fail(s);
  if (!a.quiet) {
    for (const std::string& n : notes) std::fprintf(stderr, "dermis export: note: %s\n", n.c_str());
    std::size_t vertices = 0;
    for (const AssetMesh& m : out.meshes) {
      for (const AssetPrimitive& p : m.primitives) vertices += p.positions.size();
    }
    std::fprintf(
        stderr,
        "dermis export: %s mode, %zu meshes, %zu vertices, %zu skins, %zu clips%s\nwrote %s\n",
        a.mode.c_str(), out.meshes.size(), vertices, out.skins.size(), out.animations.size(),
        a.embed ? ", .dsurf embedded" : "", a.output.c_str());
  }
  return kExitOk;
}

}  // namespace

void AddExportCommand(CLI::App* app, std::function<int()>* run) {
  auto args = std::make_shared<ExportArgs>();
  CLI::App* cmd = app->add_subcommand(
      "export", "Export a fitted character (.dsurf) as a skinned glTF (.glb or .gltf).");
  cmd->add_option("INPUT", args->input, "Fitted character or surface (.dsurf)")->required();
  cmd->add_option("-o,--output", args->output, "Output .glb or .gltf")->required();
  cmd->add_option("--mode", args->mode,
                  "bound: original topology, UVs and materials on the displaced surface; lod: "
                  "the surface tessellated at --level")
      ->check(CLI::IsMember({"bound", "lod"}))
      ->capture_default_str();
  cmd->add_option("--level", args->level, "lod: segments per control-face edge")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  cmd->add_option("--displacement-levels", args->displacement_levels,
                  "Displacement levels to evaluate (-1: all, 0: the domain surface)")
      ->check(CLI::Range(-1, 13))
      ->capture_default_str();
  cmd->add_option("--max-influences", args->max_influences,
                  "Joint influences per vertex written (4 or 8; more are dropped, smallest first)")
      ->check(CLI::IsMember({4, 8}))
      ->capture_default_str();
  cmd->add_flag("--embed", args->embed,
                "Store the .dsurf in the glTF (extension DERMIS_displaced_surface) so that "
                "'dermis fit' reads it back losslessly");
  cmd->add_flag("-q,--quiet", args->quiet, "Print nothing but errors");
  cmd->callback([run, args]() { *run = [args]() { return RunExport(*args); }; });
}

}  // namespace dermis::cli
