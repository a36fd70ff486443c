// TODO(owner of this command): replace this placeholder with the real command.
#include <iostream>

#include "cli/commands.h"

namespace c3d::cli {

void register_evaluate(CLI::App& app) {
  auto* cmd = app.add_subcommand("evaluate", "(not implemented yet)");
  cmd->callback([] {
    std::cerr << "cadastre3d evaluate: not implemented yet\n";
    exit_code() = kExitError;
  });
}

}  // namespace c3d::cli
