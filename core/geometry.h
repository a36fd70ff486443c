#pragma once
// Small exact polygon measures shared by every stage (no library needed for
// these one-liners; heavy geometry lives with CGAL / GEOS in their stages).
#include <optional>

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

// Element totals of one building, as reported everywhere (summary, store,
// report, exports). sigma_* combine the element sigmas in quadrature.
struct BuildingTotals {
  double roof = 0, roof_plan = 0, wall = 0, party_wall = 0, ground = 0, outer_ceiling = 0;
  double sigma_roof = 0, sigma_wall = 0, sigma_party_wall = 0, sigma_ground = 0,
         sigma_outer_ceiling = 0;
  int roof_planes = 0;
};
BuildingTotals totals(const Building& b);

}  // namespace c3d
