#pragma once
// What a point cloud or a terrain raster holds, as `cadastre3d info` shows it,
// and which kind of file a path is.
#include <array>
#include <string>

#include "core/types.h"

namespace c3d {

// By the extension: .las .laz .ply .pcd .xyz .txt .csv (any case).
bool is_point_cloud_file(const std::string& path);

enum class GdalContent { Vector, Raster };
// Vector or raster: GDAL decides from the content, not the extension. Throws
// InputError when GDAL cannot open it or it holds neither.
GdalContent gdal_content(const std::string& path);

struct CloudInfo {
  size_t points = 0;
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();  // bounding box (zero without points)
  std::array<unsigned long long, 256> class_counts{};
  size_t classified = 0;  // points with a class: 0 when the file carries none
  std::string crs;        // display name ("(none)" without a CRS)
};
CloudInfo describe_cloud(const PointCloud& cloud);

struct RasterInfo {
  int nx = 0, ny = 0;                    // cells
  double cell_x = 0, cell_y = 0;         // cell size, m
  double x_min = 0, x_max = 0, y_min = 0, y_max = 0;  // outer edges of the grid
  double nodata_share = 0;               // before filling
  std::string crs;                       // display name
};
RasterInfo describe_raster(const Dtm& dtm);

}  // namespace c3d
