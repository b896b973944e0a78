// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Placeholder: being written.
#include "commands.h"

namespace dermis::cli {

void AddInspectCommand(CLI::App* app, std::function<int()>* run) {
  CLI::App* sub = app->add_subcommand("inspect", "Print what a file holds (not yet implemented)");
  sub->callback([run]() { *run = []() { return kExitFailure; }; });
}

}  // namespace dermis::cli
