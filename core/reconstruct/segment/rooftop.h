#pragma once
// Planes standing on a roof (a lift or stair housing's lid, a plant box, a
// tank) are no part of the roof: they would widen its outline and add their
// sides as walls. Told apart by where they stand, not by their size in points.
#include <vector>

#include "core/reconstruct/segment/segmentation.h"

namespace c3d {

// Removes the components that stand on the roof; their points keep their
// roof but no label (clutter, as a tank's points are). A component stands on
// the roof when it is small and compact (a housing or a box, not a storey,
// not a strip along the roof), the roof planes it meets in plan (within a
// metre) lie 0.5 to 4 m below it (it meets none at its own height, as a
// dormer or an annex roof does), they surround it more than half the way
// round (a tower at a building's end meets the lower roof on one side), and
// no wall goes down under it (a parapet along a facade has one), and, where
// `terrain` (local terrain z at x, y; NaN unknown) is given, the roof it meets
// stands a storey above the terrain.
void drop_rooftop_objects(const std::vector<Vec3>& points, Segmentation& seg, const Terrain& terrain);

}  // namespace c3d
