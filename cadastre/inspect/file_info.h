#pragma once
// What an input file holds and whether the pipeline can use it (`cadastre3d
// info`): a point cloud, a parcel layer or a terrain raster.
#include <string>
#include <vector>

#include "core/io/file_info.h"

namespace c3d {

struct ParcelRepair {
  std::string id, note;  // the parcel and what MakeValid repaired
};

struct ParcelLayerInfo {
  size_t parcels = 0;
  double total_area = 0;  // m2
  std::vector<std::string> fields;
  std::string crs;  // display name
  std::vector<ParcelRepair> repairs;
  std::vector<std::string> warnings;  // from reading the layer
};
// Read with the default fields, as `info` shows a layer.
ParcelLayerInfo describe_parcel_layer(const std::string& path);

struct FileInfo {
  enum class Kind { Cloud, Parcels, Raster } kind = Kind::Cloud;
  CloudInfo cloud;          // for Kind::Cloud
  ParcelLayerInfo parcels;  // for Kind::Parcels
  RasterInfo raster;        // for Kind::Raster
};
// A point cloud by its extension, else whatever GDAL finds in it (a vector
// source is read as a parcel layer, a raster as a DTM). Throws InputError on a
// file that is none of these or cannot be read.
FileInfo describe_file(const std::string& path);

// The description `info` prints: the path, then one "  key: value" line each.
std::string info_text(const std::string& path, const FileInfo& info);

}  // namespace c3d
