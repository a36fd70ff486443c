// cadastre3d batch: the main job (see cli/batch.h).
#include "cli/batch.h"
#include "cli/commands.h"

namespace c3d::cli {

void register_batch(CLI::App& app) {
  auto opt = std::make_shared<BatchOptions>();
  auto* cmd = app.add_subcommand(
      "batch",
      "Parcel batch: point clouds + parcels + DTM -> LoD2 element models, cadastre.gpkg, "
      "summary.json, report.html/.csv, CityGML/CityJSON/IFC/OBJ");
  cmd->add_option("--cloud", opt->clouds, "Classified point cloud(s): LAS, PLY, PCD, XYZ/CSV")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--walls", opt->walls, "Wall-only point cloud(s) from a terrestrial scanner")
      ->check(CLI::ExistingFile);
  cmd->add_option("--parcels", opt->parcels, "Parcel layer (any OGR vector source)")
      ->required()
      ->check(CLI::ExistingPath);
  cmd->add_option("--dtm", opt->dtm, "Terrain model (any GDAL raster); default: from ground points")
      ->check(CLI::ExistingFile);
  cmd->add_option("--out", opt->out, "Output directory")->required();
  cmd->add_option("--config", opt->config, "TOML config (default: built-in, see config/)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--jobs", opt->jobs, "Parallel parcels (default: all cores)");
  cmd->add_option("--formats", opt->formats, "Exports: gml (CityGML 2.0) gml3 (CityGML 3.0) cityjson ifc obj step")
      ->delimiter(',');
  cmd->add_flag("--resume", opt->resume, "Skip parcels already stored from the same inputs");
  cmd->add_flag("--optimize", opt->optimize, "Refine element geometry with the GPU optimizer");
  cmd->add_option("--device", opt->device, "Optimizer device: auto, cpu or vulkan")
      ->check(CLI::IsMember({"auto", "cpu", "vulkan"}));
  cmd->add_flag("--quiet", opt->quiet, "Print nothing but errors");
  cmd->callback([opt] { exit_code() = run_batch(*opt); });
}

}  // namespace c3d::cli
