// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The dermis command-line tool.
#include <cstdio>
#include <exception>
#include <functional>
#include <new>
#include <string>

#include "commands.h"

int main(int argc, char** argv) {
  CLI::App app{
      "dermis: displaced manifold surfaces (Yoon, \"A Surface Displaced from a Manifold\")",
      "dermis"};
  app.set_version_flag("--version", std::string("dermis ") + DERMIS_VERSION);
  app.require_subcommand(1);
  std::function<int()> run;
  dermis::cli::AddAnimateCommand(&app, &run);
  dermis::cli::AddExportCommand(&app, &run);
  dermis::cli::AddFitCommand(&app, &run);
  dermis::cli::AddInspectCommand(&app, &run);
  dermis::cli::AddPackCommand(&app, &run);
  dermis::cli::AddRenderCommand(&app, &run);
  dermis::cli::AddValidateCommand(&app, &run);
  dermis::cli::AddTessellateCommand(&app, &run);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::string sub;
    for (const CLI::App* s : app.get_subcommands()) sub = " " + s->get_name();
    std::fprintf(stderr, "dermis%s: error: %s\nRun 'dermis%s --help' for usage.\n", sub.c_str(),
                 e.what(), sub.c_str());
    return dermis::cli::kExitUsage;
  }
  if (!run) return dermis::cli::kExitUsage;
  // No exception leaves a command as an abort: out of memory, a library's exception or a bug all
  // end in exit 1 with a message (outputs are written atomically, so nothing half-written stays).
  std::string sub;
  for (const CLI::App* s : app.get_subcommands()) sub = " " + s->get_name();
  try {
    return run();
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr,
                 "dermis%s: error: out of memory (the input asks for more than this machine has)\n",
                 sub.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dermis%s: error: %s\n", sub.c_str(), e.what());
  } catch (...) {
    std::fprintf(stderr, "dermis%s: error: unexpected failure\n", sub.c_str());
  }
  return dermis::cli::kExitFailure;
}
