#pragma once
// Circular arcs in a roof's outline (docs/curved.md, "Round and apsed
// plans"): where a run of the roof's concave hull lies on one circle (a round
// tower, an apse, a rounded corner), the roof ends on that circle rather than
// on the polygon of straight edges the regulariser makes, if the points' edge
// follows the circle more closely than that polygon.
#include <vector>

#include "core/types.h"

namespace c3d {

// `polygon` (the regularised outline) with the runs of `hull` (the roof's
// concave hull, counter-clockwise) that lie on one circle made that circle's
// arcs, each radius read from the roof points of its sector, where the arc
// explains the points better than the straight edges (outline_likelihood in
// arcs.cpp). The circle is drawn in chords of sagitta `chord`, the ring
// holding the circle's area.
Polygon2 with_outline_arcs(const Ring2& hull, const Polygon2& polygon, const std::vector<Vec2>& points,
                           double spacing, double chord);

// The arcs drawn in a ring, read back from its vertices: per edge i (ring[i]
// -> ring[i + 1]) the index of the arc whose chord it is, or -1 for a
// straight edge, and each arc's circle. An arc is a run of at least five
// vertices turning left by at most 20 degrees each (a polygon's corners
// turn more), all on one circle within 5 mm; the chords to its ends are the
// arc's too.
struct DrawnArc {
  Vec2 centre = Vec2::Zero();
  double radius = 0;
};
struct RingArcs {
  std::vector<int> of_edge;
  std::vector<DrawnArc> arcs;
};
RingArcs arcs_in_ring(const Ring2& ring);

}  // namespace c3d
