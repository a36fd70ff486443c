#include "core/geometry/geometry.h"

#include <Eigen/Eigenvalues>

#include <cmath>

namespace c3d {

double signed_area(const Ring2& r) {
  double a = 0;
  for (size_t i = 0, n = r.size(); i < n; ++i) {
    const Vec2& p = r[i];
    const Vec2& q = r[(i + 1) % n];
    a += p.x() * q.y() - q.x() * p.y();
  }
  return 0.5 * a;
}

double area(const Polygon2& p) {
  double a = std::abs(signed_area(p.outer));
  for (const auto& h : p.holes) a -= std::abs(signed_area(h));
  return a;
}

double area(const MultiPolygon2& mp) {
  double a = 0;
  for (const auto& p : mp) a += area(p);
  return a;
}

Vec3 newell_normal(const Ring3& r) {
  Vec3 n = Vec3::Zero();
  if (r.empty()) return n;
  const Vec3 c = r.front();  // relative to a vertex: keeps precision
  for (size_t i = 0, k = r.size(); i < k; ++i) {
    n += (r[i] - c).cross(r[(i + 1) % k] - c);
  }
  return n;
}

double area(const Ring3& r) { return 0.5 * newell_normal(r).norm(); }

double area(const Face& f) {
  double a = area(f.ring);
  for (const auto& h : f.holes) a -= area(h);
  return a;
}

double plan_area(const Face& f) {
  double a = 0.5 * std::abs(newell_normal(f.ring).z());
  for (const auto& h : f.holes) a -= 0.5 * std::abs(newell_normal(h).z());
  return a;
}

Vec3 unit_normal(const Face& f) {
  Vec3 n = newell_normal(f.ring);
  double len = n.norm();
  return len > 0 ? Vec3(n / len) : Vec3(0, 0, 1);
}

Ring2 to_2d(const Ring3& ring) {
  Ring2 out;
  out.reserve(ring.size());
  for (const auto& p : ring) out.emplace_back(p.x(), p.y());
  return out;
}

std::optional<Vec2> intersect_lines(const Vec2& p, const Vec2& d, const Vec2& q, const Vec2& e) {
  double den = d.x() * e.y() - d.y() * e.x();
  if (std::abs(den) < 1e-6) return std::nullopt;
  Vec2 w = q - p;
  return Vec2(p + d * ((w.x() * e.y() - w.y() * e.x()) / den));
}

std::vector<Vec2> points_along(const std::vector<Vec2>& line, double step) {
  if (line.empty()) return {};
  std::vector<Vec2> out{line.front()};
  double walked = 0;  // since the last point
  for (size_t k = 1; k < line.size(); ++k) {
    const Vec2 d = line[k] - line[k - 1];
    const double len = d.norm();
    double t = step - walked;
    for (; t < len; t += step) out.push_back(line[k - 1] + d * (t / len));
    walked = len - (t - step);
  }
  if ((out.back() - line.back()).norm() > 1e-9) out.push_back(line.back());
  return out;
}

double SharedSigma::total() const { return std::sqrt(std::max(0.0, own2) + shared * shared); }

void SharedSigma::add(const Element& e) {
  own2 += e.sigma_area * e.sigma_area - e.sigma_shared * e.sigma_shared;
  shared += e.sigma_shared;
}

BuildingTotals totals(const Building& b) {
  BuildingTotals t;
  SharedSigma s_roof, s_wall, s_party, s_ground, s_ceiling;
  auto add = [](double& sum, SharedSigma& sigma, const Element& e) {
    sum += e.area;
    sigma.add(e);
  };
  for (const auto& e : b.elements) {
    switch (e.type) {
      case ElementType::Roof:
        add(t.roof, s_roof, e);
        t.roof_plan += e.plan_area;
        ++t.roof_planes;
        break;
      case ElementType::Wall: add(t.wall, s_wall, e); break;
      case ElementType::PartyWall: add(t.party_wall, s_party, e); break;
      case ElementType::Ground: add(t.ground, s_ground, e); break;
      case ElementType::OuterCeiling: add(t.outer_ceiling, s_ceiling, e); break;
    }
  }
  t.sigma_roof = s_roof.total();
  t.sigma_wall = s_wall.total();
  t.sigma_party_wall = s_party.total();
  t.sigma_ground = s_ground.total();
  t.sigma_outer_ceiling = s_ceiling.total();
  return t;
}

namespace {

// Whether segments ab and cd share a point. Orientation is zero when the
// sine of the angle is below 1e-9: collinear pieces of one wall top (on the
// same roof-plane line) must not count as crossing by rounding noise.
bool segments_touch(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  auto orient = [](const Vec2& p, const Vec2& q, const Vec2& r) {
    const Vec2 u = q - p, w = r - p;
    const double v = u.x() * w.y() - u.y() * w.x();
    const double eps = 1e-9 * u.norm() * w.norm();
    return v > eps ? 1 : v < -eps ? -1 : 0;
  };
  auto on = [](const Vec2& p, const Vec2& q, const Vec2& r) {  // r (collinear) within pq
    const Vec2 u = q - p;
    const double t = u.dot(r - p), len2 = u.squaredNorm();
    return t >= -1e-12 * len2 && t <= len2 * (1 + 1e-12);
  };
  int o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
  if (o1 * o2 < 0 && o3 * o4 < 0) return true;  // proper crossing
  return (o1 == 0 && on(a, b, c)) || (o2 == 0 && on(a, b, d)) || (o3 == 0 && on(c, d, a)) ||
         (o4 == 0 && on(c, d, b));
}

}  // namespace

std::optional<std::pair<size_t, size_t>> ring_crossing(const Ring3& ring, const Vec3& normal) {
  int drop = 0;  // project on the plane where the normal is largest
  normal.cwiseAbs().maxCoeff(&drop);
  const int u = (drop + 1) % 3, v = (drop + 2) % 3;
  std::vector<Vec2> q;
  for (const auto& p : ring)  // relative to the ring: no UTM magnitudes in the products
    q.emplace_back(p[u] - ring.front()[u], p[v] - ring.front()[v]);
  const size_t n = q.size();
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;  // adjacent through the closing edge
      if (segments_touch(q[i], q[(i + 1) % n], q[j], q[(j + 1) % n])) return std::make_pair(i, j);
    }
  return std::nullopt;
}

double planarity_deviation(const Face& f) {
  std::vector<Vec3> pts(f.ring.begin(), f.ring.end());
  for (const auto& h : f.holes) pts.insert(pts.end(), h.begin(), h.end());
  if (pts.size() < 4) return 0;
  Vec3 c = Vec3::Zero();
  for (const auto& p : pts) c += p;
  c /= double(pts.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : pts) cov += (p - c) * (p - c).transpose();
  const Vec3 n = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov).eigenvectors().col(0);
  double worst = 0;
  for (const auto& p : pts) worst = std::max(worst, std::abs((p - c).dot(n)));
  return worst;
}

double quantile_of_sorted(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return 0;
  const double at = std::clamp(q, 0.0, 1.0) * double(sorted.size() - 1);
  const size_t lo = size_t(std::floor(at)), hi = std::min(lo + 1, sorted.size() - 1);
  return sorted[lo] + (at - double(lo)) * (sorted[hi] - sorted[lo]);
}

bool in_polygon_plan(const Polygon2& poly, const Vec2& p) {
  if (poly.outer.size() < 3 || !in_ring_plan(poly.outer, p)) return false;
  for (const auto& h : poly.holes)
    if (h.size() >= 3 && in_ring_plan(h, p)) return false;
  return true;
}

}  // namespace c3d
