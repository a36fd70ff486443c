#include "core/reconstruct/planes/planes.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace c3d {

double Plane::z_at(double x, double y) const {
  if (std::abs(n.z()) < 1e-9) return kNaN;
  return (d - n.x() * x - n.y() * y) / n.z();
}

double Plane::slope_deg() const {
  return std::acos(std::clamp(std::abs(n.z()), 0.0, 1.0)) * 180.0 / M_PI;
}

double Plane::azimuth_deg() const {
  if (std::hypot(n.x(), n.y()) < 1e-9) return 0.0;
  double a = std::atan2(n.x(), n.y()) * 180.0 / M_PI;  // from +y (north), clockwise
  return a < 0 ? a + 360.0 : a;
}

PlaneFit fit_plane(const std::vector<Vec3>& points, const std::vector<int>& idx) {
  PlaneFit f;
  const size_t n = idx.empty() ? points.size() : idx.size();
  if (n < 3) return f;
  auto at = [&](size_t i) -> const Vec3& { return idx.empty() ? points[i] : points[idx[i]]; };
  Vec3 c = Vec3::Zero();
  for (size_t i = 0; i < n; ++i) c += at(i);
  c /= double(n);
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < n; ++i) {
    Vec3 q = at(i) - c;
    cov += q * q.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
  Vec3 normal = es.eigenvectors().col(0);
  if (normal.z() < 0) normal = -normal;
  f.plane.n = normal;
  f.plane.d = normal.dot(c);
  f.centroid = c;
  f.inliers = int(n);
  double l0 = std::max(es.eigenvalues()(0), 0.0);
  f.rmse = std::sqrt(l0 / double(n));
  // Normal uncertainty: residual variance over the spread along each in-plane axis.
  double spread = std::max(std::min(es.eigenvalues()(1), es.eigenvalues()(2)), 1e-12);
  f.sigma_normal = std::sqrt(l0 / double(std::max<size_t>(n - 3, 1)) / spread);
  f.sigma_offset = f.rmse / std::sqrt(double(n));
  return f;
}

PlaneFit fit_plane_robust(const std::vector<Vec3>& points, const std::vector<int>& idx,
                          double tol) {
  std::vector<int> cur = idx;
  if (cur.empty()) {
    cur.resize(points.size());
    for (size_t i = 0; i < points.size(); ++i) cur[i] = int(i);
  }
  PlaneFit f = fit_plane(points, cur);
  for (int iter = 0; iter < 5 && f.inliers >= 3; ++iter) {
    double limit = std::max(3.0 * f.rmse, tol);
    std::vector<int> keep;
    keep.reserve(cur.size());
    for (int i : (idx.empty() ? cur : idx))
      if (std::abs(f.plane.distance(points[i])) <= limit) keep.push_back(i);
    if (keep.size() < 3 || keep.size() == size_t(f.inliers)) break;
    cur = std::move(keep);
    f = fit_plane(points, cur);
  }
  return f;
}

std::optional<Line3> intersect(const Plane& a, const Plane& b, double min_angle_deg) {
  Vec3 dir = a.n.cross(b.n);
  double s = dir.norm();
  if (s < std::sin(min_angle_deg * M_PI / 180.0)) return std::nullopt;
  dir /= s;
  // Point on both planes closest to the origin of the local frame.
  Eigen::Matrix3d m;
  m.row(0) = a.n.transpose();
  m.row(1) = b.n.transpose();
  m.row(2) = dir.transpose();
  Vec3 p = m.colPivHouseholderQr().solve(Vec3(a.d, b.d, 0.0));
  return Line3{p, dir};
}

std::optional<Vec3> common_point(const std::vector<Plane>& planes) {
  if (planes.size() < 3) return std::nullopt;
  Eigen::MatrixXd A(planes.size(), 3);
  Eigen::VectorXd rhs(planes.size());
  for (size_t i = 0; i < planes.size(); ++i) {
    A.row(i) = planes[i].n.transpose();
    rhs(i) = planes[i].d;
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const auto& sv = svd.singularValues();
  if (sv(2) < 0.05 * sv(0)) return std::nullopt;  // planes do not fix a point
  return Vec3(svd.solve(rhs));
}

}  // namespace c3d
