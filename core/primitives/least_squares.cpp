#include "core/primitives/least_squares.h"

#include <Eigen/Dense>
#include <cmath>
#include <functional>

namespace c3d {

namespace {

using Params = Eigen::VectorXd;
using Distance = std::function<double(const Params&, const Vec3&)>;

// Unit axis from polar angles, and back.
Vec3 axis_of(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}
void angles_of(const Vec3& u, double* theta, double* phi) {
  *theta = std::acos(std::clamp(u.z(), -1.0, 1.0));
  *phi = std::atan2(u.y(), u.x());
}

double cost(const Params& x, const std::vector<Vec3>& pts, const Distance& d) {
  double s = 0;
  for (const Vec3& p : pts) s += std::pow(d(x, p), 2);
  return s;
}

// The distances' Jacobian at x by central differences: few parameters, a
// few thousand points.
Eigen::MatrixXd jacobian(const Params& x, const std::vector<Vec3>& pts, const Distance& d) {
  const long n = long(pts.size()), k = x.size();
  Eigen::MatrixXd J(n, k);
  for (long j = 0; j < k; ++j) {
    const double h = 1e-6 * (1 + std::abs(x(j)));
    Params a = x, b = x;
    a(j) += h, b(j) -= h;
    for (long i = 0; i < n; ++i) J(i, j) = (d(a, pts[size_t(i)]) - d(b, pts[size_t(i)])) / (2 * h);
  }
  return J;
}

// Levenberg-Marquardt on the distances. The damping also settles a gauge
// freedom (a point on a cylinder's axis may slide along it).
Params minimise(Params x, const std::vector<Vec3>& pts, const Distance& d) {
  const long n = long(pts.size());
  double lambda = 1e-3, c = cost(x, pts, d);
  for (int it = 0; it < 50 && lambda < 1e10; ++it) {
    const Eigen::MatrixXd J = jacobian(x, pts, d);
    Eigen::VectorXd r(n);
    for (long i = 0; i < n; ++i) r(i) = d(x, pts[size_t(i)]);
    const Eigen::MatrixXd A = J.transpose() * J;
    const Eigen::VectorXd g = J.transpose() * r;
    bool better = false;
    while (!better && lambda < 1e10) {
      Eigen::MatrixXd D = A;
      D.diagonal() += lambda * (A.diagonal().array() + 1e-9).matrix();
      const Params y = x + D.ldlt().solve(-g);
      const double cy = cost(y, pts, d);
      if (cy < c) {
        better = true;
        const double gain = (c - cy) / std::max(c, 1e-300);
        x = y, c = cy, lambda /= 3;
        if (gain < 1e-12) return x;
      } else {
        lambda *= 4;
      }
    }
  }
  return x;
}

Primitive plane_by_pca(const Primitive& start, const std::vector<Vec3>& pts) {
  Primitive p = start;
  Vec3 mean = Vec3::Zero();
  for (const Vec3& q : pts) mean += q;
  mean /= double(pts.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const Vec3& q : pts) cov += (q - mean) * (q - mean).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  p.point = mean;
  p.axis = eig.eigenvectors().col(0);
  if (p.axis.z() < 0) p.axis = -p.axis;
  return p;
}

// A curved primitive's parameters and its distance function.
struct Model {
  Params x;
  Distance d;
};

Model model_of(const Primitive& p) {
  double theta = 0, phi = 0;
  angles_of(p.axis, &theta, &phi);
  Model m;
  switch (p.kind) {
    case PrimitiveKind::Sphere:
      m.x.resize(4);
      m.x << p.point.x(), p.point.y(), p.point.z(), p.radius;
      m.d = [](const Params& y, const Vec3& q) { return (q - Vec3(y(0), y(1), y(2))).norm() - y(3); };
      break;
    case PrimitiveKind::Cylinder:
      m.x.resize(6);
      m.x << p.point.x(), p.point.y(), p.point.z(), theta, phi, p.radius;
      m.d = [](const Params& y, const Vec3& q) {
        const Vec3 u = axis_of(y(3), y(4)), v = q - Vec3(y(0), y(1), y(2));
        return (v - v.dot(u) * u).norm() - y(5);
      };
      break;
    case PrimitiveKind::Cone:
      m.x.resize(6);
      m.x << p.point.x(), p.point.y(), p.point.z(), theta, phi, p.angle;
      m.d = [](const Params& y, const Vec3& q) {
        const Vec3 u = axis_of(y(3), y(4)), v = q - Vec3(y(0), y(1), y(2));
        const double h = v.dot(u);
        return (v - h * u).norm() * std::cos(y(5)) - h * std::sin(y(5));
      };
      break;
    case PrimitiveKind::Plane: break;
  }
  return m;
}

Primitive with_params(Primitive p, const Params& x) {
  p.point = Vec3(x(0), x(1), x(2));
  if (p.kind == PrimitiveKind::Sphere) p.radius = std::abs(x(3));
  if (p.kind == PrimitiveKind::Cylinder) p.axis = axis_of(x(3), x(4)), p.radius = std::abs(x(5));
  if (p.kind == PrimitiveKind::Cone) p.axis = axis_of(x(3), x(4)), p.angle = x(5);
  return p;
}

}  // namespace

Primitive refit(const Primitive& start, const std::vector<Vec3>& pts) {
  if (pts.size() < 8) return start;
  if (start.kind == PrimitiveKind::Plane) return plane_by_pca(start, pts);
  Primitive from = start;
  if (start.kind == PrimitiveKind::Cone) {  // the axis runs from the apex into the cone: most points lie ahead of it
    double ahead = 0;
    for (const Vec3& q : pts) ahead += (q - start.point).dot(start.axis);
    if (ahead < 0) from.axis = -start.axis;
  }
  const Model m = model_of(from);
  return with_params(from, minimise(m.x, pts, m.d));
}

std::vector<std::pair<Primitive, Primitive>> fit_variations(const Primitive& p, const std::vector<Vec3>& pts) {
  if (p.kind == PrimitiveKind::Plane) return {};
  const Model m = model_of(p);
  const long n = long(pts.size()), k = m.x.size();
  if (n <= k) return {};
  const Eigen::MatrixXd J = jacobian(m.x, pts, m.d);
  const double rss = cost(m.x, pts, m.d);
  // Covariance s^2 (J'J)^-1, taken along its principal directions; a
  // direction the points do not fix (a cylinder's point sliding along its
  // axis) moves no surface and is left out.
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(J.transpose() * J);
  const double s = std::sqrt(rss / double(n - k)), top = eig.eigenvalues().maxCoeff();
  std::vector<std::pair<Primitive, Primitive>> out;
  for (long j = 0; j < k; ++j) {
    const double lambda = eig.eigenvalues()(j);
    if (lambda <= 1e-10 * top) continue;
    const Params dx = eig.eigenvectors().col(j) * (s / std::sqrt(lambda));
    out.push_back({with_params(p, m.x - dx), with_params(p, m.x + dx)});
  }
  return out;
}

}  // namespace c3d
