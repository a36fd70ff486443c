#include "core/reconstruct/planes/ransac.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace c3d {
namespace {

// Triples drawn: with 40 % of the points on the plane, 500 triples all miss
// it with odds of 1e-14; the points are few (a cluster no region grew on).
constexpr int kTriples = 500;
constexpr unsigned kSeed = 20240611u;  // fixed: the same points give the same plane
constexpr int kRefits = 3;             // least squares on the inliers, the inliers again

std::vector<int> within(const std::vector<Vec3>& points, const std::vector<int>& idx, const Plane& pl, double tol) {
  std::vector<int> in;
  for (int i : idx)
    if (std::abs(pl.distance(points[size_t(i)])) <= tol) in.push_back(i);
  return in;
}

}  // namespace

PlaneSample sample_plane_consensus(const std::vector<Vec3>& points, const std::vector<int>& idx, double tol,
                                   double min_normal_z) {
  PlaneSample best;
  if (idx.size() < 3) return best;
  std::mt19937 rng(kSeed);
  std::uniform_int_distribution<size_t> pick(0, idx.size() - 1);
  Plane best_plane;
  size_t best_count = 0;
  for (int t = 0; t < kTriples; ++t) {
    const Vec3& a = points[size_t(idx[pick(rng)])];
    const Vec3& b = points[size_t(idx[pick(rng)])];
    const Vec3& c = points[size_t(idx[pick(rng)])];
    Vec3 n = (b - a).cross(c - a);
    if (n.norm() < 1e-9) continue;  // a repeated or collinear triple
    n.normalize();
    if (n.z() < 0) n = -n;
    if (n.z() < min_normal_z) continue;
    const Plane pl{n, n.dot(a)};
    size_t count = 0;
    for (int i : idx) count += std::abs(pl.distance(points[size_t(i)])) <= tol;
    if (count > best_count) best_count = count, best_plane = pl;
  }
  if (best_count < 3) return best;
  best.inliers = within(points, idx, best_plane, tol);
  for (int r = 0; r < kRefits && best.inliers.size() >= 3; ++r) {
    best.fit = fit_plane(points, best.inliers);
    std::vector<int> again = within(points, idx, best.fit.plane, tol);
    if (again == best.inliers || again.size() < 3) break;
    best.inliers = std::move(again);
  }
  best.fit = fit_plane(points, best.inliers);
  return best;
}

double plan_hull_area(const std::vector<Vec3>& points, const std::vector<int>& idx) {
  std::vector<Vec2> p;
  for (int i : idx) p.push_back(points[size_t(i)].head<2>());
  std::sort(p.begin(), p.end(), [](const Vec2& a, const Vec2& b) { return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y()); });
  if (p.size() < 3) return 0;
  auto cross = [](const Vec2& o, const Vec2& a, const Vec2& b) {
    return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
  };
  std::vector<Vec2> hull(2 * p.size());  // Andrew's monotone chain
  size_t k = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
    hull[k++] = p[i];
  }
  for (size_t i = p.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && cross(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
    hull[k++] = p[i];
  }
  double twice = 0;
  for (size_t i = 0; i + 1 < k; ++i) twice += hull[i].x() * hull[i + 1].y() - hull[i + 1].x() * hull[i].y();
  return 0.5 * std::abs(twice);
}

}  // namespace c3d
