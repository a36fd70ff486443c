#pragma once
// Stage "planes" and "intersect": SVD plane fits (eigenvector of the smallest
// eigenvalue of the covariance) and the plane-plane / three-plane constructions.
#include <optional>
#include <vector>

#include "core/types.h"

namespace c3d {

// Plane n.x = d with |n| = 1 and n.z >= 0 (roof planes face up).
struct Plane {
  Vec3 n = Vec3(0, 0, 1);
  double d = 0;
  double distance(const Vec3& p) const { return n.dot(p) - d; }
  // Height of the plane above (x, y); NaN for vertical planes.
  double z_at(double x, double y) const;
  double slope_deg() const;
  double azimuth_deg() const;  // direction the slope faces, clockwise from +y
};

struct PlaneFit {
  Plane plane;
  Vec3 centroid = Vec3::Zero();
  double rmse = 0;          // of the inliers, m
  int inliers = 0;
  double sigma_normal = 0;  // 1-sigma angular uncertainty of the normal, rad
  double sigma_offset = 0;  // 1-sigma of the offset at the centroid, m
};

// Least-squares plane through points[idx] (all points when idx is empty).
PlaneFit fit_plane(const std::vector<Vec3>& points, const std::vector<int>& idx = {});
// Robust fit: refits on points within max(3 rmse, tol) until stable (trims clutter).
PlaneFit fit_plane_robust(const std::vector<Vec3>& points, const std::vector<int>& idx,
                          double tol);

// Intersection line of two planes; nullopt when they are within min_angle_deg of parallel.
struct Line3 {
  Vec3 point;
  Vec3 dir;  // unit
};
std::optional<Line3> intersect(const Plane& a, const Plane& b, double min_angle_deg = 3.0);
// Point closest (least squares) to all planes; with three independent planes
// it is their common point, with more it is the least-squares compromise.
std::optional<Vec3> common_point(const std::vector<Plane>& planes);

}  // namespace c3d
