#pragma once
// Small exact polygon measures shared by every stage (no library needed for
// these one-liners; heavy geometry lives with CGAL / GEOS in their stages).
#include <algorithm>
#include <optional>
#include <utility>
#include <vector>

#include "core/types.h"

namespace c3d {

double signed_area(const Ring2& ring);           // > 0 counter-clockwise
double area(const Polygon2& p);                  // outer minus holes
double area(const MultiPolygon2& mp);
Vec3 newell_normal(const Ring3& ring);           // length = 2 * area
double area(const Ring3& ring);                  // true 3D area of a planar ring
double area(const Face& f);                      // minus holes
double plan_area(const Face& f);                 // horizontal projection
Vec3 unit_normal(const Face& f);
Ring2 to_2d(const Ring3& ring);
// Where the lines p + t d and q + s e meet (d, e unit); nullopt when they are
// parallel within 1e-6.
std::optional<Vec2> intersect_lines(const Vec2& p, const Vec2& d, const Vec2& q, const Vec2& e);

// Points every `step` along a polyline, its ends included: sums and fits over
// them weigh the line by its length, whatever vertices it is drawn with (a
// straight stretch may have two, a staircase one per step).
std::vector<Vec2> points_along(const std::vector<Vec2>& line, double step);

// Whether p lies inside `ring` in plan (even-odd crossings; a Ring3 is read
// by its x and y). No GEOS call: for tests per point in a loop.
template <class Ring>
bool in_ring_plan(const Ring& ring, const Vec2& p) {
  bool in = false;
  for (size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++)
    if ((ring[i].y() > p.y()) != (ring[j].y() > p.y()) &&
        p.x() < (ring[j].x() - ring[i].x()) * (p.y() - ring[i].y()) / (ring[j].y() - ring[i].y()) + ring[i].x())
      in = !in;
  return in;
}

// Whether p lies inside the polygon in plan: in its outer ring, in no hole
// (rings of fewer than 3 vertices hold nothing).
bool in_polygon_plan(const Polygon2& poly, const Vec2& p);

// Largest distance of a face's vertices (holes too) from their least-squares plane.
double planarity_deviation(const Face& f);

// The first pair of non-adjacent edges of a planar ring that touch or cross
// (projected along the largest component of its normal); nullopt for a simple ring.
std::optional<std::pair<size_t, size_t>> ring_crossing(const Ring3& ring, const Vec3& normal);

// The sigma of a sum of one building's elements: their sigma_shared parts
// add linearly (one error moves them all), the rest in quadrature.
struct SharedSigma {
  double own2 = 0, shared = 0;
  void add(const Element& e);
  void add(double own, double shared_part) { own2 += own * own, shared += shared_part; }
  double total() const;
};

// Element totals of one building, as reported everywhere (summary, store,
// report, exports). sigma_* combine the element sigmas as SharedSigma does.
struct BuildingTotals {
  double roof = 0, roof_plan = 0, wall = 0, party_wall = 0, ground = 0, outer_ceiling = 0;
  double sigma_roof = 0, sigma_wall = 0, sigma_party_wall = 0, sigma_ground = 0,
         sigma_outer_ceiling = 0;
  int roof_planes = 0;
};
BuildingTotals totals(const Building& b);

// The q-quantile (0..1) of ascending `sorted`, linear between ranks (numpy's
// default); 0 for none.
double quantile_of_sorted(const std::vector<double>& sorted, double q);

}  // namespace c3d
