// cadastre3d info FILE…: what a point cloud, parcel layer or raster holds, and
// whether the pipeline can use it (cadastre/inspect/file_info.h).
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "cadastre/inspect/file_info.h"
#include "cli/commands.h"

namespace c3d::cli {

void register_info(CLI::App& app) {
  auto files = std::make_shared<std::vector<std::string>>();
  auto* cmd = app.add_subcommand(
      "info", "Describe point clouds (points, bbox, classes, CRS), parcel layers (count, "
              "fields, CRS, validity) and rasters (size, resolution, NoData share)");
  cmd->add_option("files", *files, "LAS/PLY/PCD/XYZ clouds, OGR vector layers, GDAL rasters")
      ->required();
  cmd->callback([files] {
    for (size_t i = 0; i < files->size(); ++i) {
      const std::string& f = (*files)[i];
      if (i) std::cout << "\n";
      try {
        std::cout << info_text(f, describe_file(f));
      } catch (const std::exception& e) {
        std::cout << std::flush;
        std::cerr << "cadastre3d: error: " << e.what() << "\n";
        exit_code() = kExitError;
      }
    }
  });
}

}  // namespace c3d::cli
