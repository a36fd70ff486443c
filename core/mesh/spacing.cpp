#include "core/mesh/spacing.h"

#include <Eigen/Eigenvalues>

#include <algorithm>

#include "core/mesh/point_index.h"

namespace c3d {

PointSpacing point_spacing(const std::vector<Vec3>& points) {
  PointSpacing s;
  s.points = points.size();
  if (points.size() < 2) return s;
  const PointIndex index(points);
  std::vector<double> nearest;
  nearest.reserve(points.size());
  for (size_t i = 0; i < points.size(); ++i)
    if (const double d = index.nearest_other(i); d >= 0) nearest.push_back(d);
  if (nearest.empty()) return s;
  std::sort(nearest.begin(), nearest.end());
  const auto at = [&](double q) { return nearest[size_t(q * double(nearest.size() - 1) + 0.5)]; };
  s.min = nearest.front(), s.max = nearest.back(), s.median = at(0.5), s.p95 = at(0.95);
  double sum = 0;
  for (double d : nearest) sum += d;
  s.mean = sum / double(nearest.size());
  return s;
}

Vec3 point_spread(const std::vector<Vec3>& points) {
  if (points.size() < 2) return Vec3::Zero();
  Vec3 mean = Vec3::Zero();
  for (const Vec3& p : points) mean += p;
  mean /= double(points.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const Vec3& p : points) cov += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov / double(points.size()));
  const Vec3 ascending = eig.eigenvalues().cwiseMax(0.0).cwiseSqrt();
  return {ascending.z(), ascending.y(), ascending.x()};
}

}  // namespace c3d
