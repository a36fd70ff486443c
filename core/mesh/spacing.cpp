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

PrincipalAxes principal_axes(const std::vector<Vec3>& points, const std::vector<int>& idx) {
  PrincipalAxes p;
  const size_t n = idx.empty() ? points.size() : idx.size();
  if (n == 0) return p;
  const auto at = [&](size_t i) -> const Vec3& { return idx.empty() ? points[i] : points[size_t(idx[i])]; };
  for (size_t i = 0; i < n; ++i) p.centre += at(i);
  p.centre /= double(n);
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < n; ++i) cov += (at(i) - p.centre) * (at(i) - p.centre).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov / double(n));
  for (int k = 0; k < 3; ++k) {  // Eigen orders them smallest first
    p.axes[size_t(k)] = eig.eigenvectors().col(2 - k);
    p.variance[k] = std::max(0.0, eig.eigenvalues()(2 - k));
  }
  return p;
}

Vec3 point_spread(const std::vector<Vec3>& points) {
  if (points.size() < 2) return Vec3::Zero();
  return principal_axes(points).variance.cwiseSqrt();
}

}  // namespace c3d
