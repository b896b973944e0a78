// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Subcommands of the dermis command-line tool. Exit codes: 0 ok, 1 invalid input or failure,
// 2 usage error.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "dermis/core/status.h"

namespace dermis::cli {

constexpr int kExitOk = 0;
constexpr int kExitFailure = 1;
constexpr int kExitUsage = 2;

/// Prints "dermis COMMAND: error: MESSAGE" (the status's message, which names the file) on
/// stderr and returns kExitFailure.
int Fail(const char* command, const Status& status);

/// Prints "dermis COMMAND: error: MESSAGE" and the hint "Run 'dermis COMMAND --help' for usage."
/// on stderr and returns kExitUsage.
int Usage(const char* command, const std::string& message);

/// Creates the folder that is to hold `path`, if it has one (errors show up when the file is
/// written).
void MakeParentFolder(const std::string& path);

/// True for the output path "-": the command writes to stdout (OBJ text or a GLB).
inline bool IsStdout(const std::string& path) { return path == "-"; }

/// Writes a complete output: to stdout for "-" (binary-safe, flushed; nothing else is written
/// there), otherwise atomically to `path` (its folder made). Errors name the path or <stdout>.
Status WriteOutput(const std::string& path, const std::string& bytes);

/// How an output path is shown in messages ("<stdout>" for "-").
inline std::string OutputName(const std::string& path) {
  return IsStdout(path) ? std::string("<stdout>") : path;
}

/// Adds -q,--quiet ("print nothing but errors") to `cmd`.
void AddQuietFlag(CLI::App* cmd, bool* quiet);

/// Adds --threads N (0: all cores) to `cmd`; `prefix` starts the help text (e.g. "--bake-sweep: ").
void AddThreadsOption(CLI::App* cmd, int* threads, const std::string& prefix = "");

/// Finishes a subcommand that writes files: adds -f,--force and sets its callback so that
/// `*run` refuses (CheckOverwrite) any of `outputs()` that exists unless --force is given, then
/// returns `body()`. `at_parse`, if set, runs when the subcommand is parsed. An output "-"
/// (stdout) is a usage error unless `stdout_ok` (commands whose format can stream: export's
/// GLB, tessellate's OBJ, animate's OBJ or GLB).
void SetRunWithOutputs(CLI::App* cmd, std::function<int()>* run, const char* command,
                       std::function<std::vector<std::string>()> outputs, std::function<int()> body,
                       std::function<void()> at_parse = nullptr, bool stdout_ok = false);

/// Adds -f,--force ("overwrite existing outputs") to `cmd`; the returned flag is set by parsing.
std::shared_ptr<bool> AddForceFlag(CLI::App* cmd);

/// The tool never overwrites a file without --force: if one of `paths` (empty ones ignored)
/// exists and `force` is false, prints "dermis COMMAND: error: PATH exists; pass --force to
/// overwrite it" with the usage hint and returns kExitUsage; otherwise kExitOk.
int CheckOverwrite(const std::string& command, const std::vector<std::string>& paths, bool force);

/// Registers `tessellate` on the app; `run` is set to the command's entry point.
void AddTessellateCommand(CLI::App* app, std::function<int()>* run);

/// Registers `fit`.
void AddFitCommand(CLI::App* app, std::function<int()>* run);

/// Registers `export`.
void AddExportCommand(CLI::App* app, std::function<int()>* run);

/// Registers `animate`.
void AddAnimateCommand(CLI::App* app, std::function<int()>* run);

/// Registers `render`.
void AddRenderCommand(CLI::App* app, std::function<int()>* run);

/// Registers `validate`.
void AddValidateCommand(CLI::App* app, std::function<int()>* run);

/// Registers `inspect`.
void AddInspectCommand(CLI::App* app, std::function<int()>* run);

/// Registers `pack`.
void AddPackCommand(CLI::App* app, std::function<int()>* run);

}  // namespace dermis::cli
