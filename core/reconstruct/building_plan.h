#pragma once
// The buildings a parcel will model, planned from the roofs it keeps: one
// outline per group of touching roof outlines, cut where a shared roof is
// split with a neighbour, and the land each may still grow onto.
#include <vector>

#include "core/config/config.h"
#include "core/reconstruct/envelope/envelope.h"
#include "core/reconstruct/scene/parcel_scene.h"
#include "core/reconstruct/segment/segmentation.h"

namespace c3d {

constexpr double kNeedleAngle = 0.0175;  // rad (1 degree): sharper than any building's corner

struct BuildingPlan {
  Polygon2 outline;
  std::vector<int> components;
  MultiPolygon2 room;  // where the outline may grow to a wall seen outside it
};

// The buildings over the components `seg` keeps, none reaching into `cut`;
// loose roof points within `loose_reach` of a plane's widen the outlines.
// turn_axes: outlines on the axes their edges show, else on the hull's own.
std::vector<BuildingPlan> plan_buildings(const ParcelScene& s, const Segmentation& seg, const MultiPolygon2& cut,
                                         double loose_reach, bool turn_axes);

// The houses of a plan whose footprint came apart under its roof (`apart`),
// one plan each (see cut_at_narrows in building_plan.cpp); none where the
// outline does not cut into more than one.
std::vector<BuildingPlan> houses_under(const BuildingPlan& bp, const FootprintApart& apart);

}  // namespace c3d
