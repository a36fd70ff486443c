#include "core/primitives/revolution_faces.h"

#include <algorithm>
#include <cmath>

#include "core/geometry/geometry.h"

namespace c3d {

namespace {
constexpr double kPi = 3.14159265358979323846;

Vec3 ring_point(const Vec2& axis, const Vec2& rho_z, int i, int n) {
  const double a = 2 * kPi * (i % n) / n;
  return {axis.x() + rho_z.x() * std::cos(a), axis.y() + rho_z.x() * std::sin(a), rho_z.y()};
}
}  // namespace

RevolvedFaces revolution_faces(const Vec2& axis, const std::vector<Vec2>& profile, int n) {
  RevolvedFaces out;
  if (profile.size() < 2) return out;
  for (size_t j = 0; j + 1 < profile.size(); ++j) {
    const Vec2 lo = profile[j], hi = profile[j + 1];
    for (int i = 0; i < n; ++i) {
      if (hi.x() <= 0)
        out.roof.push_back({{ring_point(axis, lo, i, n), ring_point(axis, lo, i + 1, n), ring_point(axis, hi, 0, n)}, {}});
      else
        out.roof.push_back({{ring_point(axis, lo, i, n), ring_point(axis, lo, i + 1, n), ring_point(axis, hi, i + 1, n),
                             ring_point(axis, hi, i, n)},
                            {}});
    }
  }
  for (int i = 0; i < n; ++i) out.rim.push_back(ring_point(axis, profile.front(), i, n));
  return out;
}

std::vector<Face> drum_faces(const Ring3& rim, double floor_z) {
  std::vector<Face> drum;
  for (size_t i = 0; i < rim.size(); ++i) {
    const Vec3 a = rim[i], b = rim[(i + 1) % rim.size()];
    drum.push_back({{{a.x(), a.y(), floor_z}, {b.x(), b.y(), floor_z}, b, a}, {}});
  }
  return drum;
}

Element element_of(ElementType type, std::vector<Face> faces) {
  Element e;
  e.type = type;
  e.faces = std::move(faces);
  for (const Face& f : e.faces) e.area += area(f), e.plan_area += plan_area(f);
  return e;
}

Building on_round_drum(RevolvedFaces roof, double ground_z, double min_wall) {
  Building b;
  b.elements.push_back(element_of(ElementType::Roof, std::move(roof.roof)));
  if (roof.rim.front().z() - ground_z >= min_wall)
    b.elements.push_back(element_of(ElementType::Wall, drum_faces(roof.rim, ground_z)));
  Ring3 ground(roof.rim.rbegin(), roof.rim.rend());
  for (Vec3& q : ground) q.z() = ground_z;
  b.elements.push_back(element_of(ElementType::Ground, {{ground, {}}}));
  return b;
}

ShapePart round_part(const Vec2& axis, double floor_z, const Vec2& rim, std::vector<ProfileStep> roof) {
  ShapePart part;
  part.revolve = true;
  part.origin = Vec3(axis.x(), axis.y(), 0);
  part.start = Vec2(0, floor_z);
  part.steps.push_back({ProfileStep::Kind::Line, {}, Vec2(rim.x(), floor_z)});
  part.steps.push_back({ProfileStep::Kind::Line, {}, rim});  // the drum, if any
  part.steps.insert(part.steps.end(), roof.begin(), roof.end());
  return part;
}

ShapePart hall_part(const Ring2& outer, double ground_z, double top_z) {
  ShapePart part;
  part.origin = Vec3(0, 0, ground_z);
  part.v = Vec3::UnitY();
  part.path = Vec3(0, 0, top_z - ground_z);
  part.start = outer.front();
  for (size_t i = 1; i < outer.size(); ++i) part.steps.push_back({ProfileStep::Kind::Line, {}, outer[i]});
  return part;
}

Polygon2 oriented(Polygon2 p) {
  if (signed_area(p.outer) < 0) std::reverse(p.outer.begin(), p.outer.end());
  for (Ring2& h : p.holes)
    if (signed_area(h) > 0) std::reverse(h.begin(), h.end());
  return p;
}

Ring3 lifted(const Ring2& r, double z) {
  Ring3 out;
  for (const Vec2& q : r) out.push_back({q.x(), q.y(), z});
  return out;
}

Face face_at(const Polygon2& p, double z, bool up) {
  auto ring = [&](const Ring2& r) { return up ? lifted(r, z) : lifted(Ring2(r.rbegin(), r.rend()), z); };
  Face f{ring(p.outer), {}};
  for (const Ring2& h : p.holes) f.holes.push_back(ring(h));
  return f;
}

void close_curved(Building& b, const std::string& id, double ground_z) {
  for (const Element& e : b.elements) b.solid.insert(b.solid.end(), e.faces.begin(), e.faces.end());
  b.id = id;
  b.terrain_z = ground_z;
  b.lod = Lod::Lod22;
}

int arc_steps(double radius, double angle, double chord) {
  const double step = 2 * std::acos(std::max(-1.0, 1 - chord / std::max(radius, chord)));
  return std::max(8, int(std::ceil(std::abs(angle) / step)));
}

void mark_wall(Element& wall, int points) {
  wall.support_points = points;
  wall.evidence = points > 0 ? WallEvidence::Measured : WallEvidence::Default;
}

void mark_walls(Building& b, int points) {
  for (Element& e : b.elements)
    if (e.type == ElementType::Wall) mark_wall(e, points);
}

void take_surface_areas(const Building& fine, Building& b) {
  for (size_t k = 0; k < b.elements.size() && k < fine.elements.size(); ++k)
    if (fine.elements[k].type == b.elements[k].type) {
      b.elements[k].area = fine.elements[k].area, b.elements[k].plan_area = fine.elements[k].plan_area;
      b.elements[k].on_surface = true;
    }
}

double quantile_se(size_t n) {
  return std::sqrt(kRimQuantile * (1 - kRimQuantile) / double(std::max<size_t>(n, 1)));
}

double quantile(std::vector<double> v, double q) {
  const size_t k = std::min(v.size() - 1, size_t(q * double(v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + long(k), v.end());
  return v[k];
}

double spread_top(std::vector<double> z) {
  std::sort(z.begin(), z.end());
  const double lo = quantile_of_sorted(z, 0.02), hi = quantile_of_sorted(z, 0.98);
  return hi + (hi - lo) * 0.02 / 0.96;
}

double revolved_z(const Primitive& p, double rho) {
  if (p.kind == PrimitiveKind::Sphere) return p.point.z() + std::sqrt(std::max(0.0, p.radius * p.radius - rho * rho));
  return p.point.z() - rho / std::tan(p.angle);  // a cone with its apex on top
}

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

}  // namespace c3d
