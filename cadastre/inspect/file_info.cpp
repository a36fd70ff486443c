#include "cadastre/inspect/file_info.h"

#include "cadastre/parcels.h"
#include "core/geometry/geometry.h"
#include "core/io/crs.h"
#include "core/io/dtm_io.h"
#include "core/io/point_io.h"

namespace c3d {

ParcelLayerInfo describe_parcel_layer(const std::string& path) {
  ParcelLayerInfo info;
  const ParcelLayer layer = read_parcels(path, ParcelFields{}, &info.warnings);
  info.parcels = layer.parcels.size();
  for (const Parcel& p : layer.parcels) {
    if (!p.repair_note.empty()) info.repairs.push_back({p.id, p.repair_note});
    info.total_area += area(p.shape);
  }
  info.fields = layer.fields;
  info.crs = crs_display_name(layer.crs_wkt);
  return info;
}

FileInfo describe_file(const std::string& path) {
  FileInfo info;
  if (is_point_cloud_file(path)) {
    info.kind = FileInfo::Kind::Cloud;
    info.cloud = describe_cloud(read_point_cloud(path));
  } else if (gdal_content(path) == GdalContent::Vector) {
    info.kind = FileInfo::Kind::Parcels;
    info.parcels = describe_parcel_layer(path);
  } else {
    info.kind = FileInfo::Kind::Raster;
    info.raster = describe_raster(read_dtm(path));
  }
  return info;
}

}  // namespace c3d
