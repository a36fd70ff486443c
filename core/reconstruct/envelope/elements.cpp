#include "core/reconstruct/envelope/elements.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/geometry/geometry.h"
#include "core/reconstruct/envelope/common.h"

namespace c3d::envelope {

// A roof region's boundary lies on an outline edge where both its ends are
// this close to the edge's line (a weld tolerance, far below any error).
constexpr double kOnEdge = 0.02;  // m

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

namespace {

// Length of `plan`'s boundary lying on the (free) outline edge e.
double length_on(const MultiPolygon2& plan, const OutlineEdge& e) {
  const Vec2 d = (e.b - e.a).normalized();
  const double len = (e.b - e.a).norm();
  auto on = [&](const Vec2& p) {
    const double t = d.dot(p - e.a);
    return std::abs(outward(d).dot(p - e.a)) < kOnEdge && t > -kOnEdge && t < len + kOnEdge;
  };
  double l = 0;
  for (const auto& part : plan)
    for (size_t i = 0; i < part.outer.size(); ++i) {
      const Vec2 &p = part.outer[i], &q = part.outer[(i + 1) % part.outer.size()];
      if (on(p) && on(q)) l += (q - p).norm();
    }
  return l;
}

}  // namespace

std::vector<Element> roof_elements(const std::vector<RoofRegion>& roof, const std::vector<PlaneFit>& fits,
                                   const std::vector<OutlineEdge>& edges, const RoofEdgeNoise& noise,
                                   const std::vector<std::vector<Face>>& by_region) {
  std::vector<Element> out;
  const double common = noise.common(sampled_perimeter(edges));
  for (size_t r = 0; r < roof.size(); ++r) {
    if (by_region[r].empty()) continue;
    Element e = make_element(ElementType::Roof, by_region[r]);
    const Plane& pl = roof[r].plane;
    const PlaneFit& fit = fits[r];
    e.slope_deg = pl.slope_deg();
    e.azimuth_deg = pl.azimuth_deg();
    e.support_points = fit.inliers;
    e.rmse = fit.rmse;
    // Its plan errs with the outline edges it reaches (each on its own, and
    // by the shift all edges share); a boundary with another region is the
    // two planes' intersection, placed by their fits, and a party edge is the
    // parcel boundary. Lifted onto the plane: area / plan area. The tilt
    // part: the fitted normal's error times the area's change with it.
    const double lift = e.plan_area > 0 ? e.area / e.plan_area : 1.0;
    SharedSigma sigma;
    double reach = 0;
    for (const auto& edge : edges) {
      if (edge.party) continue;
      const double l = length_on(roof[r].plan, edge);
      sigma.add(lift * l * noise.edge((edge.b - edge.a).norm()), 0);
      reach += l;
    }
    sigma.add(e.area * std::tan(pl.slope_deg() * M_PI / 180) * fit.sigma_normal, lift * reach * common);
    e.sigma_area = sigma.total();
    e.sigma_shared = sigma.shared;
    out.push_back(std::move(e));
  }
  return out;
}

Element ground_element(const Face& ground, const SharedSigma& sigma) {
  Element g = make_element(ElementType::Ground, {ground});
  g.sigma_area = sigma.total();
  g.sigma_shared = sigma.shared;
  return g;
}

Element outer_ceiling(const std::vector<Face>& soffits, const SharedSigma& sigma) {
  Element oc = make_element(ElementType::OuterCeiling, soffits);
  oc.sigma_area = sigma.total();
  oc.sigma_shared = sigma.shared;
  return oc;
}

}  // namespace c3d::envelope
