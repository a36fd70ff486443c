#pragma once
// Which parcel models which roof, and how a building meets its neighbours at
// the parcel boundary. Each parcel decides from its own scene, so the rules
// are written to reach the same answer from either side of a boundary:
// component ownership and the split cut (no roof modelled twice or by nobody),
// party edges (a wall shared with the neighbour's building), and roof edges
// hidden under a neighbour's higher eave.
#include <set>
#include <vector>

#include "core/reconstruct/reconstruct.h"
#include "core/reconstruct/segment/segmentation.h"

namespace c3d {

// The scan's typical roof points per cell of the size ownership counts roof
// in (the median over the cells holding any); 0 with no points.
int typical_roof_points_per_cell(const std::vector<Vec3>& roof_points);

// Gives away the components (or their parts across a boundary split with a
// neighbour) this parcel does not model; returns the neighbours split against.
std::set<int> apply_ownership(const ParcelScene& s, Segmentation& seg, const ReconstructionParams& p);

// The land a roof split with these neighbours may not reach.
MultiPolygon2 split_cut(const ParcelScene& s, const std::set<int>& split_with);

// The outline with a vertex added on an edge along the parcel boundary where
// the neighbour's roof across it ends, so the stretch meeting the neighbour's
// house and the stretch facing open land are decided apart.
Polygon2 split_where_neighbour_roof_ends(const Polygon2& outline, const ParcelScene& s, const std::vector<int>& label);

// Per outline edge (outer[i] -> outer[i+1]): a party edge, on the boundary
// with the neighbour's roof right across. `label` is the segmentation's.
std::vector<bool> find_party_edges(const Polygon2& outline, const ParcelScene& s, const std::vector<int>& label);

// The outline with its edges hidden under a neighbour's higher eave run on to
// the boundary, within `room`; the outline itself where none is.
Polygon2 grow_under_neighbour_eaves(const Polygon2& outline, const ParcelScene& s, const Segmentation& seg,
                                    const std::vector<int>& components, const MultiPolygon2& room);

}  // namespace c3d
