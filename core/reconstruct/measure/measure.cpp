#include "core/reconstruct/measure/measure.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "core/geometry/geometry.h"
#include "core/check/solid_check.h"

namespace c3d {
namespace {

constexpr double kDeg = 180.0 / M_PI;
constexpr double kFlatDeg = 0.01;

// Area-weighted outward normal of an element (length = area).
Vec3 area_normal(const std::vector<Face>& faces) {
  Vec3 n = Vec3::Zero();
  for (const auto& f : faces) {
    Vec3 u = unit_normal(f);
    n += area(f) * u;
  }
  return n;
}

double perimeter(const Ring3& r) {
  double s = 0;
  for (size_t i = 0; i < r.size(); ++i) s += (r[(i + 1) % r.size()] - r[i]).norm();
  return s;
}

// Covariance of a uniform distribution over the triangles (area-weighted).
Eigen::Matrix3d area_covariance(const std::vector<Triangle>& tris) {
  Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
  Vec3 s = Vec3::Zero();
  double total = 0;
  if (tris.empty()) return m;
  const Vec3 o = tris.front().a;  // precision: work relative to one vertex
  for (const auto& t : tris) {
    Vec3 a = t.a - o, b = t.b - o, c = t.c - o;
    double ar = 0.5 * (b - a).cross(c - a).norm();
    Vec3 sum = a + b + c;
    // integral of x x^T over a triangle = A/12 (sum v v^T + (sum v)(sum v)^T)
    m += ar / 12.0 * (a * a.transpose() + b * b.transpose() + c * c.transpose() + sum * sum.transpose());
    s += ar * sum / 3.0;
    total += ar;
  }
  if (total <= 0) return Eigen::Matrix3d::Zero();
  Vec3 mean = s / total;
  return m / total - mean * mean.transpose();
}

}  // namespace

double closed_volume(const std::vector<Face>& shell) {
  if (shell.empty() || shell.front().ring.empty()) return 0;
  const Vec3 o = shell.front().ring.front();  // V is translation invariant for a closed shell
  double v = 0;
  for (const auto& f : shell) {
    if (f.ring.size() < 3) continue;
    Vec3 c = Vec3::Zero();
    for (const auto& p : f.ring) c += p - o;
    c /= double(f.ring.size());
    v += c.dot(unit_normal(f)) * area(f);
  }
  return v / 3.0;
}

double sigma_area_from_plane(const std::vector<Face>& faces, double rmse, int n_points,
                             double boundary_sigma_m) {
  double a = 0, per = 0;
  for (const auto& f : faces) {
    a += area(f);
    per += perimeter(f.ring);
    for (const auto& h : f.holes) per += perimeter(h);
  }
  const double s_boundary = per * boundary_sigma_m;
  double s_plane = 0;
  if (n_points >= 3 && rmse > 0 && a > 0) {
    const Vec3 n = area_normal(faces).normalized();
    const double slope = std::acos(std::min(1.0, std::abs(n.z())));
    const double tilt = std::min(slope, M_PI / 2 - slope);  // to the projection plane
    const Eigen::Matrix3d cov = area_covariance(triangulate(faces));
    double s2;
    Vec3 down = Vec3::UnitZ() - n.z() * n;  // steepest in-plane direction
    if (tilt > 0.5 / kDeg && down.norm() > 1e-9) {
      down.normalize();
      s2 = down.dot(cov * down);
    } else {  // no defined slope direction: the narrower in-plane extent
      const Vec3 a0 = std::abs(n.x()) < 0.6 ? Vec3::UnitX() : Vec3::UnitY();
      const Vec3 u = a0.cross(n).normalized(), v = n.cross(u);
      Eigen::Matrix2d c2;
      c2 << u.dot(cov * u), u.dot(cov * v), v.dot(cov * u), v.dot(cov * v);
      s2 = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(c2).eigenvalues()(0);
    }
    if (s2 > 0) {
      const double st = rmse / std::sqrt(n_points * s2);
      s_plane = a * (std::tan(tilt) * st + 0.5 * st * st);
    }
  }
  return std::hypot(s_plane, s_boundary);
}

double sigma_area_from_plane(const Face& face, double rmse, int n_points, double boundary_sigma_m) {
  return sigma_area_from_plane(std::vector<Face>{face}, rmse, n_points, boundary_sigma_m);
}

void measure_element(Element& e, double boundary_sigma_m) {
  if (!e.on_surface) {
    e.area = e.plan_area = 0;
    for (const auto& f : e.faces) {
      e.area += area(f);
      // A roof's plan area is what is seen from above: not the underside of
      // an onion dome's bulge, which faces down.
      if (e.type != ElementType::Roof || newell_normal(f.ring).z() >= 0) e.plan_area += plan_area(f);
    }
    if (e.type == ElementType::OuterCeiling) e.area = e.plan_area;
  }
  const Vec3 n = area_normal(e.faces);
  const double len = n.norm();
  e.slope_deg = len > 0 ? std::acos(std::min(1.0, std::abs(n.z()) / len)) * kDeg : 0;
  e.azimuth_deg = 0;
  if (e.slope_deg >= kFlatDeg) {
    double az = std::atan2(n.x(), n.y()) * kDeg;  // clockwise from +y
    e.azimuth_deg = az < 0 ? az + 360 : az;
  }
  if (!std::isnan(boundary_sigma_m))
    e.sigma_area = sigma_area_from_plane(e.faces, e.rmse, e.support_points, boundary_sigma_m);
}

void measure_building(Building& b, double storey_height) {
  double roof_lo = INFINITY, roof_hi = -INFINITY, top = -INFINITY;
  for (auto& e : b.elements) {
    measure_element(e);
    if (e.type != ElementType::Roof) continue;
    for (const auto& f : e.faces)
      for (const auto& p : f.ring) {
        roof_lo = std::min(roof_lo, p.z());
        roof_hi = std::max(roof_hi, p.z());
      }
  }
  for (const auto& f : b.solid)
    for (const auto& p : f.ring) top = std::max(top, p.z());
  if (!std::isfinite(roof_hi)) roof_lo = roof_hi = std::isfinite(top) ? top : b.terrain_z;
  b.eave_height = roof_lo - b.terrain_z;
  b.ridge_height = roof_hi - b.terrain_z;
  b.storeys = storey_height > 0 ? std::max(1, int(std::lround(b.eave_height / storey_height))) : 1;
  b.volume = closed_volume(b.solid);
  if (b.solid.empty()) {
    b.solid_valid = false;
    b.solid_problem = "no solid";
    return;
  }
  SolidCheck check = check_solid(b.solid);
  b.solid_valid = check.ok;
  b.solid_problem = check.ok ? "" : check.summary();
}

}  // namespace c3d
