#include <algorithm>
#include <cmath>

#include "core/geometry/geometry.h"
#include "core/geometry/polygon_ops.h"
#include "core/primitives/curved_building.h"
#include "core/primitives/least_squares.h"
#include "core/primitives/revolution_faces.h"

// A flat roof carrying domes or cones (docs/curved.md): the hall from its
// planar model, each cap on the flat roof or on a drum.
namespace c3d {

namespace {

constexpr double kPi = 3.14159265358979323846;

// A ring lowered to height z.
Ring3 at_height(Ring3 ring, double z) {
  for (Vec3& q : ring) q.z() = z;
  return ring;
}

// The radius at which surface p comes down to height z, NaN where it does
// not (a sphere's rim lies at most on its equator).
double meeting_radius(const Primitive& p, double z) {
  if (p.kind == PrimitiveKind::Sphere) {
    const double dz = z - p.point.z();
    return dz >= 0 && dz < p.radius ? std::sqrt(p.radius * p.radius - dz * dz) : kNaN;
  }
  const double h = p.point.z() - z;
  return h > 0 ? h * std::tan(p.angle) : kNaN;
}

// A cap's rim on a flat roof at roof_z: where its surface meets the roof,
// unless its points end a drum's height (kMinDrumM) above it; NaN where the
// cap cannot stand on the roof.
double rim_on_roof(const Primitive& p, const std::vector<Vec3>& points, double roof_z) {
  if (points.size() < 10) return kNaN;
  std::vector<double> rho2;
  for (const Vec3& q : points) rho2.push_back((q.head<2>() - p.point.head<2>()).squaredNorm());
  double r = std::sqrt(quantile(rho2, kRimQuantile) / kRimQuantile);  // as drum_radius
  if (p.kind == PrimitiveKind::Sphere) r = std::min(r, p.radius);
  const double meet = meeting_radius(p, roof_z);
  if (!std::isnan(meet) && (r >= meet || revolved_z(p, r) - roof_z < kMinDrumM)) return meet;
  return revolved_z(p, r) > roof_z ? r : kNaN;
}

// Plan distance from c to the segment ab.
double segment_distance(const Vec2& c, const Vec2& a, const Vec2& b) {
  const Vec2 d = b - a;
  const double t = std::clamp((c - a).dot(d) / std::max(d.squaredNorm(), 1e-12), 0.0, 1.0);
  return (a + t * d - c).norm();
}

// Whether the discs (centre, radius) lie inside the footprint, clear of its
// edges and of each other by `margin`.
bool discs_fit(const Polygon2& foot, const std::vector<std::pair<Vec2, double>>& discs, double margin) {
  for (size_t k = 0; k < discs.size(); ++k) {
    const auto& [c, r] = discs[k];
    if (!in_polygon_plan(foot, c)) return false;
    std::vector<const Ring2*> rings{&foot.outer};
    for (const Ring2& h : foot.holes) rings.push_back(&h);
    for (const Ring2* ring : rings)
      for (size_t i = 0; i < ring->size(); ++i)
        if (segment_distance(c, (*ring)[i], (*ring)[(i + 1) % ring->size()]) < r + margin) return false;
    for (size_t j = 0; j < k; ++j)
      if ((c - discs[j].first).norm() < r + discs[j].second + margin) return false;
  }
  return true;
}

// One wall per edge of `ring` from z0 to z1, facing right of its direction
// (out of a counter-clockwise outer ring, into a clockwise hole).
void add_edge_walls(const Ring2& ring, double z0, double z1, Building& b) {
  for (size_t i = 0; i < ring.size(); ++i) {
    const Vec2 p = ring[i], q = ring[(i + 1) % ring.size()];
    if ((q - p).norm() < 1e-6) continue;
    b.elements.push_back(element_of(ElementType::Wall, {{{{p.x(), p.y(), z0}, {q.x(), q.y(), z0}, {q.x(), q.y(), z1},
                                                        {p.x(), p.y(), z1}},
                                                       {}}}));
  }
}

// A cap's areas with its rim at radius r: its roof, the drum under it down
// to roof_z, and the disc it takes from the flat roof.
struct CapAreas {
  double roof = 0, drum = 0, disc = 0;
};

CapAreas cap_areas(const Primitive& p, double r, double roof_z, double chord) {
  if (p.kind == PrimitiveKind::Sphere) r = std::min(r, p.radius);
  const RevolvedFaces c = cap_faces(p, r, chord);
  CapAreas a;
  for (const Face& f : c.roof) a.roof += area(f);
  for (const Face& f : drum_faces(c.rim, roof_z)) a.drum += area(f);
  a.disc = plan_area(Face{c.rim, {}});
  return a;
}

// The sigma of each of a cap's areas, from the independent sources of its
// error, each moved by its standard error both ways: the surface along each
// principal direction of its fit (a rim where it meets the roof moves with
// it) and, on a drum, the rim's quantile (as a round building's drum).
CapAreas cap_sigma(const Primitive& p, const std::vector<Vec3>& points, double rim, double roof_z, bool on_drum,
                   double chord) {
  std::vector<std::pair<CapAreas, CapAreas>> moves;
  if (on_drum) {
    const double se = rim * quantile_se(points.size()) / (2 * kRimQuantile);
    moves.push_back({cap_areas(p, rim - se, roof_z, chord), cap_areas(p, rim + se, roof_z, chord)});
  }
  for (const auto& [minus, plus] : fit_variations(p, points)) {
    const double lo = rim_on_roof(minus, points, roof_z), hi = rim_on_roof(plus, points, roof_z);
    if (!std::isnan(lo) && !std::isnan(hi))
      moves.push_back({cap_areas(minus, lo, roof_z, chord), cap_areas(plus, hi, roof_z, chord)});
  }
  CapAreas var;
  for (const auto& [lo, hi] : moves) {
    var.roof += std::pow((hi.roof - lo.roof) / 2, 2);
    var.drum += std::pow((hi.drum - lo.drum) / 2, 2);
    var.disc += std::pow((hi.disc - lo.disc) / 2, 2);
  }
  return {std::sqrt(var.roof), std::sqrt(var.drum), std::sqrt(var.disc)};
}

Building domed(const DomedRoofInput& in, const Polygon2& foot, const std::vector<double>& rims) {
  Building b;
  Face flat = face_at(foot, in.roof_z, true), roof = flat;  // the solid's roof; the element's, overhang included
  const bool overhang = in.roof_outline.outer.size() >= 3;
  if (overhang) roof = face_at(oriented(in.roof_outline), in.roof_z, true);
  std::vector<Element> caps, drums;
  b.exact.parts.push_back(hall_part(foot.outer, in.ground_z, in.roof_z));
  for (size_t k = 0; k < in.caps.size(); ++k) {
    RevolvedFaces cap = cap_faces(in.caps[k], rims[k], in.chord);
    Ring3 hole = at_height(cap.rim, in.roof_z);
    const bool on_drum = cap.rim.front().z() - in.roof_z > 1e-9;
    if (on_drum) drums.push_back(element_of(ElementType::Wall, drum_faces(cap.rim, in.roof_z)));
    if (on_drum) mark_wall(drums.back(), 0);  // under the cap's rim
    else hole = cap.rim;  // the cap meets the roof: its own rim, vertex for vertex
    std::reverse(hole.begin(), hole.end());
    flat.holes.push_back(hole);
    roof.holes.push_back(hole);
    b.exact.parts.push_back(round_part(in.caps[k].point.head<2>(), in.roof_z, {rims[k], cap.rim.front().z()},
                                       cap_curve(in.caps[k], rims[k])));
    caps.push_back(element_of(ElementType::Roof, std::move(cap.roof)));
    caps.back().support_points = int(in.cap_points[k].size());
    caps.back().rmse = in.caps[k].rmse;
  }
  if (!foot.holes.empty()) b.exact = {};  // hall_part sweeps the outer ring only: the faces stand for it
  b.elements.push_back(element_of(ElementType::Roof, {roof}));
  b.elements.insert(b.elements.end(), caps.begin(), caps.end());
  b.elements.insert(b.elements.end(), drums.begin(), drums.end());
  add_edge_walls(foot.outer, in.ground_z, in.roof_z, b);
  for (const Ring2& h : foot.holes) add_edge_walls(h, in.ground_z, in.roof_z, b);
  b.elements.push_back(element_of(ElementType::Ground, {face_at(foot, in.ground_z, false)}));
  close_curved(b, in.building_id, in.ground_z);
  b.solid.front() = flat;
  if (!overhang) return b;
  std::vector<Face> soffits;  // the outer ceiling, not in the solid (docs/design.md)
  for (const Polygon2& p : poly::subtract({in.roof_outline}, {foot}))
    if (area(p) > 0.01) soffits.push_back(face_at(oriented(p), in.roof_z, false));
  if (!soffits.empty()) b.elements.push_back(element_of(ElementType::OuterCeiling, std::move(soffits)));
  return b;
}

// Every element measured on a tessellation kMeasureFiner times finer, and
// each cap's, its drum's and the flat roof's sigma from the caps' (the
// elements: flat roof, caps, drums in the caps' order, ...). The flat roof's
// outline is the planar model's, and so is that part of its sigma
// (curved_roofs adds it).
void measure_and_sigma(const DomedRoofInput& in, const Polygon2& foot, const std::vector<double>& rims, Building& b) {
  DomedRoofInput fine = in;
  fine.chord = in.chord / kMeasureFiner;
  take_surface_areas(domed(fine, foot, rims), b);
  double holes = 0;
  size_t drum = 1 + in.caps.size();
  for (size_t k = 0; k < in.caps.size(); ++k) {
    const bool on_drum = revolved_z(in.caps[k], rims[k]) - in.roof_z > 1e-9;
    const CapAreas s = cap_sigma(in.caps[k], in.cap_points[k], rims[k], in.roof_z, on_drum, in.chord);
    b.elements[1 + k].sigma_area = s.roof;
    if (on_drum) b.elements[drum++].sigma_area = s.drum;
    holes += s.disc * s.disc;
  }
  b.elements.front().sigma_area = std::sqrt(holes);
}

}  // namespace

std::optional<Building> domed_roof_building(const DomedRoofInput& given) {
  if (given.caps.empty() || given.caps.size() != given.cap_points.size() || given.roof_z - given.ground_z < kMinWallM)
    return std::nullopt;
  // Each cap on its surface fitted to all its points (the search's to a sample).
  DomedRoofInput in = given;
  for (size_t k = 0; k < in.caps.size(); ++k) in.caps[k] = refit(given.caps[k], given.cap_points[k]);
  const Polygon2 foot = oriented(in.footprint);
  if (foot.outer.size() < 3) return std::nullopt;
  std::vector<double> rims;
  std::vector<std::pair<Vec2, double>> discs;
  for (size_t k = 0; k < in.caps.size(); ++k) {
    const Primitive& p = in.caps[k];
    const bool upright = p.kind == PrimitiveKind::Sphere ||
                         (p.kind == PrimitiveKind::Cone && std::abs(p.axis.z()) >= std::cos(5 * kPi / 180));
    const double rim = upright ? rim_on_roof(p, in.cap_points[k], in.roof_z) : kNaN;
    if (std::isnan(rim) || rim < 0.5) return std::nullopt;
    rims.push_back(rim);
    discs.push_back({p.point.head<2>(), rim});
  }
  if (!discs_fit(foot, discs, std::max(0.001, in.spacing / 2))) return std::nullopt;
  Building b = domed(in, foot, rims);
  measure_and_sigma(in, foot, rims, b);
  return b;
}

}  // namespace c3d
