#include "core/io/file_info.h"

#include <algorithm>
#include <filesystem>

#include "core/error.h"
#include "core/gdal_dataset.h"
#include "core/io/crs.h"

namespace c3d {

bool is_point_cloud_file(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
  static const std::array<const char*, 7> exts = {".las", ".laz", ".ply", ".pcd", ".xyz", ".txt", ".csv"};
  return std::find(exts.begin(), exts.end(), ext) != exts.end();
}

GdalContent gdal_content(const std::string& path) {
  register_gdal_drivers();
  CPLPushErrorHandler(CPLQuietErrorHandler);
  GdalDataset ds(GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_RASTER | GDAL_OF_READONLY));
  CPLPopErrorHandler();
  if (!ds) throw InputError(path, "neither a point cloud, a vector layer nor a raster");
  if (ds->GetLayerCount() > 0) return GdalContent::Vector;
  if (ds->GetRasterCount() > 0) return GdalContent::Raster;
  throw InputError(path, "holds no layer and no raster band");
}

CloudInfo describe_cloud(const PointCloud& cloud) {
  CloudInfo info;
  info.points = cloud.points.size();
  if (!cloud.points.empty()) {
    info.lo = info.hi = cloud.points[0];
    for (const Vec3& p : cloud.points) info.lo = info.lo.cwiseMin(p), info.hi = info.hi.cwiseMax(p);
  }
  for (uint8_t k : cloud.classes) ++info.class_counts[k];
  info.classified = cloud.classes.size();
  info.crs = crs_display_name(cloud.crs_wkt);
  return info;
}

RasterInfo describe_raster(const Dtm& d) {
  RasterInfo info;
  info.nx = d.nx;
  info.ny = d.ny;
  info.cell_x = d.dx;
  info.cell_y = -d.dy;
  info.x_min = d.x0 - 0.5 * d.dx;
  info.x_max = d.x0 + (d.nx - 0.5) * d.dx;
  info.y_min = d.y0 + (d.ny - 0.5) * d.dy;
  info.y_max = d.y0 - 0.5 * d.dy;
  info.nodata_share = d.nodata_share;
  info.crs = crs_display_name(d.crs_wkt);
  return info;
}

}  // namespace c3d
