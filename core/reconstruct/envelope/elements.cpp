#include "core/reconstruct/envelope/elements.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/geometry/geometry.h"

namespace c3d::envelope {

// A roof region's boundary is placed to within this fraction of the roof
// point spacing (a hull edge lies between its points and the next ones).
constexpr double kBoundarySigmaPerSpacing = 0.25;

Element make_element(ElementType type, std::vector<Face> faces) {
  Element e;
  e.type = type;
  e.faces = std::move(faces);
  for (const auto& f : e.faces) {
    e.area += area(f);
    e.plan_area += plan_area(f);
  }
  if (type == ElementType::OuterCeiling) e.area = e.plan_area;
  return e;
}

double perimeter(const Ring2& r) {
  double p = 0;
  for (size_t i = 0; i < r.size(); ++i) p += (r[(i + 1) % r.size()] - r[i]).norm();
  return p;
}

double azimuth_of(const Face& f) {
  Vec3 n = unit_normal(f);
  return std::fmod(std::atan2(n.x(), n.y()) * 180 / M_PI + 360.0, 360.0);
}

const Face& widest_face(const Element& e) {
  return *std::max_element(e.faces.begin(), e.faces.end(),
                           [](const Face& x, const Face& y) { return area(x) < area(y); });
}

std::vector<Element> roof_elements(const std::vector<RoofRegion>& roof, const std::vector<PlaneFit>& fits,
                                   double spacing, const std::vector<std::vector<Face>>& by_region) {
  std::vector<Element> out;
  for (size_t r = 0; r < roof.size(); ++r) {
    if (by_region[r].empty()) continue;
    Element e = make_element(ElementType::Roof, by_region[r]);
    const Plane& pl = roof[r].plane;
    const PlaneFit& fit = fits[r];
    e.slope_deg = pl.slope_deg();
    e.azimuth_deg = pl.azimuth_deg();
    e.support_points = fit.inliers;
    e.rmse = fit.rmse;
    double per = 0;
    for (const auto& part : roof[r].plan) per += perimeter(part.outer);
    double tilt = e.area * std::tan(pl.slope_deg() * M_PI / 180) * fit.sigma_normal;
    double edge = 0.5 * per * kBoundarySigmaPerSpacing * spacing;
    e.sigma_area = std::sqrt(tilt * tilt + edge * edge);
    out.push_back(std::move(e));
  }
  return out;
}

Element ground_element(const Face& ground, double sigma_ground2) {
  Element g = make_element(ElementType::Ground, {ground});
  g.sigma_area = std::sqrt(sigma_ground2);
  return g;
}

Element outer_ceiling(const std::vector<Face>& soffits, const Polygon2& outline, double spacing,
                      double sigma_ground2) {
  Element oc = make_element(ElementType::OuterCeiling, soffits);
  double edge = perimeter(outline.outer) * kBoundarySigmaPerSpacing * spacing;
  oc.sigma_area = std::sqrt(sigma_ground2 + edge * edge);
  return oc;
}

}  // namespace c3d::envelope
