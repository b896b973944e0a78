// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// dermis pack: a fitted character (.dsurf of any version) -> runtime archive (a version-4
// .dsurf, docs/file-format.md "Runtime archives"), with the error it costs.
#include <cstdio>
#include <memory>
#include <string>

#include "commands.h"
#include "dermis/core/file_io.h"
#include "dermis/core/path.h"
#include "dermis/dsurf/dsurf.h"
#include "dermis/offline/character/runtime_archive.h"

namespace dermis::cli {
namespace {

constexpr const char* kPackCommand = "pack";

struct PackArgs {
  std::string input;
  std::string output;
  bool quantize = false;
  bool keep_source = false;
  int threads = 0;
  bool quiet = false;
};

int RunPack(const PackArgs& a) {
  if (LowerExtension(a.output) != ".dsurf") {
    return Usage(kPackCommand, a.output +
                                   ": the output must be .dsurf (a runtime archive is a "
                                   "version-4 .dsurf; e.g. NAME.runtime.dsurf)");
  }
  std::string bytes;
  Character ch;
  std::uint32_t version = 0;
  Status s = ReadCharacter(a.input, &ch, &version, &bytes);
  if (!s.ok()) return Fail(kPackCommand, s);
  RuntimeArchiveOptions options;
  options.quantize_displacements = a.quantize;
  options.keep_source = a.keep_source;
  std::string archive;
  RuntimeArchiveReport report;
  s = BuildRuntimeArchive(ch, options, a.threads, &archive, &report);
  if (!s.ok()) return Fail(kPackCommand, s);
  MakeParentFolder(a.output);
  s = WriteFileAtomically(a.output, archive);
  if (!s.ok()) return Fail(kPackCommand, s);
  if (!a.quiet) {
    const RuntimeArchiveError& e = report.error;
    std::fprintf(
        stderr,
        "dermis pack: %s (version %u, %zu bytes) -> runtime archive%s%s: %llu bytes "
        "(%.1f %%)\n",
        a.input.c_str(), version, bytes.size(), a.quantize ? ", 16-bit displacements" : "",
        a.keep_source ? ", source kept" : "", static_cast<unsigned long long>(report.bytes),
        bytes.empty()
            ? 0.0
            : 100.0 * static_cast<double>(report.bytes) / static_cast<double>(bytes.size()));
    for (const auto& section : report.sections) {
      std::fprintf(stderr, "  %-26s %10llu bytes\n", section.first.c_str(),
                   static_cast<unsigned long long>(section.second));
    }
    std::fprintf(stderr,
                 "error against the input at the rest pose, over the diagonal %.6g: level 8 "
                 "(%llu samples) max %.3g, mean %.3g; bound vertices (%llu) max %.3g\nwrote %s\n",
                 e.diagonal, static_cast<unsigned long long>(report.level8_samples), e.level8_max,
                 e.level8_mean, static_cast<unsigned long long>(report.bound_vertices), e.bound_max,
                 a.output.c_str());
  }
  return kExitOk;
}

}  // namespace

void AddPackCommand(CLI::App* app, std::function<int()>* run) {
  auto args = std::make_shared<PackArgs>();
  CLI::App* cmd = app->add_subcommand(
      "pack",
      "Pack a fitted character into a compact runtime archive (a version-4 .dsurf) for engines: "
      "the rig instead of the source asset, f32 and 16-bit storage, optionally 16-bit "
      "displacements; prints the bytes per section and the error it costs.");
  cmd->add_option("INPUT", args->input, "Fitted character or surface (.dsurf of any version)")
      ->required();
  cmd->add_option("-o,--output", args->output, "Output runtime archive (.dsurf)")->required();
  cmd->add_flag("--quantize-displacements", args->quantize,
                "Store displacement coefficients in 16 bits (per chart and level an offset and "
                "a scale)");
  cmd->add_flag("--keep-source", args->keep_source,
                "Keep the source asset (meshes, materials, images, clips) and the fit summaries, "
                "so that export, animate and render can read the archive");
  AddThreadsOption(cmd, &args->threads, "error measurement: ");
  AddQuietFlag(cmd, &args->quiet);
  SetRunWithOutputs(
      cmd, run, kPackCommand, [args] { return std::vector<std::string>{args->output}; },
      [args] { return RunPack(*args); });
}

}  // namespace dermis::cli
