#include "core/reconstruct/outline/arcs.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <optional>
#include <opencv2/core/optim.hpp>

#include "core/geometry/geometry.h"
#include "core/geometry/polygon_ops.h"
#include "core/primitives/revolution_faces.h"

namespace c3d {
namespace {

struct OutlineArc {
  Vec2 centre = Vec2::Zero();
  double radius = 0;
  double from = 0, span = 0;  // counter-clockwise from angle `from` over `span` (rad) about the centre
};

constexpr double kPi = 3.14159265358979323846;
// A run of hull vertices is an arc candidate where they lie on one circle
// within a point spacing (the hull's teeth; at least 5 cm), at least
// kMinRunVertices of them, over half the turn at least (an apse, a bow, a
// round tower), bowing at least 0.3 m from their chord (a straight edge
// fits a huge circle too), with a radius a building's curve may have
// (2.5-60 m). A shorter or tighter arc is a corner: a convex corner's
// points thin out across both its edges' blur, which the likelihood below
// (one edge's) does not expect, and on Cimahi's roofs arcs of 1.7-4 m over
// a quarter turn, and of 2.7 m over 154 degrees, explained the points
// better than their ragged corners did.
constexpr double kHullTolSpacings = 1.0, kMinHullTol = 0.05;
// Neighbouring runs join where their vertices lie on one circle within 1.5
// spacings: the hull's teeth are deeper across a gap in the scan.
constexpr double kJoinTolSpacings = 1.5;
// A whole hull on one circle within 2 spacings is a round roof's candidate.
constexpr double kWholeTolSpacings = 2.0;
constexpr size_t kMinRunVertices = 10;
constexpr double kMinSpan = kPi, kMinBow = 0.3, kMinRadius = 2.5, kMaxRadius = 60;
// The edge's blur for outline_likelihood: 1 cm to 1 m, in 5 % steps; the
// share of stray points it allows for (outliers, a neighbour's points).
constexpr double kMinBlur = 0.01, kMaxBlur = 1.0, kBlurStep = 1.05, kStray = 0.01;
// An arc over nearly the whole turn is a full circle; one over most of it
// is tried as one too.
constexpr double kFullTurn = 2 * kPi - 0.3, kMostOfTurn = 1.5 * kPi;
// An arc's first radius is read from its sector's points (sector_radius),
// as a drum's rim (revolution_faces.h, kRimQuantile): at least this many.
constexpr size_t kMinSectorPoints = 30;
// Then centre, radius and the edge's blur are refined to the most likely
// (Nelder-Mead): first steps 10 cm and a third of the blur's log, stopping
// at 1e-4 in the log-likelihood or after 300 steps.
constexpr double kStepCentre = 0.1, kStepLogBlur = 0.3, kStopChange = 1e-4;
constexpr int kMaxSteps = 300;
// An arc's ends move to meet the outline (met_ends) by a degree at a time,
// by 45 degrees at most, a millimetre nearer to count; vertices closer than 1 mm to the
// line through their neighbours are dropped.
constexpr double kEndStep = kPi / 180, kMaxEndMove = kPi / 4, kSameGap = 1e-3, kCollinear = 1e-3;
constexpr double kArcParameters = 3;
// Reading arcs back from a ring (arcs_in_ring): at least this many vertices
// on one circle (within kOnCircle), each turning by at most kMaxChordTurn.
constexpr size_t kMinArcVertices = 5;
constexpr double kOnCircle = 0.005, kMaxChordTurn = kPi / 9, kJunctionChord = 1.5;
// The sector, to 95 % of the radius, must lie 98 % inside the roof (its hull
// and outline together): its radius is read from the points there.
constexpr double kSectorInside = 0.95, kSectorShare = 0.98;

struct Circle {
  Vec2 centre = Vec2::Zero();
  double radius = 0, rms = INFINITY;
};

Ring2 circle_ring(const Vec2& c, double r, double chord);
Ring2 wedge(const OutlineArc& arc);

// Kasa's algebraic circle fit, and the rms of the points' distances to it.
Circle fit_circle(const std::vector<Vec2>& pts) {
  Eigen::MatrixXd A(long(pts.size()), 3);
  Eigen::VectorXd b(long(pts.size()));
  for (size_t k = 0; k < pts.size(); ++k) {
    A.row(long(k)) << pts[k].x(), pts[k].y(), 1;
    b(long(k)) = -pts[k].squaredNorm();
  }
  const Eigen::Vector3d x = A.colPivHouseholderQr().solve(b);
  Circle c;
  c.centre = Vec2(-x(0) / 2, -x(1) / 2);
  const double r2 = c.centre.squaredNorm() - x(2);
  if (!(r2 > 0)) return c;
  c.radius = std::sqrt(r2);
  double ss = 0;
  for (const Vec2& p : pts) ss += std::pow((p - c.centre).norm() - c.radius, 2);
  c.rms = std::sqrt(ss / double(pts.size()));
  return c;
}

// The angle from direction u to direction v, counter-clockwise positive.
double turn(const Vec2& u, const Vec2& v) { return std::atan2(u.x() * v.y() - u.y() * v.x(), u.dot(v)); }

// A stretch of hull vertices: `count` of them from `first` on.
struct Run {
  size_t first = 0, count = 0;
};

std::vector<Vec2> run_points(const Ring2& ring, const std::vector<Run>& runs) {
  std::vector<Vec2> out;
  for (const Run& r : runs)
    for (size_t k = 0; k < r.count; ++k) out.push_back(ring[(r.first + k) % ring.size()]);
  return out;
}

// Angle of q about c relative to `from`, in [0, 2 pi).
double angle_from(const Vec2& q, const Vec2& c, double from) {
  const double a = std::fmod(std::atan2(q.y() - c.y(), q.x() - c.x()) - from, 2 * kPi);
  return a < 0 ? a + 2 * kPi : a;
}

// A first radius from the points in the arc's sector: seen from the air
// they lie evenly over the plan, so ρ² is uniform on [0, r²] there and r
// is read from ρ²'s kRimQuantile quantile. NaN with too few points.
double sector_radius(const std::vector<Vec2>& points, const OutlineArc& arc) {
  std::vector<double> rho2;
  for (const Vec2& q : points)
    if (angle_from(q, arc.centre, arc.from) <= arc.span) rho2.push_back((q - arc.centre).squaredNorm());
  if (rho2.size() < kMinSectorPoints) return kNaN;
  return std::sqrt(quantile(std::move(rho2), kRimQuantile) / kRimQuantile);
}

// Whether the sector (to just inside the arc) lies within the polygon: the
// radius read above needs the whole sector to be roof.
bool sector_inside(const OutlineArc& arc, const MultiPolygon2& roof) {
  OutlineArc inner = arc;
  inner.radius *= kSectorInside;
  const MultiPolygon2 sector = poly::intersect({Polygon2{wedge(inner), {}}},
                                               {Polygon2{circle_ring(arc.centre, inner.radius, kMinHullTol), {}}});
  double whole = 0, in = 0;
  for (const Polygon2& p : sector) whole += area(p);
  for (const Polygon2& p : poly::intersect(sector, roof)) in += area(p);
  return whole > 0 && in >= kSectorShare * whole;
}

// The hull ring from its sharpest turn, so that no arc is cut by the ring's start.
Ring2 from_sharpest_turn(const Ring2& ring) {
  size_t start = 0;
  double sharpest = -1;
  for (size_t i = 0; i < ring.size(); ++i) {
    const Vec2 a = ring[(i + ring.size() - 1) % ring.size()], b = ring[i], c = ring[(i + 1) % ring.size()];
    const double at = std::abs(turn(b - a, c - b));
    if (at > sharpest) sharpest = at, start = i;
  }
  Ring2 out(ring.begin() + long(start), ring.end());
  out.insert(out.end(), ring.begin(), ring.begin() + long(start));
  return out;
}

// Maximal runs of at least kMinRunVertices hull vertices on one circle within tol.
std::vector<Run> circle_runs(const Ring2& ring, double tol) {
  std::vector<Run> out;
  for (size_t i = 0; i + kMinRunVertices <= ring.size();) {
    Run run{i, kMinRunVertices};
    if (fit_circle(run_points(ring, {run})).rms > tol) {
      ++i;
      continue;
    }
    while (run.first + run.count < ring.size() && fit_circle(run_points(ring, {{i, run.count + 1}})).rms <= tol)
      ++run.count;
    out.push_back(run);
    i += run.count;
  }
  return out;
}

// Neighbouring runs on one circle are one arc: the hull strays off it for a
// vertex or two where the scan left a gap. The last group may close the ring
// onto the first.
std::vector<std::vector<Run>> arc_groups(const Ring2& ring, const std::vector<Run>& runs, double tol) {
  std::vector<std::vector<Run>> groups;
  for (const Run& r : runs) {
    if (!groups.empty()) {
      std::vector<Run> joined = groups.back();
      joined.push_back(r);
      if (fit_circle(run_points(ring, joined)).rms <= tol) {
        groups.back() = std::move(joined);
        continue;
      }
    }
    groups.push_back({r});
  }
  if (groups.size() > 1) {
    std::vector<Run> joined = groups.back();
    joined.insert(joined.end(), groups.front().begin(), groups.front().end());
    if (fit_circle(run_points(ring, joined)).rms <= tol) groups.front() = joined, groups.pop_back();
  }
  return groups;
}

// The arc of a group of runs about the circle fitted to them: from its
// first vertex, turning counter-clockwise to its last (through the gaps).
// A full circle where the group leaves fewer than kMinRunVertices of the
// hull out and the hull turns once about the centre.
std::optional<OutlineArc> group_arc(const Ring2& ring, const std::vector<Run>& group) {
  const Circle c = fit_circle(run_points(ring, group));
  if (!(c.radius >= kMinRadius && c.radius <= kMaxRadius)) return std::nullopt;
  const size_t first = group.front().first, n = ring.size();
  const size_t last = (group.back().first + group.back().count - 1) % n;
  auto about_centre = [&](size_t k) { return turn(ring[k % n] - c.centre, ring[(k + 1) % n] - c.centre); };
  const size_t covered = (last + n - first) % n + 1;
  double span = 0, whole = 0;
  for (size_t k = 0; k < n; ++k) (k + 1 < covered ? span : whole) += about_centre(first + k);
  whole += span;
  OutlineArc arc{c.centre, c.radius, std::atan2(ring[first].y() - c.centre.y(), ring[first].x() - c.centre.x()), span};
  if (n - covered < kMinRunVertices && std::abs(whole - 2 * kPi) < 0.1) arc.span = 2 * kPi;
  const double bow = c.radius * (1 - std::cos(std::min(arc.span, kPi) / 2));
  if (arc.span < kMinSpan || bow < kMinBow) return std::nullopt;
  return arc;
}

// Candidate arcs: the hull's runs on one circle (radius from the hull).
std::vector<OutlineArc> candidates(const Ring2& hull, double spacing) {
  const Ring2 ring = from_sharpest_turn(hull);
  const double tol = std::max(kMinHullTol, kHullTolSpacings * spacing);
  const double join_tol = std::max(kMinHullTol, kJoinTolSpacings * spacing);
  std::vector<OutlineArc> out;
  for (const std::vector<Run>& group : arc_groups(ring, circle_runs(ring, tol), join_tol))
    if (const auto arc = group_arc(ring, group)) out.push_back(*arc);
  // A round roof whose thin scan broke the hull into runs on circles of
  // their own: the whole hull on one circle within kWholeTolSpacings.
  const bool whole = std::any_of(out.begin(), out.end(), [](const OutlineArc& a) { return a.span >= kFullTurn; });
  const Circle all = fit_circle(ring);
  if (!whole && all.rms <= kWholeTolSpacings * spacing && all.radius >= kMinRadius && all.radius <= kMaxRadius)
    out.push_back({all.centre, all.radius, 0, 2 * kPi});
  return out;
}

// Signed distance from q to the polygon's outer ring: positive outside.
double signed_distance(const Polygon2& poly, const Vec2& q) {
  double d2 = INFINITY;
  const Ring2& ring = poly.outer;
  for (size_t i = 0; i < ring.size(); ++i) {
    const Vec2 a = ring[i], ab = ring[(i + 1) % ring.size()] - a;
    const double t = std::clamp((q - a).dot(ab) / std::max(ab.squaredNorm(), 1e-18), 0.0, 1.0);
    d2 = std::min(d2, (a + t * ab - q).squaredNorm());
  }
  return in_polygon_plan(poly, q) ? -std::sqrt(d2) : std::sqrt(d2);
}

// Log-likelihood of the roof points under an outline: points spread evenly
// over its plan, blurred across its edge by a Gaussian of width `blur` (the
// scan's noise and spacing), so a point at signed distance d has density
// Phi(-d / blur) / A; and a share kStray of strays spread evenly over
// `background` (m², the points' box), so that one stray point far out does
// not outweigh the whole edge.
double log_likelihood(const std::vector<double>& distances, double plan_area, double blur, double background) {
  const double stray = kStray / background;
  double ll = 0;
  for (double d : distances)
    ll += std::log((1 - kStray) * 0.5 * std::erfc(d / (blur * std::sqrt(2.0))) / plan_area + stray);
  return ll;
}

// The area of the points' bounding box.
double box_area(const std::vector<Vec2>& points) {
  Vec2 lo = points.front(), hi = lo;
  for (const Vec2& q : points) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
  return std::max((hi - lo).prod(), 1e-6);
}

std::vector<double> signed_distances(const Polygon2& poly, const std::vector<Vec2>& points) {
  std::vector<double> d;
  d.reserve(points.size());
  for (const Vec2& q : points) d.push_back(signed_distance(poly, q));
  return d;
}

// The polygon's log-likelihood at the blur that explains the points best
// (read on a log grid).
double outline_likelihood(const Polygon2& poly, const std::vector<Vec2>& points) {
  const std::vector<double> d = signed_distances(poly, points);
  const double background = box_area(points);
  double best = -INFINITY;
  for (double s = kMinBlur; s <= kMaxBlur; s *= kBlurStep)
    best = std::max(best, log_likelihood(d, area(poly), s, background));
  return best;
}

// A circle as a counter-clockwise ring of chords of sagitta `chord`, its
// vertices a little outside so that the ring holds the circle's area.
Ring2 circle_ring(const Vec2& c, double r, double chord) {
  const int n = std::max(16, int(std::ceil(kPi / std::acos(std::max(-1.0, 1 - chord / r)))));
  const double rv = r * std::sqrt(2 * kPi / (n * std::sin(2 * kPi / n)));
  Ring2 ring;
  for (int k = 0; k < n; ++k) ring.push_back(c + rv * Vec2(std::cos(2 * kPi * k / n), std::sin(2 * kPi * k / n)));
  return ring;
}

// The sector from c over the arc's span, reaching well past it.
Ring2 wedge(const OutlineArc& arc) {
  Ring2 ring{arc.centre};
  const int steps = std::max(2, int(std::ceil(arc.span / (kPi / 18))));
  for (int k = 0; k <= steps; ++k) {
    const double a = arc.from + arc.span * k / steps;
    ring.push_back(arc.centre + 3 * arc.radius * Vec2(std::cos(a), std::sin(a)));
  }
  return ring;
}

// `polygon` with the wedge of the arc (from its centre, over its span) made
// the circle's; the circle a ring of chords of sagitta `chord` whose area is
// the circle's. The polygon unchanged where that fails.
Polygon2 with_arc(const Polygon2& polygon, const OutlineArc& arc, double chord) {
  const Polygon2 disc{circle_ring(arc.centre, arc.radius, chord), {}};
  if (arc.span >= kFullTurn) return disc;
  const MultiPolygon2 w{Polygon2{wedge(arc), {}}};
  // The disc's sector added, then the wedge beyond the circle taken away:
  // no step of the two joins where the polygon crosses the wedge's rays.
  const MultiPolygon2 out =
      poly::subtract(poly::unite({polygon}, poly::intersect(w, {disc})), poly::subtract(w, {disc}));
  const MultiPolygon2 valid = poly::make_valid(out);
  if (valid.empty()) return polygon;
  Polygon2 best = poly::largest(valid);
  best.holes.clear();
  // Without the vertices the overlay left on straight runs (a chord cut
  // where the polygon crossed it): they would split an arc's chords. (GEOS's
  // simplifiers keep a ring's first vertex.)
  Ring2& ring = best.outer;
  for (size_t i = 0; ring.size() > 3 && i < ring.size();) {
    const Vec2 a = ring[(i + ring.size() - 1) % ring.size()], b = ring[i], c = ring[(i + 1) % ring.size()];
    const Vec2 d = (c - a).normalized();
    if (std::abs(d.x() * (b - a).y() - d.y() * (b - a).x()) < kCollinear && (b - a).dot(c - b) > 0)
      ring.erase(ring.begin() + long(i));
    else
      ++i;
  }
  return best;
}

// The vertices of a ring that are no arc's (arcs_in_ring): its corners.
size_t corners(const Ring2& ring) {
  const std::vector<int> arc = arcs_in_ring(ring).of_edge;
  size_t n = 0;
  for (size_t i = 0; i < ring.size(); ++i) n += arc[i] < 0 || arc[(i + ring.size() - 1) % ring.size()] < 0;
  return n;
}

// The arc's circle and the edge's blur that explain the points best, with
// `polygon` so curved, and its log-likelihood (-inf where the arc cannot be
// drawn).
class ArcFit : public cv::MinProblemSolver::Function {
 public:
  ArcFit(const Polygon2& polygon, const OutlineArc& arc, const std::vector<Vec2>& points, double chord)
      : polygon_(polygon), arc_(arc), points_(points), chord_(chord), background_(box_area(points)) {}
  int getDims() const override { return 4; }  // centre x, y, radius, log blur
  double calc(const double* x) const override {
    const Polygon2 p = drawn(x);
    if (p.outer.size() < 3 || !(x[2] >= kMinRadius && x[2] <= kMaxRadius)) return kHuge;
    return -log_likelihood(signed_distances(p, points_), area(p), std::exp(x[3]), background_);
  }
  Polygon2 drawn(const double* x) const {
    OutlineArc a = arc_;
    a.centre = Vec2(x[0], x[1]), a.radius = x[2];
    return with_arc(polygon_, a, chord_);
  }

 private:
  static constexpr double kHuge = 1e300;
  const Polygon2& polygon_;
  const OutlineArc arc_;
  const std::vector<Vec2>& points_;
  const double chord_;
  const double background_;
};

OutlineArc most_likely_arc(const Polygon2& polygon, const OutlineArc& arc, const std::vector<Vec2>& points,
                           double chord) {
  const cv::Ptr<ArcFit> fit = cv::makePtr<ArcFit>(polygon, arc, points, chord);
  cv::Mat x = (cv::Mat_<double>(1, 4) << arc.centre.x(), arc.centre.y(), arc.radius, std::log(0.05));
  const cv::Mat step = (cv::Mat_<double>(1, 4) << kStepCentre, kStepCentre, kStepCentre, kStepLogBlur);
  const cv::Ptr<cv::DownhillSolver> solver = cv::DownhillSolver::create(
      fit, step, cv::TermCriteria(cv::TermCriteria::MAX_ITER + cv::TermCriteria::EPS, kMaxSteps, kStopChange));
  solver->minimize(x);
  OutlineArc out = arc;
  out.centre = Vec2(x.at<double>(0), x.at<double>(1)), out.radius = x.at<double>(2);
  return out;
}

// Distance from c to the polygon's boundary along angle a, the crossing
// nearest to r (r itself where the ray meets none).
double ray_to_polygon(const Polygon2& poly, const Vec2& c, double a, double r) {
  const Vec2 u(std::cos(a), std::sin(a));
  double best = r, nearest = INFINITY;
  const Ring2& ring = poly.outer;
  for (size_t i = 0; i < ring.size(); ++i) {
    const Vec2 p = ring[i], d = ring[(i + 1) % ring.size()] - p, w = p - c;
    const double den = u.x() * d.y() - u.y() * d.x();
    if (std::abs(den) < 1e-12) continue;
    const double t = (w.x() * d.y() - w.y() * d.x()) / den, s = (w.x() * u.y() - w.y() * u.x()) / den;
    if (t > 0 && s >= 0 && s <= 1 && std::abs(t - r) < nearest) nearest = std::abs(t - r), best = t;
  }
  return best;
}

// The hull's run ends near, not at, where a curve meets a straight edge
// (there the two are alike): each end of the arc moves, a degree at a time
// and by 45 degrees at most either way, to where the circle comes nearest
// to the outline along the ray from its centre (where it crosses an edge,
// or touches a tangent one), the nearer move on a tie.
OutlineArc met_ends(OutlineArc arc, const Polygon2& polygon) {
  if (arc.span >= kFullTurn) return arc;
  auto gap = [&](double a) { return std::abs(ray_to_polygon(polygon, arc.centre, a, arc.radius) - arc.radius); };
  const int steps = int(std::round(kMaxEndMove / kEndStep));
  for (const int side : {-1, 1}) {
    const double end = side < 0 ? arc.from : arc.from + arc.span;
    int best = 0;
    double nearest = gap(end);
    for (int k = 1; k <= steps; ++k)
      for (const int sign : {-1, 1}) {
        const double span = arc.span + sign * k * kEndStep;
        if (span < kMinSpan || span >= kFullTurn) continue;
        const double g = gap(end + side * sign * k * kEndStep);
        if (g < nearest - kSameGap) nearest = g, best = sign * k;
      }
    if (side < 0) arc.from -= best * kEndStep;
    arc.span += best * kEndStep;
  }
  return arc;
}

// Run of `len` gentle vertices from `first`: an arc where they lie on one
// circle within kOnCircle, its vertices' edges both ways, and past each end
// a vertex on the circle with its chord to where the arc meets a straight
// edge (at most half as long again as the arc's chords).
void add_arc(const Ring2& ring, size_t first, size_t len, RingArcs& out) {
  const size_t n = ring.size();
  std::vector<Vec2> pts;
  for (size_t m = 0; m < len; ++m) pts.push_back(ring[(first + m) % n]);
  const Circle c = fit_circle(pts);
  if (!(c.radius >= kMinRadius && c.radius <= kMaxRadius)) return;
  auto off = [&](const Vec2& p) { return std::abs((p - c.centre).norm() - c.radius); };
  for (const Vec2& p : pts)
    if (off(p) > kOnCircle) return;
  const int id = int(out.arcs.size());
  double chord = 0;
  for (size_t m = 0; m < len; ++m) {
    const size_t v = (first + m) % n;
    out.of_edge[(v + n - 1) % n] = id, out.of_edge[v] = id;
    chord = std::max(chord, (ring[(v + 1) % n] - ring[v]).norm());
  }
  if (len < n) {
    const size_t before = (first + n - 1) % n, after = (first + len) % n;
    if (off(ring[before]) <= kOnCircle && (ring[before] - ring[(before + n - 1) % n]).norm() <= kJunctionChord * chord)
      out.of_edge[(before + n - 1) % n] = id;
    if (off(ring[after]) <= kOnCircle && (ring[(after + 1) % n] - ring[after]).norm() <= kJunctionChord * chord)
      out.of_edge[after] = id;
  }
  out.arcs.push_back({c.centre, c.radius});
}

}  // namespace

RingArcs arcs_in_ring(const Ring2& ring) {
  const size_t n = ring.size();
  RingArcs out;
  out.of_edge.assign(n, -1);
  if (n < kMinArcVertices) return out;
  std::vector<bool> gentle(n);  // turning left by a chord's angle at most
  for (size_t i = 0; i < n; ++i) {
    const double at = turn(ring[i] - ring[(i + n - 1) % n], ring[(i + 1) % n] - ring[i]);
    gentle[i] = at > 0 && at <= kMaxChordTurn;
  }
  // Start after a vertex that is not gentle, so that no run is cut by the
  // ring's start; a whole circle has none.
  size_t start = 0;
  while (start < n && gentle[start]) ++start;
  const bool whole = start == n;
  for (size_t k = 1; k <= n;) {
    size_t len = 0;
    while (k + len <= n && gentle[(start + k + len) % n]) ++len;
    if (len >= kMinArcVertices) add_arc(ring, (start + k) % n, whole ? n : len, out);
    k += std::max<size_t>(len, 1);
  }
  return out;
}

Polygon2 with_outline_arcs(const Ring2& hull, const Polygon2& polygon, const std::vector<Vec2>& points,
                           double spacing, double chord) {
  if (hull.size() < kMinRunVertices || polygon.outer.size() < 3) return polygon;
  Polygon2 out = polygon;
  // Where the points are: the hull, and the outline where its edges reach past the hull's teeth.
  const MultiPolygon2 roof = poly::unite({Polygon2{hull, {}}}, {polygon});
  const double per_parameter = std::log(double(points.size())) / 2;  // the BIC's, on the log-likelihood
  double likelihood = outline_likelihood(out, points);
  for (const OutlineArc& arc : candidates(hull, spacing)) {
    if (!in_polygon_plan(out, arc.centre)) continue;  // a concave arc (centre outside the roof) stays straight
    // An arc round most of the turn may be a round roof whose hull strays
    // where the scan is thin or clutter stands: the whole circle is tried
    // too. Between the two, each corner the arc leaves counts two parameters.
    std::vector<OutlineArc> variants{arc};
    if (arc.span >= kMostOfTurn && arc.span < kFullTurn) variants.push_back({arc.centre, arc.radius, arc.from, 2 * kPi});
    std::pair<Polygon2, double> best{{}, -INFINITY};
    double best_score = -INFINITY;
    for (OutlineArc v : variants) {
      v.radius = sector_radius(points, v);
      if (std::isnan(v.radius) || !sector_inside(v, roof)) continue;
      Polygon2 curved = with_arc(out, met_ends(most_likely_arc(out, v, points, chord), out), chord);
      const double l = outline_likelihood(curved, points);
      const double score = l - 2 * per_parameter * double(corners(curved.outer));
      if (score > best_score) best_score = score, best = {std::move(curved), l};
    }
    // Kept where its three parameters (centre, radius) buy more than their
    // share of the criterion: the straight edges it replaces were placed by
    // the outline's rules, not fitted, and are not counted (counted, a
    // regular octagon at 10 pts/m² became a circle in 20 scans of 20).
    if (best.second - likelihood > kArcParameters * per_parameter) out = best.first, likelihood = best.second;
  }
  return out;
}

}  // namespace c3d
