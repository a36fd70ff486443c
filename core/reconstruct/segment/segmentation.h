#pragma once
// Stage "segment": individual roofs (connected roof point clusters) and, within
// each roof, planar roof components (PCL region growing; a second pass over the
// points the first left, on smoothed normals, for textured sheet), cleaned so
// clutter (antennas, tanks, vegetation) does not become roof planes.
#include <functional>
#include <vector>

#include "core/config/config.h"
#include "core/reconstruct/planes/planes.h"
#include "core/types.h"

namespace c3d {

struct RoofComponent {
  std::vector<int> points;  // indices into the segmented point list
  PlaneFit fit;
  int roof = 0;             // individual roof it belongs to
  int min_points = 0;       // fewest points a part of it is a plane with (0: min_component_points):
                            // min_plane_points at the scan's density
};

struct Segmentation {
  std::vector<RoofComponent> components;
  int roof_count = 0;
  std::vector<int> label;   // per point: component index or -1 (outlier / clutter)
  std::vector<int> roof_of; // per point: individual roof, or -1 (outlier, a roof with no component,
                            // a steep surface no plane took, a point ownership gave away)
  double spacing = 0.2;     // median nearest-neighbour distance in plan, m, of the places (copies
                            // folded), at least 0.5 / sqrt(density) (points on scan rows)
  double density = 0;       // median points per m2 around a place (0: too few points to tell)
};

constexpr int kMinPlanePoints = 10;  // fewer points judge no plane, at any density

// The fewest points a roof plane needs at `density` points/m2: those a patch of
// min_component_area_m2 holds, never more than min_component_points (a dense
// scan's patch is held to its area) nor fewer than a plane can be judged on.
int min_plane_points(double density, const ReconstructionParams& p);

// Copies of a point (within kSamePlaceM) are segmented as one place and share
// its labels; a component holds every copy of its places. A component is kept
// with min_plane_points(density) points covering min_component_area_m2 at the
// measured density.
// Planes standing on a roof are dropped (drop_rooftop_objects, `terrain` its
// local terrain z, empty: unknown).
using Terrain = std::function<double(double, double)>;
Segmentation segment_roofs(const std::vector<Vec3>& points, const ReconstructionParams& p,
                           const Terrain& terrain = {});

// Per individual roof, its loose points: points of the roof no plane took
// (textured tiles, corrugation, gutters, small features) that lie within
// `reach` (in plan) of a point some plane did take. They are roof all the same
// and belong inside its outline; points further out are clutter beside it.
std::vector<std::vector<int>> loose_roof_points(const std::vector<Vec3>& points, const Segmentation& seg,
                                                double reach);

}  // namespace c3d
