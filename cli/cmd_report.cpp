// cadastre3d report --store OUT/cadastre.gpkg --out DIR [--config FILE]
// Writes DIR/report.html (summary), DIR/report/ (detail pages, one printable
// page per parcel) and DIR/report.csv from the store alone. With --config
// the stored model is valued again with that file's valuation section.
#include <filesystem>
#include <iostream>
#include <memory>

#include "cadastre/batch/out_dir.h"
#include "cli/commands.h"
#include "core/config/config.h"
#include "cadastre/report/report.h"

namespace c3d::cli {

void register_report(CLI::App& app) {
  struct Args {
    std::string store, out, config;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("report", "Write the report (report.html, report/, report.csv) from a store");
  cmd->add_option("--store", args->store, "Cadastre3D store (cadastre.gpkg or postgresql://...)")
      ->required()
      ->check(existing_store);
  cmd->add_option("--out", args->out, "Output directory")->required();
  cmd->add_option("--config", args->config, "Re-value with this config (TOML)")
      ->check(CLI::ExistingFile);
  cmd->callback([args] {
    bool revalue = !args->config.empty();
    Config cfg = revalue ? load_config(args->config) : default_config();
    write_staged_into(
        args->out, [&](const std::string& stage) { write_report_from_store(args->store, stage, cfg, revalue); },
        {"report"});
    namespace fs = std::filesystem;
    std::cout << "report: " << (fs::path(args->out) / "report.html").string() << "\n"
              << "pages:  " << (fs::path(args->out) / "report").string() << "/\n"
              << "csv:    " << (fs::path(args->out) / "report.csv").string() << "\n";
    exit_code() = kExitOk;
  });
}

}  // namespace c3d::cli
