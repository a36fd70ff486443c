#include "cadastre/inspect/parcel_inputs.h"

#include "cadastre/parcels.h"
#include "core/config/config.h"
#include "core/io/crs.h"

namespace c3d {

ParcelLayer read_parcels_for_clouds(const std::string& path, const std::string& id_field,
                                    std::vector<PointCloud>& clouds, std::vector<std::string>& warnings) {
  ParcelLayer layer = read_parcels(path, parcel_fields(id_field), &warnings);
  const CrsReconciliation crs = reconcile_crs(layer, clouds);
  warnings.insert(warnings.end(), crs.warnings.begin(), crs.warnings.end());
  return layer;
}

}  // namespace c3d
