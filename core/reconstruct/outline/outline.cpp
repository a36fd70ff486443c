#include "core/reconstruct/outline/outline.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "core/geometry/geometry.h"
#include "core/geometry/polygon_ops.h"
#include "core/reconstruct/outline/arcs.h"

namespace c3d {
namespace {

// Internal thresholds, each with its reason. Lengths in m, areas in m^2.
// Regularising edges (both outlines).
constexpr double kMergeAngleDeg = 2.0;       // consecutive edges nearer parallel than this may be one line...
constexpr double kMergeOffset = 0.3;         // ...when their lines are at most this far apart
constexpr double kDiagonalTolShare = 0.5;    // a 45-degree snap takes half the axis tolerance: diagonals are rarer
constexpr double kObliqueWeight = 0.5;       // an oblique edge counts as half its length: real corner cuts are square or 45
constexpr double kParallelCos = 0.995;       // neighbours of a short edge this near parallel make a jog...
constexpr double kMaxJog = 0.35;             // ...one straight edge when their offset is below this
constexpr double kMinNotchEnd = 0.1;         // a notch's end this wide or wider stays
constexpr double kCornerReachEdges = 2.0;    // neighbours meet at most this many min_len from a dropped edge
constexpr double kMinOutlinePart = 0.5;      // parts of a rebuilt outline smaller than this are slivers
constexpr double kMaxRegularizeChange = 0.05;  // a footprint changing area by more was regularised wrongly
constexpr double kPeakWindowDeg = 10.0;      // edges this near the direction histogram's peak set the axes
// Placing each edge where the point density ends (roof outline).
constexpr size_t kMinOutlinePoints = 10;     // fewer points make no outline
constexpr double kHullMinAlpha = 1.0;        // the concave hull bridges gaps of a metre at least...
constexpr double kHullSpacings = 5.0;        // ...and of 5 point spacings, so a sparse roof holds together
constexpr double kSimplifyMin = 0.15;        // the hull simplified by at least this...
constexpr double kSimplifySpacings = 1.5;    // ...and by 1.5 point spacings: its teeth are a spacing deep
constexpr double kRoofMinEdge = 1.5;         // shorter roof outline edges are hull chamfers at corners
constexpr double kEdgeEndMargin = 0.5;       // an edge's ends belong to the corners: up to this much...
constexpr double kEdgeEndShare = 0.2;        // ...or a fifth of the edge is left out at each end
constexpr double kFallbackSpacings = 0.5;    // an edge too short to measure moves half a spacing out
constexpr double kArcChord = 0.02;           // an arc's chords within 2 cm of it, as the exports' (their area the circle's)
constexpr double kMaxRebuildChange = 0.3;    // an outline changing the hull's area by more went wrong
constexpr double kDensityBeyond = 1.0;       // points further out than this are not the roof's
constexpr long kMinBandPoints = 15;          // fewer points in the density band measure nothing
// Maximum-likelihood edges (refine_edges).
constexpr double kMinRefineArea = 4.0;       // smaller outlines are left as the density placed them
constexpr double kTurnPadShare = 0.02;       // a degree's turn moves an edge's ends by under 2 % of its length...
constexpr double kTurnPad = 0.1;             // ...plus this, the points it may see
constexpr double kMinSigma = 0.005;          // the planimetric noise searched from 5 mm...
constexpr double kMaxSigma = 0.15;           // ...to 15 cm
constexpr double kMaxTurnDeg = 1.0;          // the building turned by at most a degree: the hull is good to 0.3
constexpr double kMaxMleShift = 0.3;         // a larger shift means the edge saw another roof's points
constexpr double kMinSampledEdge = 1.0;      // the middle of an edge shorter than this holds too few points
constexpr double kMinEdgePoints = 10.0;      // expected points in the band inside an edge to place it
constexpr double kTailSigmas = 8.0;          // points more than 8 sigma inside add nothing (Phi = 1)
constexpr double kBoundSigmas = 3.0;         // the edge searched 3 sigma within the band's ends
constexpr double kBracket = 0.1;             // the first pass leaves the edge within this: bracket there first

struct EdgeLine {
  Vec2 origin;   // a point on the line
  Vec2 dir;      // unit direction, ring order
  double t0 = 0, t1 = 0;  // extent along dir from origin
  bool keep = false;      // a short edge that is a real step of the outline
  bool oblique = false;   // off the building's axes and diagonals: likely a hull chamfer
};

Vec2 outward(const Vec2& dir) { return Vec2(dir.y(), -dir.x()); }  // CCW ring

double wrap_quarter(double a) {
  a = std::fmod(a, M_PI / 2);
  return a < 0 ? a + M_PI / 2 : a;
}

// Snaps an edge direction to the dominant axes (0/90) or their diagonals (45).
Vec2 snap_direction(const Vec2& dir, double dominant, double tol) {
  double a = std::atan2(dir.y(), dir.x());
  for (int k = -8; k <= 8; ++k) {
    double axis = dominant + k * M_PI / 4;
    double diff = std::remainder(a - axis, 2 * M_PI);
    double lim = (k % 2 == 0) ? tol : tol * kDiagonalTolShare;  // 45 degree snaps are stricter
    if (std::abs(diff) < lim) return Vec2(std::cos(axis), std::sin(axis));
  }
  return dir;
}

std::optional<Vec2> line_intersection(const EdgeLine& a, const EdgeLine& b) {
  return intersect_lines(a.origin, a.dir, b.origin, b.dir);
}

// Consecutive edges with (nearly) the same snapped direction and offset are one line.
std::vector<EdgeLine> merge_collinear(std::vector<EdgeLine> lines) {
  bool changed = true;
  while (changed && lines.size() > 3) {
    changed = false;
    for (size_t i = 0; i < lines.size(); ++i) {
      EdgeLine& a = lines[i];
      EdgeLine& b = lines[(i + 1) % lines.size()];
      if (a.dir.dot(b.dir) < std::cos(kMergeAngleDeg * M_PI / 180)) continue;
      double off = std::abs(outward(a.dir).dot(b.origin - a.origin));
      if (off > kMergeOffset) continue;
      Vec2 start = a.origin + a.t0 * a.dir, end = b.origin + b.t1 * b.dir;
      double la = a.t1 - a.t0, lb = b.t1 - b.t0;
      EdgeLine m;
      m.dir = a.dir;
      // Offset: length-weighted mean of both lines.
      double sb = outward(a.dir).dot(b.origin - a.origin);
      m.origin = a.origin + outward(a.dir) * (sb * lb / (la + lb));
      m.t0 = m.dir.dot(start - m.origin);
      m.t1 = m.dir.dot(end - m.origin);
      lines[i] = m;
      lines.erase(lines.begin() + long((i + 1) % lines.size()));
      changed = true;
      break;
    }
  }
  return lines;
}

// Short edges at corners (chamfers left by the hull) are removed by extending
// their neighbours until they meet, when that point is close by. An oblique
// edge counts as half its length: a real corner cut is square or 45 degrees.
// With keep_notch_ends, the end (10 cm or wider) of a narrow notch stays: its
// sides, sharper than 30 degrees, would otherwise run on into a spike. Used
// on footprints, where such wedges were seen (05792, 09365); the roof hull's
// outline, whose edges the density moves afterwards, keeps the older rule.
constexpr double kCos30 = 0.8660254037844386;

std::vector<EdgeLine> drop_short_edges(std::vector<EdgeLine> lines, double min_len,
                                       bool keep_notch_ends) {
  auto weight = [](const EdgeLine& l) { return (l.t1 - l.t0) * (l.oblique ? kObliqueWeight : 1.0); };
  while (lines.size() > 3) {
    size_t k = 0;
    double shortest = 1e18;
    for (size_t i = 0; i < lines.size(); ++i)
      if (!lines[i].keep && weight(lines[i]) < shortest) shortest = weight(lines[i]), k = i;
    if (shortest >= min_len) break;
    size_t n = lines.size();
    EdgeLine& prev = lines[(k + n - 1) % n];
    EdgeLine& next = lines[(k + 1) % n];
    auto p = line_intersection(prev, next);
    Vec2 mid = lines[k].origin + 0.5 * (lines[k].t0 + lines[k].t1) * lines[k].dir;
    double jog = std::abs(outward(prev.dir).dot(next.origin - prev.origin));
    if (prev.dir.dot(next.dir) > kParallelCos && jog < kMaxJog) {
      // A small jog between two parallel edges: one straight edge.
      Vec2 start = prev.origin + prev.t0 * prev.dir, end = next.origin + next.t1 * next.dir;
      double lp = prev.t1 - prev.t0, ln = next.t1 - next.t0;
      EdgeLine m = prev;
      m.origin = prev.origin + outward(prev.dir) * (outward(prev.dir).dot(next.origin - prev.origin) * ln / (lp + ln));
      m.t0 = m.dir.dot(start - m.origin);
      m.t1 = m.dir.dot(end - m.origin);
      size_t kn = (k + 1) % n, kp = (k + n - 1) % n;
      lines[kp] = m;
      // erase the short edge and the absorbed next edge (higher index first)
      std::vector<size_t> gone{k, kn};
      std::sort(gone.rbegin(), gone.rend());
      for (size_t g : gone) lines.erase(lines.begin() + long(g));
      continue;
    }
    const bool notch_end =
        keep_notch_ends && prev.dir.dot(next.dir) < -kCos30 && lines[k].t1 - lines[k].t0 >= kMinNotchEnd;
    if (!p || (*p - mid).norm() > kCornerReachEdges * min_len || notch_end) {
      lines[k].keep = true;  // a real step of the outline, or a notch's end
      continue;
    }
    prev.t1 = prev.dir.dot(*p - prev.origin);
    next.t0 = next.dir.dot(*p - next.origin);
    lines.erase(lines.begin() + long(k));
  }
  return lines;
}

Ring2 rebuild_ring(const std::vector<EdgeLine>& lines) {
  Ring2 ring;
  for (size_t i = 0; i < lines.size(); ++i) {
    const EdgeLine& prev = lines[(i + lines.size() - 1) % lines.size()];
    const EdgeLine& cur = lines[i];
    if (auto p = line_intersection(prev, cur)) {
      ring.push_back(*p);
    } else {  // parallel: join with a short perpendicular step
      Vec2 end = prev.origin + prev.t1 * prev.dir;
      ring.push_back(end);
      ring.push_back(cur.origin + cur.dir * cur.dir.dot(end - cur.origin));
    }
  }
  return ring;
}

// Second pass: maximum likelihood. Across a straight roof edge the plan
// density is rho * Phi((e - s) / sigma): uniform inside, blurred by the
// planimetric noise sigma. With rho known from the whole roof (points / first
// outline area, precise to about 1 %), every point near the edge informs e, not
// only the count beyond a line: about 1 cm instead of 2.5 cm at 40 pts/m2 and
// 3 cm noise. sigma is shared by the roof's edges and fitted with them. A small
// floor on the density keeps a stray point beyond the edge from dragging it out.
struct EdgeSample {
  std::vector<double> s;  // offsets (outward) of the points near the edge
  double expected = 0;    // rho * measured length: points per metre of offset
};

constexpr double kBand = 0.5;       // points from this far inside the edge...
constexpr double kBeyond = 1.0;     // ...to this far outside inform it
constexpr double kStray = 0.01;     // density floor beyond the edge, share of rho

double normal_cdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }
double normal_pdf(double z) { return std::exp(-0.5 * z * z) / std::sqrt(2 * M_PI); }

// The edge offset maximising the likelihood for a given sigma (the score is
// decreasing in e, so bisection), and that likelihood.
// es.s is sorted: points more than 8 sigma inside the edge add nothing to the
// score or the likelihood (Phi = 1), so only the tail beyond is visited.
std::pair<double, double> edge_mle(const EdgeSample& es, double sigma) {
  auto near = [&](double e) { return std::lower_bound(es.s.begin(), es.s.end(), e - kTailSigmas * sigma); };
  auto score = [&](double e) {
    double g = 0;
    for (auto it = near(e); it != es.s.end(); ++it) {
      double z = (e - *it) / sigma;
      g += normal_pdf(z) / (sigma * (normal_cdf(z) + kStray));
    }
    return g - es.expected;
  };
  double lo = -kBand + kBoundSigmas * sigma, hi = kBeyond - kBoundSigmas * sigma;
  if (lo >= hi) return {0.0, -1e300};
  // The first pass leaves the edge within centimetres: bracket there first.
  const double a = std::max(lo, -kBracket), b = std::min(hi, kBracket);
  const bool near_zero = score(a) > 0 && score(b) < 0;
  if (near_zero) lo = a, hi = b;
  for (int it = near_zero ? 11 : 14; it > 0; --it) {  // to 0.1 mm
    double mid = 0.5 * (lo + hi);
    (score(mid) > 0 ? lo : hi) = mid;
  }
  double e = 0.5 * (lo + hi), ll = -es.expected * (e + kBand);
  // Per point log((Phi + stray) / (1 + stray)): zero deep inside, so the
  // skipped points leave the comparison between sigmas unchanged.
  for (auto it = near(e); it != es.s.end(); ++it)
    ll += std::log((normal_cdf((e - *it) / sigma) + kStray) / (1 + kStray));
  return {e, ll};
}

// The points near one edge, as offsets across it (only its middle: the
// corners belong to two edges); empty when too few to place it.
EdgeSample sample_edge(const std::vector<Vec2>& points, const EdgeLine& l, double density) {
  EdgeSample es;
  double margin = std::min(kEdgeEndMargin, kEdgeEndShare * (l.t1 - l.t0));  // as sampled_edge_length
  double t0 = l.t0 + margin, t1 = l.t1 - margin;
  if (t1 - t0 < kMinSampledEdge) return es;
  Vec2 n = outward(l.dir);
  for (const auto& p : points) {
    Vec2 q = p - l.origin;
    double t = l.dir.dot(q), s = n.dot(q);
    if (t >= t0 && t <= t1 && s >= -kBand && s <= kBeyond) es.s.push_back(s);
  }
  std::sort(es.s.begin(), es.s.end());
  es.expected = density * (t1 - t0);
  if (es.expected * kBand < kMinEdgePoints) es.s.clear();  // too few to place it
  return es;
}

// Maximum of f on [lo, hi] by golden-section search (f unimodal there).
template <class F>
double golden_max(F f, double lo, double hi, int iterations) {
  const double g = (std::sqrt(5.0) - 1) / 2;
  double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
  double f1 = f(x1), f2 = f(x2);
  for (int it = 0; it < iterations; ++it) {
    if (f1 > f2) hi = x2, x2 = x1, f2 = f1, x1 = hi - g * (hi - lo), f1 = f(x1);
    else lo = x1, x1 = x2, f1 = f2, x2 = lo + g * (hi - lo), f2 = f(x2);
  }
  return 0.5 * (x1 + x2);
}

// The edges on the building's axes and diagonals turned by `angle` about their
// midpoints (oblique edges keep their own direction).
std::vector<EdgeLine> turned(const std::vector<EdgeLine>& lines, double angle) {
  std::vector<EdgeLine> out = lines;
  const double c = std::cos(angle), s = std::sin(angle);
  for (auto& l : out) {
    if (l.oblique) continue;
    Vec2 mid = l.origin + 0.5 * (l.t0 + l.t1) * l.dir;
    double half = 0.5 * (l.t1 - l.t0);
    l.dir = Vec2(c * l.dir.x() - s * l.dir.y(), s * l.dir.x() + c * l.dir.y());
    l.origin = mid;
    l.t0 = -half, l.t1 = half;
  }
  return out;
}

void refine_edges(const std::vector<Vec2>& points, std::vector<EdgeLine>& lines, bool turn_axes) {
  Ring2 first = rebuild_ring(lines);
  double a = std::abs(signed_area(first));
  if (a < kMinRefineArea) return;
  double density = double(points.size()) / a;
  // The points each edge can see while it turns (a degree moves its ends by
  // under 1 % of its length), gathered once.
  std::vector<std::vector<Vec2>> near(lines.size());
  for (size_t i = 0; i < lines.size(); ++i) {
    const EdgeLine& l = lines[i];
    const double pad = kTurnPadShare * (l.t1 - l.t0) + kTurnPad;
    const Vec2 n = outward(l.dir);
    for (const auto& p : points) {
      Vec2 q = p - l.origin;
      double t = l.dir.dot(q), s = n.dot(q);
      if (t >= l.t0 - pad && t <= l.t1 + pad && s >= -kBand - pad && s <= kBeyond + pad) near[i].push_back(p);
    }
  }
  auto samples_of = [&](const std::vector<EdgeLine>& ls) {
    std::vector<EdgeSample> out;
    for (size_t i = 0; i < ls.size(); ++i) out.push_back(sample_edge(near[i], ls[i], density));
    return out;
  };
  auto total = [](const std::vector<EdgeSample>& samples, double sigma) {
    double ll = 0;
    for (const auto& es : samples)
      if (!es.s.empty()) ll += edge_mle(es, sigma).second;
    return ll;
  };
  // sigma shared by the edges (log scale, to about 0.3 %) ...
  auto fit_sigma = [&](const std::vector<EdgeSample>& samples, double lo, double hi, int iterations) {
    return std::exp(golden_max([&](double x) { return total(samples, std::exp(x)); }, std::log(lo),
                               std::log(hi), iterations));
  };
  std::vector<EdgeSample> samples = samples_of(lines);
  double sigma = fit_sigma(samples, kMinSigma, kMaxSigma, turn_axes ? 9 : 13);  // refined again once turned
  // ... and the building's orientation: the hull's edge directions are good to
  // about 0.3 degrees, which at the ends of a 12 m edge is 3 cm, as much as
  // the noise. One turn for all axis edges, within a degree, to 0.02 degree.
  if (turn_axes) {
    const double limit = kMaxTurnDeg * M_PI / 180;
    double turn = golden_max([&](double t) { return total(samples_of(turned(lines, t)), sigma); }, -limit,
                             limit, 9);
    lines = turned(lines, turn);
    samples = samples_of(lines);
    sigma = fit_sigma(samples, sigma / 1.5, sigma * 1.5, 8);
  }
  for (size_t i = 0; i < lines.size(); ++i) {
    if (samples[i].s.empty()) continue;
    double off = edge_mle(samples[i], sigma).first;
    if (std::abs(off) < kMaxMleShift) lines[i].origin += outward(lines[i].dir) * off;
  }
}

}  // namespace

double sampled_edge_length(double length) {
  return length - 2 * std::min(kEdgeEndMargin, kEdgeEndShare * length);
}

Polygon2 regularize_polygon(const Polygon2& poly, double min_edge) {
  const Ring2& ring = poly.outer;
  std::vector<EdgeLine> lines;
  for (size_t i = 0; i < ring.size(); ++i) {
    Vec2 a = ring[i], b = ring[(i + 1) % ring.size()];
    if ((b - a).norm() < 1e-6) continue;
    EdgeLine l;
    l.dir = (b - a).normalized();
    l.origin = 0.5 * (a + b);
    l.t0 = l.dir.dot(a - l.origin);
    l.t1 = l.dir.dot(b - l.origin);
    lines.push_back(l);
  }
  lines = merge_collinear(drop_short_edges(merge_collinear(lines), min_edge, true));
  if (lines.size() < 3) return poly;
  Polygon2 out{rebuild_ring(lines), {}};
  MultiPolygon2 valid = poly::drop_small(poly::make_valid({out}), kMinOutlinePart);
  if (valid.empty()) return poly;
  Polygon2 best = poly::largest(valid);
  if (std::abs(area(best) - area(poly)) > kMaxRegularizeChange * area(poly)) return poly;
  best.holes.clear();
  return best;
}

double dominant_direction(const Ring2& ring) {
  // Length-weighted circular mean of 4*angle (period 90 degrees), refined once
  // around the histogram peak so short noisy edges do not pull it.
  std::vector<double> hist(90, 0.0);
  for (size_t i = 0; i < ring.size(); ++i) {
    Vec2 e = ring[(i + 1) % ring.size()] - ring[i];
    double a = wrap_quarter(std::atan2(e.y(), e.x()));
    hist[std::min(89, int(a * 180 / M_PI))] += e.norm();
  }
  int peak = int(std::max_element(hist.begin(), hist.end()) - hist.begin());
  double sx = 0, sy = 0;
  for (size_t i = 0; i < ring.size(); ++i) {
    Vec2 e = ring[(i + 1) % ring.size()] - ring[i];
    double a = wrap_quarter(std::atan2(e.y(), e.x()));
    double diff = std::remainder(a - (peak + 0.5) * M_PI / 180, M_PI / 2);
    if (std::abs(diff) > kPeakWindowDeg * M_PI / 180) continue;
    sx += e.norm() * std::cos(4 * a);
    sy += e.norm() * std::sin(4 * a);
  }
  return wrap_quarter(std::atan2(sy, sx) / 4);
}

double density_edge_offset(const std::vector<Vec2>& points, const Vec2& origin, const Vec2& dir,
                           double t0, double t1) {
  // For a uniform point density that stops at the edge (blurred by any
  // symmetric noise), the points beyond a reference line inside the edge
  // number density * (edge - reference): solve for the edge.
  const double inner0 = -1.0, inner1 = -0.45;  // density band, m inside the current line
  Vec2 n = outward(dir);
  long band = 0, beyond = 0;
  for (const auto& p : points) {
    Vec2 q = p - origin;
    double t = dir.dot(q);
    if (t < t0 || t > t1) continue;
    double s = n.dot(q);
    if (s > kDensityBeyond) continue;
    if (s >= inner0 && s < inner1) ++band;
    else if (s >= inner1) ++beyond;
  }
  if (band < kMinBandPoints) return kNaN;
  double per_metre = band / (inner1 - inner0);
  return inner1 + beyond / per_metre;
}

Polygon2 roof_outline(const std::vector<Vec2>& points, const OutlineOptions& opt) {
  if (points.size() < kMinOutlinePoints) return {};
  MultiPolygon2 hull = poly::concave_hull(points, std::max(kHullMinAlpha, kHullSpacings * opt.spacing));
  if (hull.empty()) return {};
  Polygon2 biggest = poly::largest(hull);
  biggest.holes.clear();
  MultiPolygon2 simple = poly::simplify({biggest}, std::max(kSimplifyMin, kSimplifySpacings * opt.spacing));
  if (simple.empty() || simple[0].outer.size() < 3) return {};
  Ring2 ring = simple[0].outer;
  double dominant = dominant_direction(ring);

  std::vector<EdgeLine> lines;
  for (size_t i = 0; i < ring.size(); ++i) {
    Vec2 a = ring[i], b = ring[(i + 1) % ring.size()];
    if ((b - a).norm() < 1e-6) continue;
    EdgeLine l;
    Vec2 raw = (b - a).normalized();
    l.dir = snap_direction(raw, dominant, opt.snap_angle_deg * M_PI / 180);
    l.oblique = l.dir == raw;  // no axis or diagonal near it
    l.origin = 0.5 * (a + b);
    l.t0 = l.dir.dot(a - l.origin);
    l.t1 = l.dir.dot(b - l.origin);
    lines.push_back(l);
  }
  lines = merge_collinear(lines);
  lines = drop_short_edges(lines, kRoofMinEdge, false);
  lines = merge_collinear(lines);
  if (lines.size() < 3) return {};
  // Move every edge to where the density says the roof ends.
  for (auto& l : lines) {
    double len = l.t1 - l.t0;
    double margin = std::min(kEdgeEndMargin, kEdgeEndShare * len);
    double off = density_edge_offset(points, l.origin, l.dir, l.t0 + margin, l.t1 - margin);
    if (std::isnan(off)) off = kFallbackSpacings * opt.spacing;  // too short to measure
    l.origin += outward(l.dir) * off;
  }
  refine_edges(points, lines, opt.refine_orientation);
  Polygon2 out{rebuild_ring(lines), {}};
  MultiPolygon2 valid = poly::drop_small(poly::make_valid({out}), kMinOutlinePart);
  if (valid.empty()) return {};
  Polygon2 best = poly::largest(valid);
  // A rebuilt outline far from the hull means the regularisation went wrong.
  if (std::abs(area(best) - area(biggest)) > kMaxRebuildChange * area(biggest)) return biggest;
  best.holes.clear();
  // Where a run of the hull lies on a circle the points' edge follows, the
  // roof ends on that circle (arcs.h).
  return with_outline_arcs(biggest.outer, best, points, opt.spacing, kArcChord);
}

}  // namespace c3d
