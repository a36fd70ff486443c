// Curved truth buildings: barrel vaults (on walls and springing from the
// ground), domes, shallow domes, cones and onion domes on round drums, and a
// square hall with a dome on its flat roof, halls under free-form roofs (a
// saddle, a wave), and flat roofs over curved plans (a round tower, a hall
// ending in a half-circle apse). Their areas and volumes are exact (closed forms; the
// onion's and the free-form roofs' by quadratures accurate to 1e-8); the faces
// are a tessellation within kChord of the surface, used to scan the points.
#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>

#include "core/geometry/geometry.h"
#include "core/synthetic/sample_detail.h"

namespace c3d {

using namespace sample_detail;

namespace {

// Largest distance of a tessellation from its curved surface, m: far below
// the scan noise (cm), so points on the faces are points on the surface.
constexpr double kChord = 0.002;

// Steps that keep an arc of `radius` over `angle` within kChord of its chords.
int arc_steps(double radius, double angle) {
  const double step = 2 * std::acos(std::max(-1.0, 1 - kChord / std::max(radius, kChord)));
  return std::max(4, int(std::ceil(angle / step)));
}

// The face with its normal turned away from `inside`.
Face facing_away(Ring3 ring, const Vec3& inside) {
  Vec3 c = Vec3::Zero();
  for (const Vec3& p : ring) c += p;
  c /= double(ring.size());
  Vec3 n = Vec3::Zero();
  for (size_t i = 0; i < ring.size(); ++i) n += ring[i].cross(ring[(i + 1) % ring.size()]);
  if (n.dot(c - inside) < 0) std::reverse(ring.begin(), ring.end());
  return {std::move(ring), {}};
}

Element element_of(ElementType t, std::vector<Face> faces, double area, double plan_area) {
  Element e;
  e.type = t;
  e.faces = std::move(faces);
  measure(e);  // slope and azimuth of the first face
  e.area = area;
  e.plan_area = plan_area;
  return e;
}

// A profile turned about the vertical axis through `centre`: rho(t), z(t) for
// t in [0, 1] from the rim (t = 0) to the apex (rho = 0 at t = 1).
struct Profile {
  std::function<double(double)> rho, z, drho, dz;
};

// Area and volume under a profile by composite Simpson (smooth integrands).
double revolved_area(const Profile& p) {
  const int n = 20000;
  auto f = [&](double t) { return 2 * kPi * p.rho(t) * std::hypot(p.drho(t), p.dz(t)); };
  double s = f(0) + f(1);
  for (int i = 1; i < n; ++i) s += (i % 2 ? 4 : 2) * f(double(i) / n);
  return s / (3.0 * n);
}

double revolved_volume(const Profile& p) {
  const int n = 20000;
  auto f = [&](double t) { return kPi * p.rho(t) * p.rho(t) * p.dz(t); };
  double s = f(0) + f(1);
  for (int i = 1; i < n; ++i) s += (i % 2 ? 4 : 2) * f(double(i) / n);
  return s / (3.0 * n);
}

// Rings of the rim polygon at angles `angles` (the drum's and the roof's shared vertices).
std::vector<double> ring_angles(int n) {
  std::vector<double> a(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) a[size_t(i)] = 2 * kPi * i / n;
  return a;
}

// The revolved roof as faces: quads between rings, triangles at the apex.
std::vector<Face> revolved_faces(const Profile& p, const Vec2& centre, const std::vector<double>& angles, int rings) {
  auto at = [&](double t, double a) {
    const double r = p.rho(t);
    return Vec3(centre.x() + r * std::cos(a), centre.y() + r * std::sin(a), p.z(t));
  };
  std::vector<Face> out;
  const size_t n = angles.size();
  for (int j = 0; j < rings; ++j) {
    const double t0 = double(j) / rings, t1 = double(j + 1) / rings;
    for (size_t i = 0; i < n; ++i) {
      const double a0 = angles[i], a1 = angles[(i + 1) % n];
      Ring3 r = j + 1 == rings ? Ring3{at(t0, a0), at(t0, a1), at(t1, 0)}
                               : Ring3{at(t0, a0), at(t0, a1), at(t1, a1), at(t1, a0)};
      const Vec3 mid = (r[0] + r[1]) / 2;
      out.push_back(facing_away(r, Vec3(centre.x(), centre.y(), mid.z())));
    }
  }
  return out;
}

// A spherical cap of rim radius r and rise h on the rim circle at height z0.
Profile cap(double r, double h, double z0) {
  const double R = (r * r + h * h) / (2 * h), zc = z0 + h - R, a0 = std::asin(std::min(1.0, r / R));
  const double a_rim = h <= R ? a0 : kPi - a0;  // polar angle of the rim from the apex
  return {[=](double t) { return R * std::sin(a_rim * (1 - t)); },
          [=](double t) { return zc + R * std::cos(a_rim * (1 - t)); },
          [=](double t) { return -a_rim * R * std::cos(a_rim * (1 - t)); },
          [=](double t) { return a_rim * R * std::sin(a_rim * (1 - t)); }};
}

Profile cone(double r, double h, double z0) {
  return {[=](double t) { return r * (1 - t); }, [=](double t) { return z0 + h * t; }, [=](double) { return -r; },
          [=](double) { return h; }};
}

// An onion: widens past the drum to about 1.08 r, then closes to a point.
Profile onion(double r, double h, double z0) {
  return {[=](double t) { return r * std::pow(1 - t, 1.5) * (1 + 2.5 * t); }, [=](double t) { return z0 + h * t; },
          [=](double t) { return r * (-1.5 * std::sqrt(1 - t) * (1 + 2.5 * t) + 2.5 * std::pow(1 - t, 1.5)); },
          [=](double) { return h; }};
}

// A flat disc of radius r at height z0 (a round tower's roof).
Profile disc(double r, double z0) {
  return {[=](double t) { return r * (1 - t); }, [=](double) { return z0; }, [=](double) { return -r; },
          [=](double) { return 0.0; }};
}

// Widest radius of a profile (its roof's plan outline).
double widest(const Profile& p) {
  double w = 0;
  for (int i = 0; i <= 2000; ++i) w = std::max(w, p.rho(i / 2000.0));
  return w;
}

TruthBuilding finish(TruthBuilding tb, const Ring2& footprint, const std::string& roof_type, double volume) {
  Building& m = tb.model;
  double lo = 1e300, hi = -1e300;
  for (const Element& e : m.elements) {
    for (const Face& f : e.faces) {
      m.solid.push_back(f);
      if (e.type != ElementType::Roof) continue;
      for (const Vec3& p : f.ring) lo = std::min(lo, p.z()), hi = std::max(hi, p.z());
    }
  }
  m.volume = volume;
  m.eave_height = lo;
  m.ridge_height = hi;
  m.storeys = std::max(1, int(std::floor(std::max(lo, 2.5) / 3.0)));
  tb.wall_top_height = lo;
  tb.footprint = footprint;
  tb.roof_type = roof_type;
  tb.exact_areas = true;
  return tb;
}

// A round drum of radius r and height H centred at (r, r) with a revolved roof.
TruthBuilding on_drum(double r, double H, const Profile& roof, int roof_rings, double roof_area, double roof_volume,
                      const std::string& roof_type) {
  const Vec2 c(r, r);
  const std::vector<double> angles = ring_angles(std::max(64, arc_steps(std::max(r, widest(roof)), 2 * kPi)));
  Ring2 foot;
  for (double a : angles) foot.push_back(c + r * Vec2(std::cos(a), std::sin(a)));
  TruthBuilding tb;
  const double plan = kPi * std::pow(std::max(r, widest(roof)), 2);
  tb.model.elements.push_back(
      element_of(ElementType::Roof, revolved_faces(roof, c, angles, roof_rings), roof_area, plan));
  std::vector<Face> drum;
  for (size_t i = 0; i < foot.size(); ++i) {
    const Vec2 a = foot[i], b = foot[(i + 1) % foot.size()];
    drum.push_back(facing_away({{a.x(), a.y(), 0}, {b.x(), b.y(), 0}, {b.x(), b.y(), H}, {a.x(), a.y(), H}},
                               Vec3(c.x(), c.y(), H / 2)));
  }
  tb.model.elements.push_back(element_of(ElementType::Wall, std::move(drum), 2 * kPi * r * H, 0));
  Ring3 ground;
  for (auto it = foot.rbegin(); it != foot.rend(); ++it) ground.push_back({it->x(), it->y(), 0});
  tb.model.elements.push_back(element_of(ElementType::Ground, {{ground, {}}}, kPi * r * r, kPi * r * r));
  return finish(std::move(tb), foot, roof_type, kPi * r * r * H + roof_volume);
}

// A barrel vault along u over [0, L] x [0, W]: walls to H, a circular arc of rise h.
TruthBuilding vault(double L, double W, double H, double h) {
  const double R = (W * W / 4 + h * h) / (2 * h), zc = H + h - R, phi = std::asin(std::min(1.0, W / (2 * R)));
  const int n = arc_steps(R, 2 * phi);
  std::vector<Vec2> arc;  // (v, z) from v = 0 to v = W
  for (int k = 0; k <= n; ++k) {
    const double b = -phi + 2 * phi * k / n;
    arc.push_back({W / 2 + R * std::sin(b), zc + R * std::cos(b)});
  }
  arc.front() = {0, H}, arc.back() = {W, H};
  TruthBuilding tb;
  std::vector<Face> roof;
  for (int k = 0; k < n; ++k) {
    const Vec2 a = arc[size_t(k)], b = arc[size_t(k) + 1];
    roof.push_back(facing_away({{0, a.x(), a.y()}, {L, a.x(), a.y()}, {L, b.x(), b.y()}, {0, b.x(), b.y()}},
                               Vec3(L / 2, W / 2, zc)));
  }
  tb.model.elements.push_back(element_of(ElementType::Roof, std::move(roof), L * R * 2 * phi, L * W));
  const Vec3 mid(L / 2, W / 2, std::max(H, zc) / 2 + h / 2);
  const double segment = R * R * (2 * phi - std::sin(2 * phi)) / 2;
  for (double u : {0.0, L}) {  // end walls up to the arc
    Ring3 end;
    if (H > 0) end.push_back({u, 0, 0}), end.push_back({u, W, 0});
    for (auto it = arc.rbegin(); it != arc.rend(); ++it) end.push_back({u, it->x(), it->y()});
    tb.model.elements.push_back(element_of(ElementType::Wall, {facing_away(end, mid)}, W * H + segment, 0));
  }
  if (H > 0)
    for (double v : {0.0, W})  // side walls up to the springing line
      tb.model.elements.push_back(
          element_of(ElementType::Wall, {facing_away({{0, v, 0}, {L, v, 0}, {L, v, H}, {0, v, H}}, mid)}, L * H, 0));
  tb.model.elements.push_back(
      element_of(ElementType::Ground, {{{{0, 0, 0}, {0, W, 0}, {L, W, 0}, {L, 0, 0}}, {}}}, L * W, L * W));
  return finish(std::move(tb), {{0, 0}, {L, 0}, {L, W}, {0, W}}, H > 0 ? "vault" : "ground_vault",
                L * (W * H + segment));
}

// A square hall of side s, flat roof at H, a cap of radius a and rise h at its centre.
TruthBuilding dome_on_flat(double s, double H, double a, double h) {
  const Vec2 c(s / 2, s / 2);
  std::vector<double> angles = ring_angles(std::max(64, arc_steps(a, 2 * kPi)));
  for (double corner : {kPi / 4, 3 * kPi / 4, 5 * kPi / 4, 7 * kPi / 4}) angles.push_back(corner);
  std::sort(angles.begin(), angles.end());
  angles.erase(std::unique(angles.begin(), angles.end(), [](double x, double y) { return y - x < 1e-9; }),
               angles.end());
  auto on_square = [&](double t) {  // where the ray from the centre at angle t leaves the square
    const Vec2 d(std::cos(t), std::sin(t));
    const double k = (s / 2) / std::max(std::abs(d.x()), std::abs(d.y()));
    return Vec2(c + k * d);
  };
  std::vector<Face> flat;
  for (size_t i = 0; i < angles.size(); ++i) {
    const double t0 = angles[i], t1 = angles[(i + 1) % angles.size()];
    const Vec2 p0 = c + a * Vec2(std::cos(t0), std::sin(t0)), p1 = c + a * Vec2(std::cos(t1), std::sin(t1));
    const Vec2 q0 = on_square(t0), q1 = on_square(t1);
    flat.push_back({{{p0.x(), p0.y(), H}, {q0.x(), q0.y(), H}, {q1.x(), q1.y(), H}, {p1.x(), p1.y(), H}}, {}});
  }
  const Profile dome = cap(a, h, H);
  const double R = (a * a + h * h) / (2 * h);
  TruthBuilding tb;
  tb.model.elements.push_back(element_of(ElementType::Roof, std::move(flat), s * s - kPi * a * a, s * s - kPi * a * a));
  tb.model.elements.push_back(element_of(ElementType::Roof, revolved_faces(dome, c, angles, arc_steps(R, kPi / 2)),
                                         2 * kPi * R * h, kPi * a * a));
  const Ring2 foot{{0, 0}, {s, 0}, {s, s}, {0, s}};
  for (size_t i = 0; i < 4; ++i) {
    const Vec2 p = foot[i], q = foot[(i + 1) % 4];
    tb.model.elements.push_back(
        element_of(ElementType::Wall,
                   {facing_away({{p.x(), p.y(), 0}, {q.x(), q.y(), 0}, {q.x(), q.y(), H}, {p.x(), p.y(), H}},
                                Vec3(c.x(), c.y(), H / 2))},
                   s * H, 0));
  }
  tb.model.elements.push_back(
      element_of(ElementType::Ground, {{{{0, 0, 0}, {0, s, 0}, {s, s, 0}, {s, 0, 0}}, {}}}, s * s, s * s));
  return finish(std::move(tb), foot, "dome_on_flat", s * s * H + kPi * h * h * (3 * R - h) / 3);
}

// A hall of width W and length L under a flat roof at H, ending at u = L in a
// half-circle apse of radius W / 2 (its centre at (L - W / 2, W / 2)).
TruthBuilding apsed_hall(double L, double W, double H) {
  const double r = W / 2, a = L - r;
  const int n = arc_steps(r, kPi);
  Ring2 foot{{0, 0}, {a, 0}};
  for (int k = 1; k < n; ++k) foot.push_back(Vec2(a, r) + r * Vec2(std::sin(kPi * k / n), -std::cos(kPi * k / n)));
  foot.push_back({a, W}), foot.push_back({0, W});
  const double plan = a * W + kPi * r * r / 2;
  const Vec3 mid(a / 2, r, H / 2);
  auto wall = [&](size_t i) {
    const Vec2 p = foot[i], q = foot[(i + 1) % foot.size()];
    return facing_away({{p.x(), p.y(), 0}, {q.x(), q.y(), 0}, {q.x(), q.y(), H}, {p.x(), p.y(), H}}, mid);
  };
  std::vector<Face> apse;  // edges 1 .. size - 3: from (a, 0) round to (a, W)
  for (size_t i = 1; i + 2 < foot.size(); ++i) apse.push_back(wall(i));
  Ring3 roof, ground;
  for (const Vec2& q : foot) roof.push_back({q.x(), q.y(), H});
  for (auto it = foot.rbegin(); it != foot.rend(); ++it) ground.push_back({it->x(), it->y(), 0});
  TruthBuilding tb;
  tb.model.elements.push_back(element_of(ElementType::Roof, {{roof, {}}}, plan, plan));
  tb.model.elements.push_back(element_of(ElementType::Wall, {wall(0)}, a * H, 0));
  tb.model.elements.push_back(element_of(ElementType::Wall, std::move(apse), kPi * r * H, 0));
  tb.model.elements.push_back(element_of(ElementType::Wall, {wall(foot.size() - 2)}, a * H, 0));
  tb.model.elements.push_back(element_of(ElementType::Wall, {wall(foot.size() - 1)}, W * H, 0));
  tb.model.elements.push_back(element_of(ElementType::Ground, {{ground, {}}}, plan, plan));
  return finish(std::move(tb), foot, "apsed_hall", plan * H);
}

// A free-form roof over the hall [0, L] x [0, W]: its height z(u, v), and the
// slopes dz/du, dz/dv.
struct HeightField {
  std::function<double(double, double)> z, zu, zv;
};

// Integral of f over [0, a] x [0, b] by composite Simpson on n x n steps.
double simpson2(const std::function<double(double, double)>& f, double a, double b, int n = 600) {
  auto w = [n](int i) { return i == 0 || i == n ? 1.0 : i % 2 ? 4.0 : 2.0; };
  double s = 0;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) s += w(i) * w(j) * f(a * i / n, b * j / n);
  return s * (a / n) * (b / n) / 9;
}

// Integral of g over [0, a] by composite Simpson on n steps.
double simpson1(const std::function<double(double)>& g, double a, int n = 2000) {
  double s = g(0) + g(a);
  for (int i = 1; i < n; ++i) s += (i % 2 ? 4 : 2) * g(a * i / n);
  return s * (a / n) / 3;
}

// A rectangular hall under a free-form roof: the roof as triangles on an
// n_u x n_v grid (fine enough for kChord on these gentle surfaces), a wall
// per side up to it, areas and volume by quadrature.
TruthBuilding height_field_hall(double L, double W, const HeightField& f, const std::string& roof_type) {
  const int nu = std::max(8, int(std::ceil(L / 0.1))), nv = std::max(8, int(std::ceil(W / 0.1)));
  auto at = [&](int i, int j) {
    const double u = L * i / nu, v = W * j / nv;
    return Vec3(u, v, f.z(u, v));
  };
  std::vector<Face> roof;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {  // counter-clockwise in plan: facing up
      roof.push_back({{at(i, j), at(i + 1, j), at(i + 1, j + 1)}, {}});
      roof.push_back({{at(i, j), at(i + 1, j + 1), at(i, j + 1)}, {}});
    }
  TruthBuilding tb;
  const double slope_area =
      simpson2([&](double u, double v) { return std::sqrt(1 + std::pow(f.zu(u, v), 2) + std::pow(f.zv(u, v), 2)); },
               L, W);
  tb.model.elements.push_back(element_of(ElementType::Roof, std::move(roof), slope_area, L * W));
  const Ring2 foot{{0, 0}, {L, 0}, {L, W}, {0, W}};
  const int steps[] = {nu, nv, nu, nv};
  for (size_t k = 0; k < 4; ++k) {  // a wall per side, its top following the roof
    const Vec2 p = foot[k], q = foot[(k + 1) % 4];
    Ring3 ring{{p.x(), p.y(), 0}, {q.x(), q.y(), 0}};
    for (int s = steps[k]; s >= 0; --s) {
      const Vec2 m = p + (q - p) * double(s) / steps[k];
      ring.push_back({m.x(), m.y(), f.z(m.x(), m.y())});
    }
    const double len = (q - p).norm();
    const double wall = simpson1([&](double t) { const Vec2 m = p + (q - p) * (t / len); return f.z(m.x(), m.y()); },
                                 len);
    tb.model.elements.push_back(element_of(ElementType::Wall, {{ring, {}}}, wall, 0));
  }
  tb.model.elements.push_back(
      element_of(ElementType::Ground, {{{{0, 0, 0}, {0, W, 0}, {L, W, 0}, {L, 0, 0}}, {}}}, L * W, L * W));
  return finish(std::move(tb), foot, roof_type, simpson2(f.z, L, W));
}

// A hyperbolic paraboloid: two opposite corners at H, the other two at H + h.
TruthBuilding saddle(double L, double W, double H, double h) {
  const double c = 2 * h / (L * W);
  return height_field_hall(L, W,
                           {[=](double u, double v) { return H + h / 2 + c * (u - L / 2) * (v - W / 2); },
                            [=](double, double v) { return c * (v - W / 2); },
                            [=](double u, double) { return c * (u - L / 2); }},
                           "saddle");
}

// A wave along the hall: one and a half periods of rise h from the eave at u = 0.
TruthBuilding wave(double L, double W, double H, double h) {
  const double k = 3 * kPi / L;
  return height_field_hall(L, W,
                           {[=](double u, double) { return H + h * (1 - std::cos(k * u)) / 2; },
                            [=](double u, double) { return h * k * std::sin(k * u) / 2; },
                            [=](double, double) { return 0.0; }},
                           "wave");
}

}  // namespace

bool sample_detail::is_curved(SampleLayout l) {
  switch (l) {
    case SampleLayout::Vault:
    case SampleLayout::GroundVault:
    case SampleLayout::Dome:
    case SampleLayout::ShallowDome:
    case SampleLayout::Cone:
    case SampleLayout::OnionDome:
    case SampleLayout::DomeOnFlat:
    case SampleLayout::Saddle:
    case SampleLayout::Wave:
    case SampleLayout::RoundTower:
    case SampleLayout::ApsedHall: return true;
    default: return false;
  }
}

TruthBuilding sample_detail::make_curved_building(const BuildingParams& p) {
  const double r = std::min(p.length, p.width) / 2, H = p.eave_height, h = p.rise;
  TruthBuilding tb;
  switch (p.layout) {
    case SampleLayout::Vault: tb = vault(p.length, p.width, H, h); break;
    case SampleLayout::GroundVault: tb = vault(p.length, p.width, 0, p.width / 2); break;
    case SampleLayout::Dome:
    case SampleLayout::ShallowDome: {
      const double R = (r * r + h * h) / (2 * h);
      tb = on_drum(r, H, cap(r, h, H), arc_steps(R, kPi / 2), 2 * kPi * R * h, kPi * h * h * (3 * R - h) / 3,
                   p.layout == SampleLayout::Dome ? "dome" : "shallow_dome");
      break;
    }
    case SampleLayout::Cone:
      tb = on_drum(r, H, cone(r, h, H), 1, kPi * r * std::hypot(r, h), kPi * r * r * h / 3, "cone");
      break;
    case SampleLayout::OnionDome: {
      const Profile o = onion(r, h, H);
      tb = on_drum(r, H, o, 200, revolved_area(o), revolved_volume(o), "onion");
      break;
    }
    case SampleLayout::DomeOnFlat: tb = dome_on_flat(p.length, H, p.dome_radius, h); break;
    case SampleLayout::Saddle: tb = saddle(p.length, p.width, H, h); break;
    case SampleLayout::Wave: tb = wave(p.length, p.width, H, h); break;
    case SampleLayout::RoundTower: tb = on_drum(r, H, disc(r, H), 1, kPi * r * r, 0, "round_tower"); break;
    case SampleLayout::ApsedHall: tb = apsed_hall(p.length, p.width, H); break;
    default: throw std::invalid_argument("make_curved_building: not a curved layout");
  }
  tb.params = p;
  return tb;
}

}  // namespace c3d
