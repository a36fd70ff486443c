#include "core/primitives/revolved_roof.h"

#include <Geom2dAPI_PointsToBSpline.hxx>
#include <Geom2d_BSplineCurve.hxx>
#include <Standard_Failure.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColgp_Array1OfPnt2d.hxx>

#include <algorithm>
#include <cmath>

#include "core/geometry/geometry.h"
#include "core/geometry/polygon_ops.h"
#include "core/primitives/revolution_faces.h"

namespace c3d {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr size_t kMinPoints = 50;
constexpr size_t kMinBinPoints = 3;
constexpr int kMinBins = 8;
constexpr int kDenseSamples = 256;

double quantile_of(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return quantile_of_sorted(v, q);
}

// The points seen from the pole (0, pole_z) of an axis at `axis`: elevation
// angle theta and distance d of each.
struct PolarPoints {
  std::vector<double> theta, d;
};

PolarPoints polar(const std::vector<Vec3>& pts, const Vec2& axis, double pole_z) {
  PolarPoints p;
  for (const Vec3& q : pts) {
    const double rho = (q.head<2>() - axis).norm(), dz = q.z() - pole_z;
    p.theta.push_back(std::atan2(dz, rho));
    p.d.push_back(std::hypot(rho, dz));
  }
  return p;
}

// Medians of d in `bins` even steps of theta from theta0; a step holding
// fewer than kMinBinPoints takes its neighbours' line.
struct Bins {
  double theta0 = 0, step = 0;
  std::vector<double> median;
  double at(double theta) const {
    const double x = std::clamp((theta - theta0) / step - 0.5, 0.0, double(median.size() - 1));
    const size_t i = std::min(size_t(x), median.size() - 2);
    return median[i] + (x - double(i)) * (median[i + 1] - median[i]);
  }
};

std::optional<Bins> bin_medians(const PolarPoints& p, double theta0, int bins) {
  Bins b;
  b.theta0 = theta0;
  b.step = (kPi / 2 - theta0) / bins;
  std::vector<std::vector<double>> by_bin(static_cast<size_t>(bins));
  for (size_t i = 0; i < p.theta.size(); ++i) {
    const int k = int((p.theta[i] - theta0) / b.step);
    if (k >= 0) by_bin[size_t(std::min(k, bins - 1))].push_back(p.d[i]);
  }
  std::vector<double> xs, ys;
  for (int k = 0; k < bins; ++k)
    if (by_bin[size_t(k)].size() >= kMinBinPoints) xs.push_back(k), ys.push_back(quantile_of(by_bin[size_t(k)], 0.5));
  if (xs.size() < 4 || xs.front() > 0) return std::nullopt;
  for (int k = 0; k < bins; ++k) {  // fill the empty steps along the line of their neighbours
    const size_t j = size_t(std::lower_bound(xs.begin(), xs.end(), double(k)) - xs.begin());
    if (j < xs.size() && xs[j] == k) b.median.push_back(ys[j]);
    else if (j == xs.size()) b.median.push_back(ys.back());
    else b.median.push_back(ys[j - 1] + (k - xs[j - 1]) * (ys[j] - ys[j - 1]) / (xs[j] - xs[j - 1]));
  }
  return b;
}

// Mean absolute departure of the points from their bin medians: what the
// axis search minimises.
double departure(const std::vector<Vec3>& pts, const Vec2& axis, double pole_z, double theta0, int bins) {
  const PolarPoints p = polar(pts, axis, pole_z);
  const std::optional<Bins> b = bin_medians(p, theta0, bins);
  if (!b) return 1e300;
  double sum = 0;
  for (size_t i = 0; i < p.d.size(); ++i) sum += std::abs(p.d[i] - b->at(p.theta[i]));
  return sum / double(p.d.size());
}

// Pattern search from `guess`: steps of 0.4 m down to 5 mm.
Vec2 best_axis(const std::vector<Vec3>& pts, Vec2 axis, double pole_z, double theta0, int bins) {
  double cost = departure(pts, axis, pole_z, theta0, bins);
  for (double step = 0.4; step >= 0.005; step /= 2)
    for (bool moved = true; moved;) {
      moved = false;
      for (const Vec2& dir : {Vec2(1, 0), Vec2(-1, 0), Vec2(0, 1), Vec2(0, -1)}) {
        const double c = departure(pts, axis + step * dir, pole_z, theta0, bins);
        if (c < cost) cost = c, axis += step * dir, moved = true;
      }
    }
  return axis;
}

// Distance of q to the polyline's nearest segment.
double polyline_distance(const std::vector<Vec2>& line, const Vec2& q) {
  double best = 1e300;
  for (size_t i = 0; i + 1 < line.size(); ++i) {
    const Vec2 a = line[i], d = line[i + 1] - a;
    const double t = std::clamp((q - a).dot(d) / std::max(d.squaredNorm(), 1e-18), 0.0, 1.0);
    best = std::min(best, (a + t * d - q).norm());
  }
  return best;
}

// Seen from the air the roof is a height over its plan: up the profile its
// distance from the axis only shrinks. Where the spline folds (swings in
// and out again over sparse bins near the rim), its outermost course stays.
void keep_outermost_course(std::vector<Vec2>& profile) {
  std::vector<Vec2> kept;
  double outer = -1;
  for (auto q = profile.rbegin(); q != profile.rend(); ++q)
    if (q->x() >= outer) kept.push_back(*q), outer = q->x();
  profile.assign(kept.rbegin(), kept.rend());
}

struct SeenDrum {
  double radius = kNaN, top = kNaN;
  int points = 0;
};

// Where a wall scan saw the drum: the median distance to the axis of the
// wall points under the roof's widest ring, near it, and the height they
// reach (from their 2 and 98 % quantiles, as points spread evenly up it),
// where at least kMinWallPoints lie around at least a quarter of it (their
// count); NaN and none otherwise.
SeenDrum seen_drum(const RevolvedBuildingInput& in) {
  const Vec2 widest = in.roof.profile.front();
  std::vector<double> rho, z;
  std::vector<bool> sector(12, false);
  for (const Vec3& q : in.wall_points) {
    const Vec2 d = q.head<2>() - in.roof.axis;
    if (d.norm() > widest.x() + kWallReachM || d.norm() < widest.x() / 2 || q.z() < in.ground_z + 0.3 ||
        q.z() > widest.y())
      continue;
    rho.push_back(d.norm());
    z.push_back(q.z());
    sector[size_t(std::fmod(std::atan2(d.y(), d.x()) + 2 * kPi, 2 * kPi) / (2 * kPi) * 12) % 12] = true;
  }
  if (rho.size() < kMinWallPoints || std::count(sector.begin(), sector.end(), true) < 3) return {};
  return {quantile_of(rho, 0.5), spread_top(z), int(rho.size())};
}

// The building on `profile` (rho, z from the drum's top to the apex).
// Its exact part: the drum, the underside band where the profile starts at
// the drum's top (one point more than the roof's), the roof's profile as a
// spline through its points.
Building on_drum(const RevolvedBuildingInput& in, const std::vector<Vec2>& profile) {
  const std::vector<Vec2> rings = poly::simplify_line(profile, in.chord);
  Building b = on_round_drum(revolution_faces(in.roof.axis, rings, arc_steps(rings.front().x(), 2 * kPi, in.chord)),
                             in.ground_z, kMinWallM);
  close_curved(b, in.building_id, in.ground_z);
  const size_t first = profile.size() > in.roof.profile.size() ? 1 : 0;  // the widest ring
  std::vector<ProfileStep> roof;
  if (first) roof.push_back({ProfileStep::Kind::Line, {}, profile[1]});
  roof.push_back({ProfileStep::Kind::Spline, {profile.begin() + long(first) + 1, profile.end() - 1}, profile.back()});
  b.exact.parts.push_back(round_part(in.roof.axis, in.ground_z, profile.front(), std::move(roof)));
  return b;
}

// The profile from the drum's top: the roof's widest ring, or the drum the
// wall scan saw inside it and the underside band up to that ring; `grow`
// moves the widest ring and the drum out (in, negative).
std::vector<Vec2> drum_profile(const RevolvedBuildingInput& in, double drum_r, double drum_top, double grow) {
  std::vector<Vec2> profile = in.roof.profile;
  const double scale = (profile.front().x() + grow) / profile.front().x();
  for (Vec2& q : profile) q.x() *= scale;
  if (!std::isnan(drum_r) && drum_r + grow < profile.front().x() - in.chord)
    profile.insert(profile.begin(), Vec2(drum_r + grow, std::min(drum_top, profile.front().y())));
  return profile;
}

}  // namespace

std::optional<Building> revolved_roof_building(const RevolvedBuildingInput& in) {
  if (in.roof.profile.size() < 3 || in.roof.profile.front().y() - in.ground_z < kMinWallM) return std::nullopt;
  const SeenDrum drum = seen_drum(in);
  const double drum_r = drum.radius, drum_top = drum.top;
  Building b = on_drum(in, drum_profile(in, drum_r, drum_top, 0));
  mark_walls(b, drum.points);
  const double sigma = std::max(0.001, in.spacing / 2);
  const Building small = on_drum(in, drum_profile(in, drum_r, drum_top, -sigma));
  const Building large = on_drum(in, drum_profile(in, drum_r, drum_top, sigma));
  for (size_t k = 0; k < b.elements.size(); ++k)
    b.elements[k].sigma_area = std::abs(large.elements[k].area - small.elements[k].area) / 2;
  b.elements.front().rmse = in.roof.rmse;
  b.elements.front().support_points = int(in.roof.inliers.size());
  return b;
}

bool drum_seen(const RevolvedBuildingInput& in) { return seen_drum(in).points > 0; }

bool RevolvedRoof::may_overhang() const {
  constexpr double kSteepRad = 60 * kPi / 180;
  const Vec2 rim = profile.front();
  for (const Vec2& q : profile)  // the direction up the roof over its first 0.2 m
    if ((q - rim).norm() >= 0.2) return std::atan2(q.y() - rim.y(), rim.x() - q.x()) > kSteepRad;
  return false;
}

std::string RevolvedRoof::describe() const {
  char s[160];
  std::snprintf(s, sizeof s, "surface of revolution, widest r %.2f m, %d parameters, fit %.3f m",
                profile.empty() ? 0.0 : profile.front().x(), parameters, rmse);
  return s;
}

namespace {

// The axis (`axis`, searched from `guess`) and the profile's steps in
// elevation from the pole at pole_z. A steep rim (an onion's bulb about its
// widest ring) shows little plan to the air: where the lowest step holds
// too few points, wider steps.
std::optional<Bins> axis_and_steps(const std::vector<Vec3>& points, const Vec2& guess, double pole_z, Vec2& axis) {
  const double theta0 = quantile_of(polar(points, guess, pole_z).theta, 0.002);
  for (int bins = std::clamp(int(points.size() / 40), 16, 64); bins >= kMinBins; bins /= 2) {
    axis = best_axis(points, guess, pole_z, theta0, bins);
    if (std::optional<Bins> b = bin_medians(polar(points, axis, pole_z), theta0, bins)) return b;
  }
  return std::nullopt;
}

}  // namespace

std::optional<RevolvedRoof> fit_revolved_roof(const std::vector<Vec3>& points, const Vec2& axis_guess,
                                              double noise) {
  if (points.size() < kMinPoints) return std::nullopt;
  std::vector<double> z;
  for (const Vec3& q : points) z.push_back(q.z());
  const double pole_z = quantile_of(z, 0.005);
  RevolvedRoof roof;
  const std::optional<Bins> b = axis_and_steps(points, axis_guess, pole_z, roof.axis);
  if (!b) return std::nullopt;
  // (theta, d) at each step, theta its parameter (OCCT 7.6's y-values
  // variant overruns its knot array: valgrind).
  const int n = int(b->median.size());
  TColgp_Array1OfPnt2d medians(1, n);
  TColStd_Array1OfReal thetas(1, n);
  for (int k = 0; k < n; ++k) {
    const double theta = b->theta0 + b->step * (k + 0.5);
    medians.SetValue(k + 1, gp_Pnt2d(theta, b->median[size_t(k)]));
    thetas.SetValue(k + 1, theta);
  }
  Handle(Geom2d_BSplineCurve) curve;
  try {
    Geom2dAPI_PointsToBSpline fit(medians, thetas, 3, 8, GeomAbs_C2, std::max(noise, 0.005));
    if (!fit.IsDone()) return std::nullopt;
    curve = fit.Curve();
  } catch (const Standard_Failure&) {
    return std::nullopt;
  }
  const double t0 = curve->FirstParameter(), t1 = curve->LastParameter();
  std::vector<Vec2> dense;
  for (int k = 0; k <= kDenseSamples; ++k) {  // up to the apex, theta = pi / 2
    const double t = t0 + (t1 - t0) * k / kDenseSamples;
    const gp_Pnt2d p = curve->Value(t);
    const double theta = k == kDenseSamples ? kPi / 2 : p.X();
    dense.push_back({std::max(0.0, p.Y() * std::cos(theta)), pole_z + p.Y() * std::sin(theta)});
  }
  // A pointed tip (an onion's, a spire's) is sharper than the spline's
  // steps: the apex stands as high as the highest points (the third highest:
  // not an outlier).
  dense.back() = Vec2(0, std::max(dense.back().y(), quantile_of(z, 1 - 3.0 / double(z.size()))));
  // The widest ring seen from the air: in the lowest quarter of the profile
  // (an onion's bulge, a dome's rim), where the points stop.
  const auto widest = std::max_element(dense.begin(), dense.begin() + kDenseSamples / 4,
                                       [](const Vec2& a, const Vec2& c) { return a.x() < c.x(); });
  roof.profile.assign(widest, dense.end());
  if (roof.profile.size() < 3) return std::nullopt;
  // The spline starts half a step above the lowest points: the roof seen
  // from the air ends at their height, out where they reach (points lie
  // evenly over the plan: rho^2 uniform, as a drum's radius is read).
  std::vector<double> rho2;
  for (const Vec3& q : points) rho2.push_back((q.head<2>() - roof.axis).squaredNorm());
  const Vec2 rim(std::sqrt(quantile_of(rho2, kRimQuantile) / kRimQuantile), pole_z);
  std::vector<Vec2>& pr = roof.profile;
  const auto inside = std::find_if(pr.begin(), pr.end(), [&](const Vec2& q) { return q.x() <= rim.x(); });
  if (inside != pr.begin() && inside != pr.end()) {  // the spline swings out past the points: cut it there
    const Vec2 a = *(inside - 1), b = *inside;
    const Vec2 cut = a + (b - a) * ((a.x() - rim.x()) / std::max(a.x() - b.x(), 1e-12));
    pr.erase(pr.begin(), inside);
    pr.insert(pr.begin(), cut);
  } else if (inside == pr.begin() && rim.x() > pr.front().x() && rim.y() < pr.front().y()) {
    pr.insert(pr.begin(), rim);
  }
  keep_outermost_course(pr);
  if (pr.size() < 3) return std::nullopt;
  double rss = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const double e = polyline_distance(roof.profile, {(points[i].head<2>() - roof.axis).norm(), points[i].z()});
    if (e > 2.5 * noise) continue;
    rss += e * e;
    roof.inliers.push_back(int(i));
  }
  roof.rmse = std::sqrt(rss / double(std::max<size_t>(1, roof.inliers.size())));
  roof.parameters = curve->NbPoles() + 3;
  return roof;
}

}  // namespace c3d
