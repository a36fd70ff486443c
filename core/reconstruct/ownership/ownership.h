#pragma once
// Stage "ownership": which parcel models which roof, and how a building meets
// its neighbours at the parcel boundary. Decided once, right after
// segmentation, into an Ownership value; the later stages ask it about an
// outline (party edges, where a neighbour's roof ends, a neighbour's eave
// over this roof) and never go back to the scene. Each parcel decides from
// its own scene, so the rules are written to reach the same answer from
// either side of a boundary: component ownership and the split cut (no roof
// modelled twice or by nobody), party edges (a wall shared with the
// neighbour's building), and roof edges hidden under a neighbour's higher eave.
#include <set>
#include <map>
#include <utility>
#include <vector>

#include "core/reconstruct/ownership/point_grid.h"
#include "core/config/config.h"
#include "core/reconstruct/scene/parcel_scene.h"
#include "core/reconstruct/segment/segmentation.h"

namespace c3d {

struct Ownership {
  // Who models what. Per scene roof point, as in Segmentation: the component
  // this parcel models it in (-1: another's, an outlier, or a part too small
  // for a plane, left to the roof's loose points) and its roof (-1: another's).
  std::vector<int> label, roof_of;
  std::vector<std::vector<int>> component_points;  // per component, the points this parcel keeps
  std::set<int> split_with;  // neighbours a shared roof is split against (indices into `neighbours`)
  MultiPolygon2 cut;         // the land a roof split with them may not reach

  // The boundary the queries below look at, copied from the scene.
  MultiPolygon2 parcel;
  MultiPolygon2 parcel_core;  // the parcel less its boundary strip
  std::vector<MultiPolygon2> neighbours;
  std::vector<Vec3> roof_points, wall_points;  // the scene's, in its order
  PointGrid roof_grid, wall_grid;              // the same points by plan cell
};

// The scan's typical roof points per cell of the size ownership counts roof
// in (the median over the cells holding any); 0 with no points.
int typical_roof_points_per_cell(const std::vector<Vec3>& roof_points);
// The same for a scan counted a part at a time: the cell a plan point counts
// in, and the typical count from a histogram (points in a cell -> cells).
std::pair<long, long> roof_cell(const Vec2& q);
int typical_roof_points_per_cell(const std::map<int, size_t>& cells_by_count);

// Decides, from the scene and its segmentation, what this parcel models.
Ownership decide_ownership(const ParcelScene& s, const Segmentation& seg, const ReconstructionParams& p);

// `seg` with what this parcel does not model taken out (labels, roofs and
// component points as `own` keeps them; planes as fitted before).
Segmentation kept_segmentation(const Segmentation& seg, const Ownership& own);

// The outline with a vertex added on an edge along the parcel boundary where
// the neighbour's roof across it ends, so the stretch meeting the neighbour's
// house and the stretch facing open land are decided apart.
Polygon2 split_where_neighbour_roof_ends(const Polygon2& outline, const Ownership& own);

// Per outline edge (outer[i] -> outer[i+1]): a party edge, on the boundary
// with the neighbour's roof right across.
std::vector<bool> find_party_edges(const Polygon2& outline, const Ownership& own);

// The outline of a building on roofs `roofs` with its edges hidden under a
// neighbour's higher eave run on to the boundary, within `room`; the outline
// itself where none is.
Polygon2 grow_under_neighbour_eaves(const Polygon2& outline, const Ownership& own, const std::set<int>& roofs,
                                    const MultiPolygon2& room);

}  // namespace c3d
