#include "core/optimizer/exact_surfaces.h"

#include "core/optimizer/height_field_eval.h"

#include <Eigen/Dense>
#include <cmath>
#include <memory>
#include <optional>
#include <tuple>

namespace c3d {

namespace {

// A line of the profile steeper than this is a cylinder (or flatter, a
// plane): its radius (height) changes by at most 1 % of its length, and the
// apex of the cone it would be stays within reach of float arithmetic.
constexpr double kStraightRatio = 0.02;
constexpr double kOnAxisM = 0.01;  // an arc centred this near the axis turns into a sphere

// Where three points' circle has its centre; none where they are in line.
std::optional<Vec2> circle_centre(const Vec2& a, const Vec2& b, const Vec2& c) {
  Eigen::Matrix2d m;
  m << 2 * (b - a).x(), 2 * (b - a).y(), 2 * (c - a).x(), 2 * (c - a).y();
  if (std::abs(m.determinant()) < 1e-12) return std::nullopt;
  const Vec2 rhs(b.squaredNorm() - a.squaredNorm(), c.squaredNorm() - a.squaredNorm());
  return Vec2(m.partialPivLu().solve(rhs));
}

// The surface line a->b of the profile (r, z) sweeps turning about the axis
// through `p.origin` along `p.v`; none where it lies on the axis.
std::optional<CurvedPrimitive> turned_line(const ShapePart& p, const Vec2& a, const Vec2& b) {
  const double dr = b.x() - a.x(), dz = b.y() - a.y();
  if (dr == 0 && dz == 0) return std::nullopt;
  CurvedPrimitive s;
  s.axis = p.v;
  s.span = p.v;
  s.span_lo = std::min(a.y(), b.y()), s.span_hi = std::max(a.y(), b.y());
  if (std::abs(dz) <= kStraightRatio * std::abs(dr)) {  // a ring or disc
    s.kind = CurvedPrimitive::Kind::Plane;
    s.point = p.origin + p.v * (a.y() + b.y()) / 2;
    s.span = Vec3::Zero();  // its extent is across the axis
    return s;
  }
  s.point = p.origin;
  if (std::abs(dr) <= kStraightRatio * std::abs(dz)) {
    s.kind = CurvedPrimitive::Kind::Cylinder;
    s.radius = (a.x() + b.x()) / 2;
    return s.radius > kOnAxisM ? std::optional(s) : std::nullopt;
  }
  // The cone's apex is where the line meets the axis; it opens towards
  // growing radius.
  s.kind = CurvedPrimitive::Kind::Cone;
  const double slope = dz / dr, apex_z = a.y() - a.x() * slope;
  s.point = p.origin + p.v * apex_z;
  s.axis = p.v * (slope > 0 ? 1.0 : -1.0);
  s.angle = std::atan2(std::abs(dr), std::abs(dz));
  s.span = p.v;
  s.span_lo -= apex_z, s.span_hi -= apex_z;  // spans are measured from the apex
  return s;
}

void add_turned(const ShapePart& p, const Vec2& from, const ProfileStep& step, std::vector<CurvedPrimitive>& out) {
  if (step.kind == ProfileStep::Kind::Arc && step.through.size() == 1) {
    const std::optional<Vec2> c = circle_centre(from, step.through[0], step.to);
    if (!c || std::abs(c->x()) > kOnAxisM) return;  // a torus: not a snapping surface
    CurvedPrimitive s;
    s.kind = CurvedPrimitive::Kind::Sphere;
    s.point = p.origin + p.v * c->y();
    s.radius = (from - *c).norm();
    s.span = p.v;
    const double lo = std::min({from.y(), step.through[0].y(), step.to.y()}) - c->y();
    const double hi = std::max({from.y(), step.through[0].y(), step.to.y()}) - c->y();
    s.span_lo = lo, s.span_hi = hi;
    out.push_back(s);
    return;
  }
  std::vector<Vec2> line{from};  // a spline: the cones along its points
  if (step.kind == ProfileStep::Kind::Spline) line.insert(line.end(), step.through.begin(), step.through.end());
  line.push_back(step.to);
  for (size_t k = 1; k < line.size(); ++k)
    if (auto s = turned_line(p, line[k - 1], line[k])) out.push_back(*s);
}

// A swept part: each step's surface along the path, and the end caps.
void add_swept(const ShapePart& p, const Vec2& from, const ProfileStep& step, std::vector<CurvedPrimitive>& out) {
  const double length = p.path.norm();
  CurvedPrimitive s;
  s.span = p.path / length;
  s.span_lo = 0, s.span_hi = length;
  const auto world = [&](const Vec2& q) { return Vec3(p.origin + q.x() * p.u + q.y() * p.v); };
  if (step.kind == ProfileStep::Kind::Arc && step.through.size() == 1) {
    const std::optional<Vec2> c = circle_centre(from, step.through[0], step.to);
    if (!c) return;
    s.kind = CurvedPrimitive::Kind::Cylinder;
    s.point = world(*c);
    s.axis = s.span;
    s.radius = (from - *c).norm();
    out.push_back(s);
    return;
  }
  const Vec3 along = world(step.to) - world(from);
  if (step.kind != ProfileStep::Kind::Line || along.norm() <= 0) return;  // swept splines: none made
  s.kind = CurvedPrimitive::Kind::Plane;
  s.point = world(from);
  s.axis = along.cross(p.path).normalized();
  out.push_back(s);
}

// The end caps of a swept part; a hall under a free-form roof has its
// floor only, the roof closes it above.
void add_caps(const ShapePart& p, std::vector<CurvedPrimitive>& out) {
  std::vector<Vec3> ends{p.origin};
  if (p.roof.empty()) ends.push_back(p.origin + p.path);
  for (const Vec3& at : ends) {
    CurvedPrimitive cap;
    cap.kind = CurvedPrimitive::Kind::Plane;
    cap.point = at;
    cap.axis = p.path.normalized();
    out.push_back(cap);
  }
}

void add_roof(const ShapePart& p, std::vector<CurvedPrimitive>& out) {
  if (p.roof.empty()) return;
  const std::optional<HeightFieldData> data = height_field_data(p.roof);
  if (!data) return;
  CurvedPrimitive s;
  s.kind = CurvedPrimitive::Kind::HeightField;
  s.heights = std::make_shared<const HeightFieldData>(*data);
  out.push_back(s);
}

}  // namespace

std::pair<Vec2, Vec2> spline_plan_frame(const SplineSurface& s) {
  const Vec2 e1 = (s.poles[1] - s.poles[0]).head<2>().normalized(), e2(-e1.y(), e1.x());
  // The first poles stand at their Greville abscissae, the first knots.
  return {s.poles[0].head<2>() - s.knots_u.front() * e1 - s.knots_v.front() * e2, e1};
}

std::optional<HeightFieldData> height_field_data(const SplineSurface& s) {
  const size_t nu = size_t(s.poles_u), nv = size_t(s.poles_v);
  if (s.degree_u != 3 || s.degree_v != 3 || nu < 4 || nv < 4 || s.poles.size() != nu * nv ||
      s.knots_u.size() != nu + 4 || s.knots_v.size() != nv + 4)
    return std::nullopt;
  HeightFieldData f;
  f.nu = int(nu), f.nv = int(nv);
  f.ku = s.knots_u, f.kv = s.knots_v;
  for (const Vec3& q : s.poles) f.z.push_back(q.z());
  std::tie(f.origin, f.e1) = spline_plan_frame(s);
  return f;
}

std::vector<CurvedPrimitive> exact_surfaces(const ExactShape& shape) {
  std::vector<CurvedPrimitive> out;
  for (const ShapePart& p : shape.parts) {
    if (!p.revolve && p.path.norm() <= 0) continue;
    add_roof(p, out);
    Vec2 from = p.start;
    std::vector<ProfileStep> steps = p.steps;
    steps.push_back({ProfileStep::Kind::Line, {}, p.start});  // the profile closes with a line
    for (const ProfileStep& step : steps) {
      if (p.revolve) add_turned(p, from, step, out);
      else add_swept(p, from, step, out);
      from = step.to;
    }
    if (!p.revolve) add_caps(p, out);
  }
  return out;
}

}  // namespace c3d
