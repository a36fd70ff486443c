#pragma once
// The batch's first step: every input read, reprojected into one CRS and
// split by class, and the batch's local frame.
#include <string>
#include <vector>

#include "cadastre/batch/batch.h"
#include "cadastre/batch/plausibility.h"
#include "cadastre/parcels.h"
#include "core/io/dtm_io.h"

namespace c3d {

struct LoadedInputs {
  ParcelLayer layer;
  Dtm dtm;
  std::vector<Vec3> roof, wall;  // world coordinates
  PointCoverage coverage;        // where the clouds have points of any class
  std::string crs_wkt;
  std::vector<std::string> warnings;
};

// Throws InputError naming the file when an input is unusable.
LoadedInputs load_inputs(const BatchInputs& inputs, const Config& cfg);

// Why parcel i cannot be modelled from these inputs (no point of the clouds
// near it, no DTM under it), or "".
std::string unreachable(const LoadedInputs& in, size_t i);

// The batch's local origin: the south-west corner of the layer, on a 10 m grid.
LocalFrame frame_of(const ParcelLayer& layer);

}  // namespace c3d
