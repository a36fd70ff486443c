#include "cadastre/inspect/parcel_inputs.h"

#include "cadastre/parcels.h"
#include "core/config/config.h"
#include "core/io/crs.h"
#include "core/io/point_io.h"

namespace c3d {
namespace {

void reconcile(ParcelLayer& layer, std::vector<PointCloud>& clouds, std::vector<std::string>& warnings) {
  const CrsReconciliation crs = reconcile_crs(layer, clouds);
  warnings.insert(warnings.end(), crs.warnings.begin(), crs.warnings.end());
}

}  // namespace

ParcelLayer read_parcels_for_clouds(const std::string& path, const std::string& id_field,
                                    std::vector<PointCloud>& clouds, std::vector<std::string>& warnings) {
  ParcelLayer layer = read_parcels(path, parcel_fields(id_field), &warnings);
  reconcile(layer, clouds, warnings);
  return layer;
}

ParcelInputs read_parcel_inputs(const std::string& path, const std::string& id_field,
                                const std::vector<std::string>& cloud_paths) {
  ParcelInputs in;
  in.layer = read_parcels(path, parcel_fields(id_field), &in.warnings);
  for (const std::string& p : cloud_paths) in.clouds.push_back(read_point_cloud(p));
  reconcile(in.layer, in.clouds, in.warnings);
  return in;
}

}  // namespace c3d
