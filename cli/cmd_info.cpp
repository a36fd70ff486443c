// cadastre3d info FILE…: what a point cloud, parcel layer or raster holds, and
// whether the pipeline can use it.
#include <gdal_priv.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "cadastre/parcels.h"
#include "cli/commands.h"
#include "core/io/crs.h"
#include "core/io/dtm_io.h"
#include "core/error.h"
#include "core/geometry/geometry.h"
#include "core/io/point_io.h"

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

bool is_point_cloud(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
  static const std::array<const char*, 7> exts = {".las", ".laz", ".ply", ".pcd",
                                                  ".xyz", ".txt", ".csv"};
  return std::find(exts.begin(), exts.end(), ext) != exts.end();
}

void info_cloud(const std::string& path) {
  PointCloud c = read_point_cloud(path);
  std::cout << path << "\n  kind:    point cloud\n  points:  " << grouped(c.points.size())
            << "\n";
  if (!c.points.empty()) {
    Vec3 lo = c.points[0], hi = c.points[0];
    for (const Vec3& p : c.points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    std::cout << "  bbox:    x " << fixed(lo.x()) << " .. " << fixed(hi.x()) << "\n"
              << "           y " << fixed(lo.y()) << " .. " << fixed(hi.y()) << "\n"
              << "           z " << fixed(lo.z()) << " .. " << fixed(hi.z()) << "\n";
  }
  if (c.classes.empty()) {
    std::cout << "  classes: none in the file\n";
  } else {
    std::array<unsigned long long, 256> count{};
    for (uint8_t k : c.classes) ++count[k];
    std::cout << "  classes:\n";
    for (int k = 0; k < 256; ++k)
      if (count[k])
        std::cout << "    class " << k << ": " << grouped(count[k]) << " ("
                  << fixed(100.0 * count[k] / c.classes.size(), 1) << " %)\n";
  }
  std::cout << "  CRS:     " << crs_display_name(c.crs_wkt) << "\n";
}

void info_parcels(const std::string& path) {
  std::vector<std::string> warnings;
  ParcelLayer layer = read_parcels(path, ParcelFields{}, &warnings);
  int repaired = 0;
  double total = 0;
  for (const Parcel& p : layer.parcels) {
    repaired += !p.repair_note.empty();
    total += area(p.shape);
  }
  std::string fields;
  for (const std::string& f : layer.fields) fields += (fields.empty() ? "" : ", ") + f;
  std::cout << path << "\n  kind:     parcel layer\n  parcels:  " << layer.parcels.size()
            << " (total area " << fixed(total, 1) << " m2)\n  fields:   " << fields
            << "\n  CRS:      " << crs_display_name(layer.crs_wkt) << "\n  validity: "
            << layer.parcels.size() - repaired << " valid, " << repaired
            << " repaired by MakeValid\n";
  for (const Parcel& p : layer.parcels)
    if (!p.repair_note.empty()) std::cout << "    parcel " << p.id << ": " << p.repair_note << "\n";
  for (const std::string& w : warnings) std::cout << "  warning: " << w << "\n";
}

void info_raster(const std::string& path) {
  Dtm d = read_dtm(path);
  std::cout << path << "\n  kind:       raster (DTM, band 1)\n  size:       " << d.nx << " x "
            << d.ny << " cells\n  resolution: " << fixed(d.dx) << " x " << fixed(-d.dy)
            << " m\n  extent:     x " << fixed(d.x0 - 0.5 * d.dx) << " .. "
            << fixed(d.x0 + (d.nx - 0.5) * d.dx) << ", y " << fixed(d.y0 + (d.ny - 0.5) * d.dy)
            << " .. " << fixed(d.y0 - 0.5 * d.dy) << "\n  NoData:     "
            << fixed(100.0 * d.nodata_share, 1) << " % of cells (filled for use)\n  CRS:        "
            << crs_display_name(d.crs_wkt) << "\n";
}

// Vector or raster: GDAL decides from the content, not the extension.
void info_gdal(const std::string& path) {
  CPLPushErrorHandler(CPLQuietErrorHandler);
  GDALDataset* ds =
      GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_RASTER | GDAL_OF_READONLY);
  CPLPopErrorHandler();
  if (!ds) throw InputError(path, "neither a point cloud, a vector layer nor a raster");
  bool vector = ds->GetLayerCount() > 0, raster = ds->GetRasterCount() > 0;
  GDALClose(ds);
  if (vector) return info_parcels(path);
  if (raster) return info_raster(path);
  throw InputError(path, "holds no layer and no raster band");
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
        if (is_point_cloud(f))
          info_cloud(f);
        else
          info_gdal(f);
      } catch (const std::exception& e) {
        std::cout << std::flush;
        std::cerr << "cadastre3d: error: " << e.what() << "\n";
        exit_code() = kExitError;
      }
    }
  });
}

}  // namespace c3d::cli
