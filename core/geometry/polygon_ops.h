#pragma once
// 2D polygon logic for the reconstruction, done by GEOS (kept out of this
// header so stages only see plain Polygon2 data). Results are normalised:
// outer rings counter-clockwise, holes clockwise, empty pieces dropped.
#include <memory>
#include <vector>

#include "core/types.h"

namespace c3d::poly {

MultiPolygon2 unite(const MultiPolygon2& a, const MultiPolygon2& b);
MultiPolygon2 unite_all(const std::vector<MultiPolygon2>& parts);
MultiPolygon2 intersect(const MultiPolygon2& a, const MultiPolygon2& b);
MultiPolygon2 subtract(const MultiPolygon2& a, const MultiPolygon2& b);
// Buffer with mitred corners (keeps right angles square); negative shrinks
// (a valid multipolygon part by part: see polygon_ops.cpp).
MultiPolygon2 buffer(const MultiPolygon2& a, double distance);
// Buffer of a polyline (round ends) - corridors around boundaries.
MultiPolygon2 buffer_line(const std::vector<Vec2>& line, double distance);
MultiPolygon2 simplify(const MultiPolygon2& a, double tolerance);
// Douglas-Peucker simplification of a polyline.
std::vector<Vec2> simplify_line(const std::vector<Vec2>& line, double tolerance);
// The strip along one side of a polyline, |width| wide and cut square at its
// ends (single-sided buffer): left of the line's direction for width > 0.
MultiPolygon2 side_strip(const std::vector<Vec2>& line, double width);
MultiPolygon2 make_valid(const MultiPolygon2& a);
bool is_valid(const MultiPolygon2& a);
// GEOS ConcaveHull of points, edges no longer than max_edge (holes not allowed).
MultiPolygon2 concave_hull(const std::vector<Vec2>& points, double max_edge);
// The convex hull of points (empty for fewer than three not on a line).
MultiPolygon2 convex_hull(const std::vector<Vec2>& points);
// The polygon of largest area (an empty polygon for an empty input).
Polygon2 largest(const MultiPolygon2& mp);
// Drops polygons (and holes) smaller than min_area.
MultiPolygon2 drop_small(const MultiPolygon2& a, double min_area);
// Removes needle tips: vertices whose two edges leave them less than
// max_angle (radians) apart, repeatedly, so a sliver spike of no width left by
// an overlay (valid to GEOS, but welded shut later) goes.
MultiPolygon2 drop_needles(const MultiPolygon2& a, double max_angle);
// Point in polygon (boundary counts as inside).
bool covers(const MultiPolygon2& a, const Vec2& p);
// Distance from p to the polygon (0 inside).
double distance(const MultiPolygon2& a, const Vec2& p);
MultiPolygon2 box(const Vec2& min, const Vec2& max);
// Shared boundary of two polygons as line pieces (each a polyline): a's
// boundary within `tolerance` of b.
std::vector<std::vector<Vec2>> shared_boundary(const MultiPolygon2& a, const MultiPolygon2& b,
                                               double tolerance);
// The same against one b many times: b's zone is built once (shared_with(a)
// equals shared_boundary(a, b, tolerance)).
class NearZone {
 public:
  NearZone(const MultiPolygon2& b, double tolerance);
  ~NearZone();
  NearZone(NearZone&&) noexcept;
  NearZone& operator=(NearZone&&) noexcept;
  std::vector<std::vector<Vec2>> shared_with(const MultiPolygon2& a) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};
// Faces of the planar subdivision made by all rings of the given polygons:
// the boundaries are noded together and polygonized, so two faces that meet
// share the very same vertices along their common edge. With grid > 0 the
// noding is snap-rounded to that grid (GEOS OverlayNG): every vertex on it,
// and none nearer an edge it is not on than half a grid step.
MultiPolygon2 planar_faces(const MultiPolygon2& shapes, double grid = 0);
// A point strictly inside the polygon (GEOS interior point).
Vec2 interior_point(const Polygon2& p);
// Land outside `a` and `b`, within `reach` of b, that lies nearer to b than
// to a: how two neighbours split the land beyond their shared corner, whoever
// holds it (GEOS Voronoi cells of points every `step` along both boundaries).
// Empty where the two lie further than twice `reach` apart.
MultiPolygon2 nearer_to(const MultiPolygon2& b, const MultiPolygon2& a, double reach, double step);
MultiPolygon2 halfplane_box(const Vec2& point_on_line, const Vec2& dir, const Vec2& side_point,
                            double extent);

}  // namespace c3d::poly
