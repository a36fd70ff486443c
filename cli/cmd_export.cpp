// TODO(owner of this command): replace this placeholder with the real command.
#include <iostream>

#include "cli/commands.h"

namespace c3d::cli {

void register_export(CLI::App& app) {
  auto* cmd = app.add_subcommand("export", "(not implemented yet)");
  cmd->callback([] {
    std::cerr << "cadastre3d export: not implemented yet\n";
    exit_code() = kExitError;
  });
}

}  // namespace c3d::cli
