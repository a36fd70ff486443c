// cadastre3d: LiDAR parcel batch -> LoD2 element models, store, valuation, exports.
#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <exception>
#include <iostream>

#include "cli/commands.h"
#include "core/gdal_messages.h"
#include "core/log.h"

namespace c3d::cli {
int& exit_code() {
  static int code = kExitOk;
  return code;
}
}  // namespace c3d::cli

int main(int argc, char** argv) {
  using namespace c3d::cli;
  GDALAllRegister();
  c3d::send_gdal_messages_to_debug_log();
  c3d::log::set_sink([](c3d::log::Level level, const std::string& message) {
    const char* kind = level == c3d::log::Level::Warn ? "warning: " : level == c3d::log::Level::Error ? "error: " : "";
    std::cerr << "cadastre3d: " << kind << message << "\n";
  });
  CLI::App app{"cadastre3d " C3D_VERSION
               " - element-based LoD2 building models for fiscal cadastre"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("cadastre3d ") + C3D_VERSION);
  app.add_flag_callback("--debug", [] { c3d::log::set_level(c3d::log::Level::Debug); },
                        "Log the reconstruction's debugging detail on stderr")
      ->trigger_on_parse();
  register_info(app);
  register_sample(app);
  register_clip(app);
  register_batch(app);
  register_evaluate(app);
  register_report(app);
  register_export(app);
  register_validate(app);
  register_optimize(app);
  register_mesh(app);
  register_classify(app);
  register_merge(app);
  register_slurm(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    int rc = app.exit(e);
    return rc == 0 ? 0 : kExitUsage;
  } catch (const std::exception& e) {
    std::cerr << "cadastre3d: error: " << e.what() << "\n";
    return kExitError;
  }
  return exit_code();
}
