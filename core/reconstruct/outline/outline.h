#pragma once
// Stage "boundary": the outline of one roof from its points. GEOS concave hull,
// simplified, edges regularised to the building's dominant direction
// (parallel / square / 45 degree), and each edge placed where the point density
// drops to half (unbiased under noise, unlike the outermost points).
#include <vector>

#include "core/types.h"

namespace c3d {

struct OutlineOptions {
  double spacing = 0.2;          // point spacing, m
  double snap_angle_deg = 12.0;  // edges this close to an axis are snapped to it
  bool refine_orientation = true;  // turn the axes to where the edge likelihood is best
};

// The outline polygon (counter-clockwise, no holes); empty if the points do not
// make a polygon.
Polygon2 roof_outline(const std::vector<Vec2>& points, const OutlineOptions& opt);

// The length of a straight roof edge of `length` whose points place it: its
// ends belong to the corners (up to 0.5 m, or a fifth of it, each).
double sampled_edge_length(double length);

// Removes edges shorter than min_edge (chamfers, small jogs) and merges
// collinear edges; returns the input when that would change it by > 5 %.
Polygon2 regularize_polygon(const Polygon2& poly, double min_edge);

// Direction (radians, in [0, pi/2)) of the dominant edge orientation of a ring.
double dominant_direction(const Ring2& ring);

// Signed position of a straight edge estimated from point density across it:
// points with along-edge parameter in [t0, t1] and offset s (outward positive,
// relative to the line through `origin` with direction `dir`) are counted.
// Returns NaN when there are too few points.
double density_edge_offset(const std::vector<Vec2>& points, const Vec2& origin, const Vec2& dir,
                           double t0, double t1);

}  // namespace c3d
