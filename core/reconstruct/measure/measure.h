#pragma once
// Stage 7 "measure": element areas, slope and azimuth, building volume, heights,
// storeys and solid validity (DESIGN.md, "Elements and how they are measured").
#include <vector>

#include "core/types.h"

namespace c3d {

// Fills area (true 3D area, holes subtracted; OuterCeiling: its plan area),
// plan_area, slope_deg (angle of the element plane to the horizontal, 0..90) and
// azimuth_deg (compass direction the outward normal faces, clockwise from grid
// north = +y, 0..360; 0 when flat, i.e. slope < 0.01 deg) from the faces.
// When boundary_sigma_m is given (not NaN), also sigma_area =
// sigma_area_from_plane(faces, rmse, support_points, boundary_sigma_m);
// otherwise sigma_area is left as it is.
void measure_element(Element& e, double boundary_sigma_m = kNaN);

// Measures every element (as above, sigma_area untouched), then fills:
//  volume        divergence theorem over b.solid (outward faces, holes allowed):
//                V = 1/3 sum_f (p_f . n_f) A_f, p_f a point of face f;
//  ridge_height  highest roof vertex above terrain_z;
//  eave_height   lowest roof vertex above terrain_z (the eave line: on an
//                overhanging roof, the lower edge of the overhang);
//                without roof elements both are the top of the solid;
//  storeys       max(1, round(eave_height / storey_height));
//  solid_valid / solid_problem from check_solid(b.solid).
void measure_building(Building& b, double storey_height = 3.0);

// Signed volume of a closed, outward oriented shell by the divergence theorem.
double closed_volume(const std::vector<Face>& shell);

// 1-sigma uncertainty of the area of coplanar faces whose outline was fixed in a
// projection plane (plan for roofs, elevation for walls) and whose plane was fitted
// to n_points points with residual rmse. Two independent parts, in quadrature:
//  plane:    the fitted tilt has sigma_t = rmse / sqrt(n * s2), s2 the variance
//            of the faces' area (uniform points) along the steepest direction;
//            A = A_proj / cos(a) with a = the angle to the projection plane
//            (min(slope, 90 - slope)), so sigma = A (tan(a) sigma_t + sigma_t^2 / 2)
//            (the second-order term keeps flat roofs from getting 0);
//  boundary: every edge displaced outward by boundary_sigma_m together (a
//            correlated outline error, conservative): sigma = perimeter * sigma_b.
// n_points < 3 or rmse <= 0 drops the plane part.
double sigma_area_from_plane(const std::vector<Face>& faces, double rmse, int n_points,
                             double boundary_sigma_m);
double sigma_area_from_plane(const Face& face, double rmse, int n_points,
                             double boundary_sigma_m);

}  // namespace c3d
