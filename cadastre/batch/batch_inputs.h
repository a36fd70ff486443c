#pragma once
// The batch's first step: every input read, reprojected into one CRS and
// split by class, and the batch's local frame.
#include <string>
#include <vector>

#include "cadastre/batch/batch.h"
#include "cadastre/parcels.h"
#include "core/io/dtm_io.h"

namespace c3d {

struct LoadedInputs {
  ParcelLayer layer;
  Dtm dtm;
  std::vector<Vec3> roof, wall;  // world coordinates
  std::string crs_wkt;
  std::vector<std::string> warnings;
};

// Throws InputError naming the file when an input is unusable.
LoadedInputs load_inputs(const BatchInputs& inputs, const Config& cfg);

// The batch's local origin: the south-west corner of the layer, on a 10 m grid.
LocalFrame frame_of(const ParcelLayer& layer);

}  // namespace c3d
