// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// What every subcommand of the dermis tool shares: error and usage messages, output folders,
// --force (docs/cli.md, "Conventions").
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "commands.h"
#include "dermis/core/file_io.h"

namespace dermis::cli {

int Fail(const char* command, const Status& status) {
  std::fprintf(stderr, "dermis %s: error: %s\n", command, status.message().c_str());
  return kExitFailure;
}

int Usage(const char* command, const std::string& message) {
  std::fprintf(stderr, "dermis %s: error: %s\nRun 'dermis %s --help' for usage.\n", command,
               message.c_str(), command);
  return kExitUsage;
}

void MakeParentFolder(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  if (parent.empty()) return;
  std::error_code ec;
  std::filesystem::create_directories(parent, ec);
}

Status WriteOutput(const std::string& path, const std::string& bytes) {
  if (IsStdout(path)) {
    if (std::fwrite(bytes.data(), 1, bytes.size(), stdout) != bytes.size() ||
        std::fflush(stdout) != 0) {
      return Status::IoError("<stdout>: write failed");
    }
    return Status::Ok();
  }
  MakeParentFolder(path);
  return WriteFileAtomically(path, bytes);
}

void AddQuietFlag(CLI::App* cmd, bool* quiet) {
  cmd->add_flag("-q,--quiet", *quiet, "Print nothing but errors");
}

void AddThreadsOption(CLI::App* cmd, int* threads, const std::string& prefix) {
  cmd->add_option("--threads", *threads, prefix + "threads (0: all cores); results do not vary")
      ->check(CLI::Range(0, 1024))
      ->capture_default_str();
}

void SetRunWithOutputs(CLI::App* cmd, std::function<int()>* run, const char* command,
                       std::function<std::vector<std::string>()> outputs, std::function<int()> body,
                       std::function<void()> at_parse, bool stdout_ok) {
  auto force = AddForceFlag(cmd);
  cmd->callback([=]() {
    if (at_parse) at_parse();
    *run = [=]() {
      for (const std::string& p : outputs()) {
        if (p == "-" && !stdout_ok) {
          return Usage(command, std::string("'-o -' (stdout) is not supported by 'dermis ") +
                                    command + "': give a file name");
        }
      }
      const int rc = CheckOverwrite(command, outputs(), *force);
      return rc != kExitOk ? rc : body();
    };
  });
}

std::shared_ptr<bool> AddForceFlag(CLI::App* cmd) {
  auto force = std::make_shared<bool>(false);
  cmd->add_flag("-f,--force", *force, "Overwrite output files that exist");
  return force;
}

int CheckOverwrite(const std::string& command, const std::vector<std::string>& paths, bool force) {
  if (force) return kExitOk;
  for (const std::string& p : paths) {
    std::error_code ec;
    if (!p.empty() && p != "-" && std::filesystem::exists(p, ec)) {
      return Usage(command.c_str(), p + " exists; pass --force to overwrite it");
    }
  }
  return kExitOk;
}

}  // namespace dermis::cli
