// cadastre3d info FILE…: what a point cloud, parcel layer or raster holds, and
// whether the pipeline can use it (cadastre/inspect/file_info.h).
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "cadastre/inspect/file_info.h"
#include "cli/commands.h"

namespace c3d::cli {
namespace {

std::string grouped(unsigned long long n) {  // 244685 -> "244,685"
  std::string s = std::to_string(n);
  for (int i = int(s.size()) - 3; i > 0; i -= 3) s.insert(size_t(i), ",");
  return s;
}

std::string fixed(double v, int digits = 3) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

void print_cloud(const CloudInfo& c) {
  std::cout << "  kind:    point cloud\n  points:  " << grouped(c.points) << "\n";
  if (c.points)
    std::cout << "  bbox:    x " << fixed(c.lo.x()) << " .. " << fixed(c.hi.x()) << "\n"
              << "           y " << fixed(c.lo.y()) << " .. " << fixed(c.hi.y()) << "\n"
              << "           z " << fixed(c.lo.z()) << " .. " << fixed(c.hi.z()) << "\n";
  std::cout << (c.classified ? "  classes:\n" : "  classes: none in the file\n");
  for (int k = 0; k < 256; ++k)
    if (c.class_counts[k])
      std::cout << "    class " << k << ": " << grouped(c.class_counts[k]) << " ("
                << fixed(100.0 * c.class_counts[k] / c.classified, 1) << " %)\n";
  std::cout << "  CRS:     " << c.crs << "\n";
}

void print_parcels(const ParcelLayerInfo& p) {
  std::string fields;
  for (const std::string& f : p.fields) fields += (fields.empty() ? "" : ", ") + f;
  std::cout << "  kind:     parcel layer\n  parcels:  " << p.parcels << " (total area " << fixed(p.total_area, 1)
            << " m2)\n  fields:   " << fields << "\n  CRS:      " << p.crs << "\n  validity: "
            << p.parcels - p.repairs.size() << " valid, " << p.repairs.size() << " repaired by MakeValid\n";
  for (const ParcelRepair& r : p.repairs) std::cout << "    parcel " << r.id << ": " << r.note << "\n";
  for (const std::string& w : p.warnings) std::cout << "  warning: " << w << "\n";
}

void print_raster(const RasterInfo& r) {
  std::cout << "  kind:       raster (DTM, band 1)\n  size:       " << r.nx << " x " << r.ny
            << " cells\n  resolution: " << fixed(r.cell_x) << " x " << fixed(r.cell_y) << " m\n  extent:     x "
            << fixed(r.x_min) << " .. " << fixed(r.x_max) << ", y " << fixed(r.y_min) << " .. " << fixed(r.y_max)
            << "\n  NoData:     " << fixed(100.0 * r.nodata_share, 1) << " % of cells (filled for use)\n"
            << "  CRS:        " << r.crs << "\n";
}

void print_info(const std::string& path, const FileInfo& info) {
  std::cout << path << "\n";
  if (info.kind == FileInfo::Kind::Cloud) print_cloud(info.cloud);
  else if (info.kind == FileInfo::Kind::Parcels) print_parcels(info.parcels);
  else print_raster(info.raster);
}

}  // namespace

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
        print_info(f, describe_file(f));
      } catch (const std::exception& e) {
        std::cout << std::flush;
        std::cerr << "cadastre3d: error: " << e.what() << "\n";
        exit_code() = kExitError;
      }
    }
  });
}

}  // namespace c3d::cli
