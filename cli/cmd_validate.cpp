// TODO(owner of this command): replace this placeholder with the real command.
#include <iostream>

#include "cli/commands.h"

namespace c3d::cli {

void register_validate(CLI::App& app) {
  auto* cmd = app.add_subcommand("validate", "(not implemented yet)");
  cmd->callback([] {
    std::cerr << "cadastre3d validate: not implemented yet\n";
    exit_code() = kExitError;
  });
}

}  // namespace c3d::cli
