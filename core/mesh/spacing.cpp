#include "core/mesh/spacing.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

#include "core/mesh/point_index.h"

namespace c3d {

namespace {

constexpr size_t kNoiseNeighbours = 16;
constexpr size_t kNoiseSamples = 4000;  // the median of as many points is within a few per cent

double median_noise(const std::vector<Vec3>& points, const PointIndex& index) {
  if (points.size() < kNoiseNeighbours) return 0;
  const size_t stride = (points.size() + kNoiseSamples - 1) / kNoiseSamples;
  std::vector<double> spread;
  for (size_t i = 0; i < points.size(); i += stride) {
    const PrincipalAxes p = principal_axes(points, index.nearest_k(i, kNoiseNeighbours));
    spread.push_back(std::sqrt(p.variance[2] * double(kNoiseNeighbours) / double(kNoiseNeighbours - 3)));
  }
  std::nth_element(spread.begin(), spread.begin() + long(spread.size() / 2), spread.end());
  return spread[spread.size() / 2];
}

}  // namespace

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
  s.noise = median_noise(points, index);
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
