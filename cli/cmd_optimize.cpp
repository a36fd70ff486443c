// TODO(owner of this command): replace this placeholder with the real command.
#include <iostream>

#include "cli/commands.h"

namespace c3d::cli {

void register_optimize(CLI::App& app) {
  auto* cmd = app.add_subcommand("optimize", "(not implemented yet)");
  cmd->callback([] {
    std::cerr << "cadastre3d optimize: not implemented yet\n";
    exit_code() = kExitError;
  });
}

}  // namespace c3d::cli
