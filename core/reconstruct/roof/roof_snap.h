#pragma once
// The snapping half of the roof partition (roof_snap.cpp), called by
// partition_roof; internal to core/reconstruct/roof/.
#include <vector>

#include "core/reconstruct/planes/planes.h"
#include "core/types.h"

namespace c3d::roof {

// Vertices shared by regions whose planes meet are moved onto the exact
// intersection (ridge line, or the point where three or more planes meet), so
// neighbouring faces agree in 3D, not just in plan. planes: one per region.
void snap_to_intersections(const Polygon2& outline, std::vector<MultiPolygon2>& regions,
                           const std::vector<Plane>& planes);
// A region that snapping folded over itself keeps its shape from `before`.
void undo_folding_snaps(std::vector<MultiPolygon2>& regions, const std::vector<MultiPolygon2>& before);
// Snapping may make neighbours overlap slightly; an area belongs to one region only.
void remove_overlaps(std::vector<MultiPolygon2>& regions);

}  // namespace c3d::roof
