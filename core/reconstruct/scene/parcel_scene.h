#pragma once
// What one parcel's reconstruction works on: its shape, its neighbours, the
// points that reach it and the terrain, in local coordinates. Made by the
// batch (cadastre/batch/scenes.h), read by every stage of core/reconstruct.
#include <functional>
#include <string>
#include <vector>

#include "core/reconstruct/scene/roof_density.h"
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

}  // namespace c3d
