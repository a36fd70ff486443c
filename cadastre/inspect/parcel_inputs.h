#pragma once
// The parcel layer read as the batch reads it, with point clouds brought into its CRS.
#include <string>
#include <vector>

#include "core/types.h"

namespace c3d {

// Reads the layer (ids from id_field; "": the batch's, NIB where the layer has
// it, else the feature id) and reconciles the clouds with its CRS (see
// reconcile_crs: clouds may be reprojected). Reading and CRS notes are appended
// to warnings. Throws InputError on unreadable or irreconcilable inputs.
ParcelLayer read_parcels_for_clouds(const std::string& path, const std::string& id_field,
                                    std::vector<PointCloud>& clouds, std::vector<std::string>& warnings);

struct ParcelInputs {
  ParcelLayer layer;
  std::vector<PointCloud> clouds;     // in the layer's CRS
  std::vector<std::string> warnings;  // reading and CRS notes
};
// As read_parcels_for_clouds, reading the layer first (a bad layer is reported
// before any cloud is read), then the clouds.
ParcelInputs read_parcel_inputs(const std::string& path, const std::string& id_field,
                                const std::vector<std::string>& cloud_paths);

}  // namespace c3d
