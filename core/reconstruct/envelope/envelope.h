#pragma once
// Stage "envelope": from the partitioned roof to a building of elements.
// Wall points move each roof-outline edge inward to the wall they show
// (measured; a wall seen outside the outline moves it outward first, with
// grow_to_walls_outside, before the roof is partitioned); edges without wall
// points take the building's median measured overhang (propagated) or the
// configured default (default). Walls are
// extruded from the roof underside down to the terrain; the ground floor is the
// footprint at terrain level; the roof beyond the walls is the hanging roof,
// whose underside is the outer ceiling (a horizontal soffit at the lowest
// roof height of that piece, so its area is its plan area as DESIGN.md defines).
//
// Sub-stages, each with its header in this folder, run by build_building
// (envelope.cpp) in this order: wall_evidence (the wall under each outline
// edge) -> footprint -> roof_pieces (inside / hanging, in plan) -> roof_faces
// (lifted onto their planes; soffits) -> wall_faces and elements -> shell
// (welded and noded). Their internals live in namespace c3d::envelope.
#include <functional>
#include <vector>

#include "core/reconstruct/planes/planes.h"
#include "core/reconstruct/roof/roof.h"
#include "core/types.h"

namespace c3d {

// Wall evidence for one outline edge: offset (m, negative = inside the edge) of
// the wall seen by the scanner between heights min_z and max_z, with its
// support. found=false without evidence.
struct WallFit {
  bool found = false;
  double offset = 0;
  int support = 0;
  double rms = 0;
};

// A wall seen outside the roof outline, which the outline was grown onto
// (grow_to_walls_outside): the line it stands on and its fit.
struct WallOnOutline {
  Vec2 a, b;
  WallFit fit;
};

struct EnvelopeInput {
  std::string building_id;
  Polygon2 outline;                   // roof outline, counter-clockwise
  std::vector<RoofRegion> roof;       // partition of the outline
  std::vector<PlaneFit> fits;         // plane fit per roof region (same order)
  std::vector<Vec3> wall_points;      // local coordinates
  std::vector<Vec3> roof_points;      // the roof class, facades an airborne scan grazed included
  std::vector<bool> party_edge;       // per outline edge i (outer[i] -> outer[i+1])
  std::function<double(double, double)> terrain;  // local terrain z, NaN outside
  double default_overhang = 0.5;
  double storey_height = 3.0;
  double spacing = 0.2;               // roof point spacing, for boundary sigma
  std::vector<WallOnOutline> walls_on_outline;  // edges on these are their measured walls, flush
};

// A footprint that comes apart under one roof: the roof outline narrows to less
// than its overhangs (a walkway roof joining two houses), so the walls stand in
// separate rings and one solid cannot hold them. build_building models the
// largest part; the caller cuts the outline and models each part on its own.
struct FootprintApart {
  std::vector<Polygon2> parts;  // every part of at least kMinFootprintPart, largest first
  double overhang = 0;          // the widest overhang of the outline's edges, m
};
constexpr double kMinFootprintPart = 4.0;  // m^2: smaller parts are slivers, not houses

Building build_building(const EnvelopeInput& in, FootprintApart* apart = nullptr);

// The wall under footprint edge a -> b, from ground_z up to the underside of
// the roof pieces inside the walls whose edges lie on it (the highest where
// they overlap), meeting each piece at its own corners; no face (an empty
// ring) where no piece lies on the edge.
Face wall_under(const Vec2& a, const Vec2& b, double ground_z, const std::vector<Face>& inside_pieces);

// The outline grown out to the walls the scanner saw outside it (up to
// 0.6 m: a flush eave or parapet whose roof points are missing; farther out
// stands a fence or a neighbour), each such edge moved
// parallel onto its wall within `room` (the land this building may take); the
// outline itself where no wall stands outside it. A measured wall is where the
// floor ends, so the floor reaches it and the roof over it.
struct GrownOutline {
  Polygon2 outline;
  std::vector<WallOnOutline> walls;  // for EnvelopeInput::walls_on_outline
};
GrownOutline grow_to_walls_outside(const EnvelopeInput& in, const MultiPolygon2& room);

// The wall along edge a -> b seen in the wall points between min_z and max_z:
// the fullest peak of their offsets from the edge (negative: inside) that
// enough points show along enough of the edge; found=false where none does.
// beyond_ends: look only just past the edge's ends (the facade of attached
// neighbours continuing the same line), without the coverage check.
WallFit fit_wall(const std::vector<Vec3>& wall_points, const Vec2& a, const Vec2& b,
                 double min_z, double max_z, bool beyond_ends = false);

}  // namespace c3d
