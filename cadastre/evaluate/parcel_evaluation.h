#pragma once
// A model measured against a cloud parcel by parcel, with the batch's ruler:
// every roof point inside a parcel against that parcel's roofs, every wall
// point within the reach of a parcel against that parcel's walls (so a wall
// point near two parcels counts for both).
#include <vector>

#include "core/evaluate/evaluate.h"
#include "core/evaluate/zones.h"
#include "core/io/mesh_io.h"
#include "core/types.h"

namespace c3d {

// One zone per parcel, in layer order. A face belongs to the parcel its group
// is named after ("<parcel id>_…", as the batch names its OBJ groups and
// element_groups() its elements), else to the parcel under its centroid, else
// to one whose reach holds the centroid; faces of no parcel are counted.
// Model and points in the layer's CRS.
ModelEvaluation evaluate_per_parcel(const std::vector<MeshGroup>& model, const RoofWallPoints& points,
                                    const ParcelLayer& layer, double wall_reach_m = kWallPointReachM);

}  // namespace c3d
