#include "core/primitives/curved_building.h"

#include <algorithm>
#include <cmath>

#include "core/geometry/geometry.h"
#include "core/geometry/polygon_ops.h"
#include "core/log.h"
#include "core/primitives/least_squares.h"
#include "core/primitives/revolution_faces.h"

namespace c3d {

namespace {

constexpr double kPi = 3.14159265358979323846;
// A vault whose arc ends this close to the ground springs from it.
constexpr double kSpringsM = 0.5;
// Side walls further off centre than this about a vault's axis are not taken.
constexpr double kMaxAxisOffsetM = 0.1;

// The shape a curved building stands on, in numbers: what the uncertainty
// of its rim moves.
struct Outline {
  double a = 0, b = 0;  // cylinder: extent along the axis; revolution: unused
  double half = 0;      // cylinder: half-width across the axis; revolution: the drum's radius
  bool springs = false; // a vault springing from the ground: its half-width is where its arc meets it
  // Standard errors of a, b and half, as the points placed them.
  double sigma_a = 0, sigma_b = 0, sigma_half = 0;
  // The wall points that placed each wall (none: under the roof's edge): a
  // vault's end walls at a and b and its sides (both or neither), a drum.
  int seen_a = 0, seen_b = 0, seen_sides = 0, seen_drum = 0;
  double drum_top_seen = 0;  // where the drum's wall points stop (seen_drum > 0)
};

// ---- Revolution: a sphere or cone over a round drum ----

// How far a drum may stand above its wall points' top (their spread's
// estimate is within a few cm where the scan reached the top).
constexpr double kUnseenDrumM = 1.0;

// The drum's radius: roof points seen from the air lie evenly over the disc,
// so rho^2 is uniform on [0, r^2]; from its 95 % quantile (see vault_outline).
// Its standard error: r^2's is r^2 quantile_se / q, and r's half that over r.
void drum_radius(const CurvedBuildingInput& in, Outline& o) {
  std::vector<double> rho2;
  for (const Vec3& q : in.roof_points) rho2.push_back((q.head<2>() - in.roof.point.head<2>()).squaredNorm());
  o.half = std::sqrt(quantile(rho2, kRimQuantile) / kRimQuantile);
  o.sigma_half = o.half * quantile_se(rho2.size()) / (2 * kRimQuantile);
}

Building revolved(const CurvedBuildingInput& in, const Outline& o) {
  Building b = on_round_drum(cap_faces(in.roof, o.half, in.chord), in.ground_z, kMinWallM);
  mark_walls(b, o.seen_drum);
  b.exact.parts.push_back(round_part(in.roof.point.head<2>(), in.ground_z, {o.half, revolved_z(in.roof, o.half)},
                                     cap_curve(in.roof, o.half)));
  return b;
}

// ---- A cylinder with a level axis over a rectangle ----

struct Frame {  // plan frame of the vault: t along the axis, s across
  Vec2 origin, along, across;
  double zc = 0;  // the axis' height
  Vec3 world(double t, double s, double z) const {
    const Vec2 xy = origin + t * along + s * across;
    return {xy.x(), xy.y(), z};
  }
};

// The axis is taken level at its height over the middle of the vault
// (within 2 degrees of level: curved_building refuses others).
Frame vault_frame(const Primitive& p, double t_mid = 0) {
  Frame f;
  const Vec2 h(p.axis.x(), p.axis.y());
  f.along = h.normalized();
  f.across = Vec2(-f.along.y(), f.along.x());
  f.origin = p.point.head<2>();
  f.zc = p.point.z() + t_mid * p.axis.z() / h.norm();
  return f;
}

// Half the width of a circle of radius R about zc at the ground, or R where
// the ground lies below its centre.
double to_ground(double R, double zc, double ground_z) {
  return std::sqrt(std::max(0.0, R * R - std::pow(std::max(0.0, ground_z - zc), 2)));
}

// Its extent from the points, which lie evenly over its plan (as seen from
// the air): along the axis from the 5 % and 95 % quantiles, across it from
// the 95 % quantile of the distance to the axis, each scaled to where 100 %
// would lie. Quantiles, not extremes: the noise and the odd stray point push
// extremes out, and points at the terrain may be missing.
Outline vault_outline(const CurvedBuildingInput& in, const Frame& f) {
  std::vector<double> t, s;
  for (const Vec3& q : in.roof_points) {
    const Vec2 d = q.head<2>() - f.origin;
    t.push_back(d.dot(f.along));
    s.push_back(std::abs(d.dot(f.across)));
  }
  const double lo = quantile(t, 1 - kRimQuantile), hi = quantile(t, kRimQuantile);
  const double pad = (hi - lo) * (1 - kRimQuantile) / (2 * kRimQuantile - 1);
  Outline o{lo - pad, hi + pad, quantile(s, kRimQuantile) / kRimQuantile};
  o.sigma_a = o.sigma_b = (o.b - o.a) * quantile_se(t.size()) * (1 + (1 - kRimQuantile) / (2 * kRimQuantile - 1));
  o.sigma_half = o.half * quantile_se(s.size()) / kRimQuantile;
  // The roof is the upper half of the circle, down to the ground at most; an
  // arc that ends within kSpringsM of the ground springs from it (a hangar).
  const double R = in.roof.radius, zc = vault_frame(in.roof, (o.a + o.b) / 2).zc;
  o.half = std::min(o.half, to_ground(R, zc, in.ground_z));
  // Near the springing the arc is steep: a half-width a little short puts
  // its end far above the ground. Read at two of its sigma further out.
  const double reach = std::min(o.half + 2 * o.sigma_half, to_ground(R, zc, in.ground_z));
  const double end_z = zc + std::sqrt(std::max(0.0, R * R - reach * reach));
  o.springs = end_z - in.ground_z < kSpringsM && zc - in.ground_z < kSpringsM;
  return o;
}

// The vault's exact part: its end profile at o.a in (across, z), the arc
// through its crown, swept along the axis to o.b.
ShapePart vault_part(const Frame& f, const Outline& o, const std::vector<Vec2>& arc, double radius, double ground_z,
                     bool walls) {
  ShapePart part;
  part.origin = f.world(o.a, 0, 0);
  part.u = Vec3(f.across.x(), f.across.y(), 0);
  part.path = Vec3(f.along.x(), f.along.y(), 0) * (o.b - o.a);
  part.start = Vec2(arc.front().x(), ground_z);
  part.steps.push_back({ProfileStep::Kind::Line, {}, Vec2(arc.back().x(), ground_z)});
  if (walls) part.steps.push_back({ProfileStep::Kind::Line, {}, arc.back()});
  part.steps.push_back({ProfileStep::Kind::Arc, {Vec2(0, f.zc + radius)}, arc.front()});
  return part;
}

Building vault(const CurvedBuildingInput& in, Outline o) {
  const Frame f = vault_frame(in.roof, (o.a + o.b) / 2);
  const double R = in.roof.radius;
  if (o.springs) o.half = to_ground(R, f.zc, in.ground_z);
  const double phi = std::asin(std::min(1.0, o.half / R));
  const int n = arc_steps(R, 2 * phi, in.chord);
  std::vector<Vec2> arc;  // (s, z) across the roof
  for (int k = 0; k <= n; ++k) {
    const double beta = -phi + 2 * phi * k / n;
    arc.push_back({R * std::sin(beta), std::max(in.ground_z, f.zc + R * std::cos(beta))});
  }
  if (arc.front().y() - in.ground_z < kMinWallM)
    arc.front().y() = arc.back().y() = in.ground_z;  // springs from the ground
  std::vector<Face> roof;
  for (int k = 0; k < n; ++k) {
    const Vec2 p = arc[size_t(k)], q = arc[size_t(k) + 1];
    roof.push_back({{f.world(o.a, p.x(), p.y()), f.world(o.a, q.x(), q.y()), f.world(o.b, q.x(), q.y()),
                     f.world(o.b, p.x(), p.y())},
                    {}});
  }
  Building out;
  out.elements.push_back(element_of(ElementType::Roof, std::move(roof)));
  const double wall = arc.front().y() - in.ground_z;
  for (double t : {o.a, o.b}) {  // end walls up to the arc
    Ring3 end;
    if (wall >= kMinWallM)
      end.push_back(f.world(t, o.half, in.ground_z)), end.push_back(f.world(t, -o.half, in.ground_z));
    for (const Vec2& q : arc) end.push_back(f.world(t, q.x(), q.y()));
    if (t == o.b) std::reverse(end.begin(), end.end());
    out.elements.push_back(element_of(ElementType::Wall, {{end, {}}}));
    mark_wall(out.elements.back(), t == o.a ? o.seen_a : o.seen_b);
  }
  if (wall >= kMinWallM)
    for (double s : {-o.half, o.half}) {  // side walls up to the springing
      Ring3 side{f.world(o.a, s, in.ground_z), f.world(o.b, s, in.ground_z), f.world(o.b, s, arc.front().y()),
                 f.world(o.a, s, arc.front().y())};
      if (s > 0) std::reverse(side.begin(), side.end());
      out.elements.push_back(element_of(ElementType::Wall, {{side, {}}}));
      mark_wall(out.elements.back(), o.seen_sides);
    }
  Ring3 ground{f.world(o.a, -o.half, in.ground_z), f.world(o.a, o.half, in.ground_z), f.world(o.b, o.half, in.ground_z),
               f.world(o.b, -o.half, in.ground_z)};
  out.elements.push_back(element_of(ElementType::Ground, {{ground, {}}}));
  out.exact.parts.push_back(vault_part(f, o, arc, R, in.ground_z, wall >= kMinWallM));
  return out;
}

// ---- Common: orientation, the solid, sigma ----

// Every face turned away from the inside. These solids are convex, so the
// mean of their vertices is inside and every face looks away from it.
void face_outward(Building& b) {
  Vec3 inside = Vec3::Zero();
  size_t n = 0;
  for (const Element& e : b.elements)
    for (const Face& f : e.faces)
      for (const Vec3& q : f.ring) inside += q, ++n;
  inside /= double(n);
  for (Element& e : b.elements)
    for (Face& f : e.faces) {
      Vec3 c = Vec3::Zero(), normal = Vec3::Zero();
      for (const Vec3& q : f.ring) c += q;
      c /= double(f.ring.size());
      for (size_t i = 0; i < f.ring.size(); ++i) normal += f.ring[i].cross(f.ring[(i + 1) % f.ring.size()]);
      if (normal.dot(c - inside) < 0) std::reverse(f.ring.begin(), f.ring.end());
    }
}

Building build(const CurvedBuildingInput& in, const Outline& o) {
  Building b = in.roof.kind == PrimitiveKind::Cylinder ? vault(in, o) : revolved(in, o);
  face_outward(b);
  close_curved(b, in.building_id, in.ground_z);
  return b;
}

// Every element measured on a tessellation kMeasureFiner times finer (the
// same elements, in the same order).
void measure_on_surface(const CurvedBuildingInput& in, const Outline& o, Building& b) {
  CurvedBuildingInput fine = in;
  fine.chord = in.chord / kMeasureFiner;
  take_surface_areas(build(fine, o), b);
}

// Each element's sigma from the independent sources of its error, each
// moved by its standard error both ways: the rim (a, b, half, as the points
// placed it), the ground floor level (in.ground_sigma), and the surface
// along each principal direction of its fit. A move that changes the
// building's make-up (a vault no longer springing from the ground) says
// nothing of small errors and is left out.
void add_sigma(const CurvedBuildingInput& in, const Outline& o, Building& b) {
  std::vector<std::pair<Building, Building>> moves;
  auto rim_move = [&](double Outline::*field, double sigma) {
    Outline lo = o, hi = o;
    lo.*field -= sigma, hi.*field += sigma;
    moves.push_back({build(in, lo), build(in, hi)});
  };
  rim_move(&Outline::a, o.sigma_a);
  rim_move(&Outline::b, o.sigma_b);
  if (!o.springs) rim_move(&Outline::half, o.sigma_half);
  CurvedBuildingInput lo = in, hi = in;
  if (in.ground_sigma > 0) {
    lo.ground_z -= in.ground_sigma, hi.ground_z += in.ground_sigma;
    moves.push_back({build(lo, o), build(hi, o)});
    lo.ground_z = hi.ground_z = in.ground_z;
  }
  for (const auto& [minus, plus] : fit_variations(in.roof, in.roof_points)) {
    lo.roof = minus, hi.roof = plus;
    moves.push_back({build(lo, o), build(hi, o)});
  }
  for (size_t k = 0; k < b.elements.size(); ++k) {
    double var = 0;
    for (const auto& [minus, plus] : moves)
      if (minus.elements.size() == b.elements.size() && plus.elements.size() == b.elements.size() &&
          minus.elements[k].type == b.elements[k].type && plus.elements[k].type == b.elements[k].type)
        var += std::pow((plus.elements[k].area - minus.elements[k].area) / 2, 2);
    b.elements[k].sigma_area = std::sqrt(var);
    if (b.elements[k].type != ElementType::Roof) continue;
    b.elements[k].support_points = int(in.roof_points.size());
    b.elements[k].rmse = in.roof.rmse;
  }
}

// ---- Wall points, where a wall scan saw the walls ----

// Median of v; NaN with fewer than `least` values. Its standard error,
// sqrt(pi / 2) times the mean's, goes to *se.
double median_of(std::vector<double> v, size_t least, double* se) {
  if (v.size() < least || v.empty()) return kNaN;
  double mean = 0, var = 0;
  for (double x : v) mean += x;
  mean /= double(v.size());
  for (double x : v) var += (x - mean) * (x - mean);
  *se = 1.2533 * std::sqrt(var / double(std::max<size_t>(v.size() - 1, 1)) / double(v.size()));
  return quantile(std::move(v), 0.5);
}

// The drum's radius from wall points within kWallReachM of the roof's rim
// and under it, where they lie around at least a quarter of it.
void drum_from_walls(const CurvedBuildingInput& in, Outline& o) {
  const Vec2 c = in.roof.point.head<2>();
  const double rim = revolved_z(in.roof, o.half);
  std::vector<double> rho, z;
  std::vector<bool> sector(12, false);
  for (const Vec3& q : in.wall_points) {
    const Vec2 d = q.head<2>() - c;
    if (std::abs(d.norm() - o.half) > kWallReachM || q.z() > rim - 0.1 || q.z() < in.ground_z + 0.3) continue;
    rho.push_back(d.norm());
    z.push_back(q.z());
    sector[size_t(std::fmod(std::atan2(d.y(), d.x()) + 2 * kPi, 2 * kPi) / (2 * kPi) * 12) % 12] = true;
  }
  double se = 0;
  const double r = median_of(rho, kMinWallPoints, &se);
  if (!std::isnan(r) && std::count(sector.begin(), sector.end(), true) >= 3)
    o.half = r, o.sigma_half = se, o.seen_drum = int(rho.size()), o.drum_top_seen = spread_top(z);
}

// A vault's side walls (half-width) and end walls (extent along the axis)
// from the wall points that see them. The side walls only where both are
// seen and stand evenly about the axis (the model's arc is symmetric).
void vault_from_walls(const CurvedBuildingInput& in, const Frame& f, Outline& o) {
  const double R = in.roof.radius, spring = f.zc + std::sqrt(std::max(0.0, R * R - o.half * o.half));
  std::vector<double> left, right, lo, hi;
  for (const Vec3& q : in.wall_points) {
    const Vec2 d = q.head<2>() - f.origin;
    const double t = d.dot(f.along), s = d.dot(f.across);
    if (q.z() < in.ground_z + 0.3) continue;
    const bool between_ends = t > o.a + kWallReachM && t < o.b - kWallReachM;  // not an end wall's corner
    if (std::abs(std::abs(s) - o.half) < kWallReachM && between_ends && q.z() < spring - 0.1)
      (s < 0 ? left : right).push_back(std::abs(s));
    if (std::abs(s) < o.half - kWallReachM && std::abs(t - o.a) < kWallReachM) lo.push_back(t);
    if (std::abs(s) < o.half - kWallReachM && std::abs(t - o.b) < kWallReachM) hi.push_back(t);
  }
  double se_l = 0, se_r = 0, se_a = 0, se_b = 0;
  const double l = median_of(left, kMinWallPoints / 2, &se_l), r = median_of(right, kMinWallPoints / 2, &se_r);
  if (!std::isnan(l) && !std::isnan(r) && std::abs(l - r) < 2 * kMaxAxisOffsetM) {
    o.half = std::min((l + r) / 2, R), o.seen_sides = int(left.size() + right.size());
    o.sigma_half = std::hypot(se_l, se_r) / 2;
  }
  const double a = median_of(lo, kMinWallPoints, &se_a), b = median_of(hi, kMinWallPoints, &se_b);
  if (!std::isnan(a)) o.a = a, o.sigma_a = se_a, o.seen_a = int(lo.size());
  if (!std::isnan(b)) o.b = b, o.sigma_b = se_b, o.seen_b = int(hi.size());
}

}  // namespace

std::optional<Building> curved_building(const CurvedBuildingInput& given) {
  if (given.roof_points.size() < 10) return std::nullopt;
  // The search fitted the surface to a sample of its RANSAC inliers; the
  // building stands on it fitted to all its points (and its sigma on that fit).
  CurvedBuildingInput in = given;
  in.roof = refit(given.roof, given.roof_points);
  const Primitive& p = in.roof;
  Outline o;
  if (p.kind == PrimitiveKind::Cylinder) {
    if (std::abs(p.axis.z()) > std::sin(2 * kPi / 180)) return std::nullopt;  // a vault's axis is level
    o = vault_outline(in, vault_frame(p));
    vault_from_walls(in, vault_frame(p, (o.a + o.b) / 2), o);
    if (o.b - o.a < 1 || o.half < 0.5) return std::nullopt;
  } else if (p.kind == PrimitiveKind::Sphere || p.kind == PrimitiveKind::Cone) {
    if (p.kind == PrimitiveKind::Cone && std::abs(p.axis.z()) < std::cos(5 * kPi / 180)) return std::nullopt;
    drum_radius(in, o);
    drum_from_walls(in, o);
    if (p.kind == PrimitiveKind::Sphere) {  // a hemisphere's rim is its equator; beyond it, no dome
      if (o.half > 1.05 * p.radius) return std::nullopt;
      o.half = std::min(o.half, p.radius);
    }
    if (revolved_z(p, o.half) <= in.ground_z) return std::nullopt;
    // A wall scan reaches a drum's top: where it stops well below the roof,
    // something unseen stands between (an onion's bulb over its drum).
    const double unseen = revolved_z(p, o.half) - o.drum_top_seen;
    if (o.seen_drum > 0 && unseen > kUnseenDrumM) {
      log::debug(in.building_id + ": its " + p.describe() + " would stand " + std::to_string(unseen) +
                 " m above where the drum's wall points stop");
      return std::nullopt;
    }
  } else {
    return std::nullopt;
  }
  log::debug(in.building_id + ": curved outline " + std::to_string(o.a) + " " + std::to_string(o.b) + " " +
             std::to_string(o.half) + " from " + std::to_string(in.roof_points.size()) + " points, ground " +
             std::to_string(in.ground_z) + ", " + p.describe() + " at " + std::to_string(p.point.x()) + " " +
             std::to_string(p.point.y()) + " " + std::to_string(p.point.z()));
  Building b = build(in, o);
  measure_on_surface(in, o, b);
  add_sigma(in, o, b);
  return b;
}

}  // namespace c3d
