#pragma once
// Stage "roof mesh" (2D part): partitions a building outline into roof
// components. Cells are labelled by the nearest component points, then each
// shared boundary is replaced by the projected plane-plane intersection line
// (ridge, hip, valley) or, where the planes do not meet (a step between roof
// levels), by the straight line fitted to the boundary.
#include <vector>

#include "core/reconstruct/planes/planes.h"
#include "core/types.h"

namespace c3d {

struct RoofRegion {
  int component = 0;   // index into the segmentation's components
  Plane plane;
  MultiPolygon2 plan;  // 2D region, local coordinates
};

struct RoofPartitionInput {
  Polygon2 outline;
  std::vector<Vec2> points;   // labelled roof points of this building (plan)
  std::vector<int> labels;    // component index per point
  std::vector<int> components;             // component ids present
  std::vector<Plane> planes;               // plane per entry of `components`
  double cell = 0.1;
};

std::vector<RoofRegion> partition_roof(const RoofPartitionInput& in);

// Adds the roof points no plane took (texture, clutter; 3D, inside the
// outline) to the partition where they say which plane is over them: the one
// nearest their height, within `near`, with every other plane at least `gap`
// further (a lower annex where a higher roof's labels lie nearer in plan;
// between planes of about one height, at hips and ridges, texture would only
// scatter the labels). Returns how many were added.
size_t add_points_by_height(RoofPartitionInput& in, const std::vector<Vec3>& points, double near = 0.5,
                            double gap = 1.0);

// Makes rings that share boundaries share vertices: inserts any vertex lying on
// another ring's edge into that edge and welds vertices closer than tol.
void node_rings(std::vector<Ring2*>& rings, double tol);

// Four planes meet in one point only by chance. Where four regions share a
// vertex inside the outline and their planes' heights there disagree by more
// than the height weld (2 mm) absorbs, one point would leave four step walls on
// one vertical edge, which no solid can hold. The vertex becomes two three-plane
// points joined by a short edge on the line of two opposite planes (a pyramid's
// apex becomes a hip roof's ridge a few millimetres long): the pair whose
// three-plane points each fall on the side of their own third region.
// planes: one per region.
void split_four_plane_vertices(const Polygon2& outline, std::vector<MultiPolygon2>& regions,
                               const std::vector<Plane>& planes);

// Detached bits (< 1.5 m^2, not a region's largest part) of the regions of a
// partition go to the neighbour whose points they hold most of (the one sharing
// the most boundary when they hold none): a cut along one ridge carried past a
// junction of four planes leaves such bits on the wrong side, and they would
// become steps and tilted slivers in the roof. A bit its own points hold stays.
// region_of_point: per point, the index of its region in `regions`, or -1.
void absorb_fragments(std::vector<MultiPolygon2>& regions, const std::vector<Vec2>& points,
                      const std::vector<int>& region_of_point);

}  // namespace c3d
