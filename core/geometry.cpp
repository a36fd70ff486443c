#include "core/geometry.h"

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

BuildingTotals totals(const Building& b) {
  BuildingTotals t;
  auto add = [](double& sum, double& sigma, const Element& e) {
    sum += e.area;
    sigma = std::sqrt(sigma * sigma + e.sigma_area * e.sigma_area);
  };
  for (const auto& e : b.elements) {
    switch (e.type) {
      case ElementType::Roof:
        add(t.roof, t.sigma_roof, e);
        t.roof_plan += e.plan_area;
        ++t.roof_planes;
        break;
      case ElementType::Wall: add(t.wall, t.sigma_wall, e); break;
      case ElementType::PartyWall: add(t.party_wall, t.sigma_party_wall, e); break;
      case ElementType::Ground: add(t.ground, t.sigma_ground, e); break;
      case ElementType::OuterCeiling: add(t.outer_ceiling, t.sigma_outer_ceiling, e); break;
    }
  }
  return t;
}

}  // namespace c3d
