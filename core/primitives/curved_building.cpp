#include "core/primitives/curved_building.h"

#include <algorithm>
#include <cmath>

#include "core/geometry/geometry.h"
#include "core/geometry/polygon_ops.h"
#include "core/log.h"
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
  // The wall points that placed each wall (none: under the roof's edge): a
  // vault's end walls at a and b and its sides (both or neither), a drum.
  int seen_a = 0, seen_b = 0, seen_sides = 0, seen_drum = 0;
};

// q-quantile of v (0 <= q <= 1).
double quantile(std::vector<double> v, double q) {
  const size_t k = std::min(v.size() - 1, size_t(q * double(v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + long(k), v.end());
  return v[k];
}

// ---- Revolution: a sphere or cone over a round drum ----

// Height of the surface at plan distance rho from its axis.
double revolved_z(const Primitive& p, double rho) {
  if (p.kind == PrimitiveKind::Sphere) return p.point.z() + std::sqrt(std::max(0.0, p.radius * p.radius - rho * rho));
  return p.point.z() - rho / std::tan(p.angle);  // a cone with its apex on top
}

// The drum's radius: roof points seen from the air lie evenly over the disc,
// so rho^2 is uniform on [0, r^2]; from its 95 % quantile (see vault_outline).
double drum_radius(const CurvedBuildingInput& in) {
  std::vector<double> rho2;
  for (const Vec3& q : in.roof_points) rho2.push_back((q.head<2>() - in.roof.point.head<2>()).squaredNorm());
  return std::sqrt(quantile(rho2, kRimQuantile) / kRimQuantile);
}

// A sphere's or cone's surface from radius r in to its axis (rings evenly
// in polar angle on a sphere; a cone needs none between rim and apex).
RevolvedFaces cap_faces(const Primitive& p, double r, double chord) {
  const double top_angle = std::asin(std::min(1.0, r / std::max(p.radius, r)));
  const int rings = p.kind == PrimitiveKind::Sphere ? arc_steps(p.radius, top_angle, chord) : 1;
  std::vector<Vec2> profile{{r, revolved_z(p, r)}};
  for (int j = 1; j <= rings; ++j) {
    const double rho = p.kind == PrimitiveKind::Sphere ? p.radius * std::sin(top_angle * (1 - double(j) / rings))
                                                       : r * (1 - double(j) / rings);
    profile.push_back({j == rings ? 0.0 : rho, revolved_z(p, j == rings ? 0.0 : rho)});
  }
  return revolution_faces(p.point.head<2>(), profile, arc_steps(r, 2 * kPi, chord));
}

// The exact curve of a sphere's or cone's profile from radius r in to its
// apex on the axis.
std::vector<ProfileStep> cap_curve(const Primitive& p, double r) {
  const Vec2 apex(0, revolved_z(p, 0));
  if (p.kind != PrimitiveKind::Sphere) return {{ProfileStep::Kind::Line, {}, apex}};
  const double mid = p.radius * std::sin(std::asin(std::min(1.0, r / p.radius)) / 2);
  return {{ProfileStep::Kind::Arc, {Vec2(mid, revolved_z(p, mid))}, apex}};
}

// A ring lowered to height z.
Ring3 at_height(Ring3 ring, double z) {
  for (Vec3& q : ring) q.z() = z;
  return ring;
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
  // The roof is the upper half of the circle, down to the ground at most; an
  // arc that ends within kSpringsM of the ground springs from it (a hangar).
  const double R = in.roof.radius, zc = vault_frame(in.roof, (o.a + o.b) / 2).zc;
  const double to_ground = std::sqrt(std::max(0.0, R * R - std::pow(std::max(0.0, in.ground_z - zc), 2)));
  o.half = std::min(o.half, to_ground);
  const double end_z = zc + std::sqrt(std::max(0.0, R * R - o.half * o.half));
  if (end_z - in.ground_z < kSpringsM && zc - in.ground_z < kSpringsM) o.half = to_ground;
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

Building vault(const CurvedBuildingInput& in, const Outline& o) {
  const Frame f = vault_frame(in.roof, (o.a + o.b) / 2);
  const double R = in.roof.radius, phi = std::asin(std::min(1.0, o.half / R));
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

// Moving the rim by its uncertainty (half a point spacing, at least a
// millimetre) out and in moves each element's area; half the spread is its
// sigma.
void add_sigma(const CurvedBuildingInput& in, const Outline& o, Building& b) {
  const double rim = std::max(0.001, in.spacing / 2);
  Outline lo = o, hi = o;
  lo.half -= rim, hi.half += rim;
  lo.a += rim, lo.b -= rim, hi.a -= rim, hi.b += rim;
  const Building small = build(in, lo), large = build(in, hi);
  for (size_t k = 0; k < b.elements.size() && k < small.elements.size() && k < large.elements.size(); ++k) {
    b.elements[k].sigma_area = std::abs(large.elements[k].area - small.elements[k].area) / 2;
    if (b.elements[k].type != ElementType::Roof) continue;
    b.elements[k].support_points = int(in.roof_points.size());
    b.elements[k].rmse = in.roof.rmse;
  }
}

// ---- Wall points, where a wall scan saw the walls ----

// Median of v; NaN with fewer than `least` values.
double median_of(std::vector<double> v, size_t least) {
  if (v.size() < least || v.empty()) return kNaN;
  return quantile(std::move(v), 0.5);
}

// The drum's radius from wall points within kWallReachM of the roof's rim
// and under it, where they lie around at least a quarter of it.
void drum_from_walls(const CurvedBuildingInput& in, Outline& o) {
  const Vec2 c = in.roof.point.head<2>();
  const double rim = revolved_z(in.roof, o.half);
  std::vector<double> rho;
  std::vector<bool> sector(12, false);
  for (const Vec3& q : in.wall_points) {
    const Vec2 d = q.head<2>() - c;
    if (std::abs(d.norm() - o.half) > kWallReachM || q.z() > rim - 0.1 || q.z() < in.ground_z + 0.3) continue;
    rho.push_back(d.norm());
    sector[size_t(std::fmod(std::atan2(d.y(), d.x()) + 2 * kPi, 2 * kPi) / (2 * kPi) * 12) % 12] = true;
  }
  const double r = median_of(rho, kMinWallPoints);
  if (!std::isnan(r) && std::count(sector.begin(), sector.end(), true) >= 3) o.half = r, o.seen_drum = int(rho.size());
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
  const double l = median_of(left, kMinWallPoints / 2), r = median_of(right, kMinWallPoints / 2);
  if (!std::isnan(l) && !std::isnan(r) && std::abs(l - r) < 2 * kMaxAxisOffsetM)
    o.half = std::min((l + r) / 2, R), o.seen_sides = int(left.size() + right.size());
  const double a = median_of(lo, kMinWallPoints), b = median_of(hi, kMinWallPoints);
  if (!std::isnan(a)) o.a = a, o.seen_a = int(lo.size());
  if (!std::isnan(b)) o.b = b, o.seen_b = int(hi.size());
}

// ---- A flat roof carrying domes or cones ----

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

// Half the change of a cap's and its drum's areas when its rim moves by
// +-sigma: their sigma_area, as curved_building's.
void rim_sigma(const Primitive& p, double rim, double roof_z, double sigma, double chord, Element& cap,
               Element* drum) {
  auto areas = [&](double r) {
    if (p.kind == PrimitiveKind::Sphere) r = std::min(r, p.radius);
    const RevolvedFaces c = cap_faces(p, r, chord);
    double roof = 0, wall = 0;
    for (const Face& f : c.roof) roof += area(f);
    for (const Face& f : drum_faces(c.rim, roof_z)) wall += area(f);
    return std::pair(roof, wall);
  };
  const auto [roof_lo, wall_lo] = areas(rim - sigma);
  const auto [roof_hi, wall_hi] = areas(rim + sigma);
  cap.sigma_area = std::abs(roof_hi - roof_lo) / 2;
  if (drum) drum->sigma_area = std::abs(wall_hi - wall_lo) / 2;
}

Building domed(const DomedRoofInput& in, const Polygon2& foot, const std::vector<double>& rims, double sigma) {
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
    rim_sigma(in.caps[k], rims[k], in.roof_z, sigma, in.chord, caps.back(), on_drum ? &drums.back() : nullptr);
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

}  // namespace

std::optional<Building> curved_building(const CurvedBuildingInput& in) {
  const Primitive& p = in.roof;
  if (in.roof_points.size() < 10) return std::nullopt;
  Outline o;
  if (p.kind == PrimitiveKind::Cylinder) {
    if (std::abs(p.axis.z()) > std::sin(2 * kPi / 180)) return std::nullopt;  // a vault's axis is level
    o = vault_outline(in, vault_frame(p));
    vault_from_walls(in, vault_frame(p, (o.a + o.b) / 2), o);
    if (o.b - o.a < 1 || o.half < 0.5) return std::nullopt;
  } else if (p.kind == PrimitiveKind::Sphere || p.kind == PrimitiveKind::Cone) {
    if (p.kind == PrimitiveKind::Cone && std::abs(p.axis.z()) < std::cos(5 * kPi / 180)) return std::nullopt;
    o.half = drum_radius(in);
    drum_from_walls(in, o);
    if (p.kind == PrimitiveKind::Sphere) {  // a hemisphere's rim is its equator; beyond it, no dome
      if (o.half > 1.05 * p.radius) return std::nullopt;
      o.half = std::min(o.half, p.radius);
    }
    if (revolved_z(p, o.half) <= in.ground_z) return std::nullopt;
  } else {
    return std::nullopt;
  }
  log::debug(in.building_id + ": curved outline " + std::to_string(o.a) + " " + std::to_string(o.b) + " " +
             std::to_string(o.half) + " from " + std::to_string(in.roof_points.size()) + " points, ground " +
             std::to_string(in.ground_z) + ", " + p.describe() + " at " + std::to_string(p.point.x()) + " " +
             std::to_string(p.point.y()) + " " + std::to_string(p.point.z()));
  Building b = build(in, o);
  add_sigma(in, o, b);
  return b;
}

std::optional<Building> domed_roof_building(const DomedRoofInput& in) {
  if (in.caps.empty() || in.caps.size() != in.cap_points.size() || in.roof_z - in.ground_z < kMinWallM)
    return std::nullopt;
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
  const double sigma = std::max(0.001, in.spacing / 2);
  if (!discs_fit(foot, discs, sigma)) return std::nullopt;
  return domed(in, foot, rims, sigma);
}

}  // namespace c3d
