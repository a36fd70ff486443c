#pragma once
// A plane found by sampling (RANSAC) among points of which many may lie off
// it: a shed's roof with wall and ground hits of the same class under it,
// where a least-squares start is pulled off the roof by those and a trimmed
// refit never finds it again.
#include <vector>

#include "core/reconstruct/planes/planes.h"
#include "core/types.h"

namespace c3d {

struct PlaneSample {
  PlaneFit fit;              // least squares through `inliers`
  std::vector<int> inliers;  // of `idx`, within `tol` of the plane
};

// The plane through three of points[idx] that the most of them lie within
// `tol` of, among planes no steeper than acos(min_normal_z), refitted to its
// inliers. Deterministic: the triples come from a fixed seed. Empty inliers
// when idx holds fewer than three points or no such plane.
PlaneSample sample_plane_consensus(const std::vector<Vec3>& points, const std::vector<int>& idx, double tol,
                                   double min_normal_z);

// Plan area of the convex hull of points[idx].
double plan_hull_area(const std::vector<Vec3>& points, const std::vector<int>& idx);

}  // namespace c3d
