// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Subcommands of the dermis command-line tool. Exit codes: 0 ok, 1 invalid input or failure,
// 2 usage error.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace dermis::cli {

constexpr int kExitOk = 0;
constexpr int kExitFailure = 1;
constexpr int kExitUsage = 2;

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

}  // namespace dermis::cli
