#pragma once
// How far apart a cloud's points lie: each point's distance to its nearest
// other point, summarised. Every meshing parameter of the ladder comes from
// these figures (seed 003's tables), none from a constant in metres.
#include <array>
#include <cstddef>
#include <vector>

#include "core/types.h"

namespace c3d {

struct PointSpacing {
  double min = 0, mean = 0, median = 0, p95 = 0, max = 0;  // m
  // The points' noise about their surface (m): the RMS distance of each
  // point's 16 nearest neighbours to their best plane, scaled by 16 / 13 for
  // the three parameters the plane takes, median over the points (a curved
  // surface or an edge raises a few points' figure, not the median's).
  double noise = 0;
  size_t points = 0;
};

// Copies of one place (distance 0) count once: their distance is to the next
// point elsewhere. Fewer than two distinct points: all zero; fewer than 16,
// no noise.
PointSpacing point_spacing(const std::vector<Vec3>& points);

// The points' (points[idx]'s, when idx is given) centre, principal axes,
// largest variance first, and their variances along them (m2).
struct PrincipalAxes {
  Vec3 centre = Vec3::Zero();
  std::array<Vec3, 3> axes{};
  Vec3 variance = Vec3::Zero();
};
PrincipalAxes principal_axes(const std::vector<Vec3>& points, const std::vector<int>& idx = {});

// How far the points spread along their principal axes: the square roots of
// their covariance's eigenvalues, largest first (m). A last one of nothing
// is a plane, a middle one of nothing a line.
Vec3 point_spread(const std::vector<Vec3>& points);

}  // namespace c3d
