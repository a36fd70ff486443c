#pragma once
// One parcel from points to buildings of elements: segment -> own (decided
// once into an Ownership the later steps query) -> plan the buildings (outline)
// -> per plan on a work list: partition -> envelope -> measure (a plan whose
// footprint comes apart is replaced by its houses) -> a building still invalid
// modelled again on the hull's axes, else as its LoD 1.2 prism (lod12.h) ->
// evaluate. Everything in local coordinates.
#include <functional>
#include <vector>

#include "core/config/config.h"
#include "core/reconstruct/roof_density.h"
#include "core/types.h"

namespace c3d {

struct ParcelScene {
  int parcel_index = 0;
  std::string parcel_id;
  MultiPolygon2 parcel;                    // this parcel, local coordinates
  std::vector<MultiPolygon2> neighbours;   // parcels near it, local coordinates
  std::vector<Vec3> roof_points;           // clipped with the overhang buffer + ownership context
  std::vector<Vec3> wall_points;           // clipped with the overhang buffer, at least kWallPointReachM
  std::function<double(double, double)> terrain;  // local terrain z, NaN outside
  double overhang_buffer_m = 1.6;          // how far an overhang may reach across the boundary
  double context_m = 3.1;                  // how far beyond the parcel roof_points reach
  RoofDensity roof_density;                // the scan's, by block; none known: this scene's own typical
};

// Never throws: a parcel that cannot be modelled comes back `failed` with a reason.
ParcelResult reconstruct_parcel(const ParcelScene& scene, const ReconstructionParams& p);

}  // namespace c3d
