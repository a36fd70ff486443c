#include "core/reconstruct/lod13/regularise.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/geometry/geometry.h"
#include "core/geometry/polygon_ops.h"
#include "core/reconstruct/outline/outline.h"

namespace c3d::lod13 {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180;
// Walls within this angle of each other are made parallel (the paper's
// parallel-wall prior; outlines from ~10 points/m^2 wander by 2-3 degrees).
constexpr double kParallelDeg = 5;
// A wall within this angle of the building's axes (every 45 degrees) is put
// on them: corners of 90 and 135 degrees.
constexpr double kCornerDeg = 10;
// Lines this close to parallel count as parallel when aligning and joining.
constexpr double kSameDirectionDeg = 1;
// Two consecutive lines closer to parallel than this meet too far away:
// they are joined by a square connector instead.
constexpr double kMeetSin = 0.0087;  // sin(0.5 degrees)
// Parallel neighbours nearer than this are one line.
constexpr double kCollinearM = 1e-3;

double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// Direction of a line modulo 180 degrees, in [0, pi).
double angle_of(const Vec2& d) {
  double a = std::atan2(d.y(), d.x());
  while (a < 0) a += kPi;
  while (a >= kPi) a -= kPi;
  return a;
}

// Smallest difference between two directions modulo 180 degrees.
double angle_between(double a, double b) {
  const double d = std::fmod(std::fabs(a - b), kPi);
  return std::min(d, kPi - d);
}

// The segment turned about its midpoint to direction `angle` (its sense kept).
Segment turned(const Segment& s, double angle) {
  Vec2 d(std::cos(angle), std::sin(angle));
  if (d.dot(s.b - s.a) < 0) d = -d;
  const Vec2 m = 0.5 * (s.a + s.b);
  const double h = 0.5 * s.length();
  return {m - h * d, m + h * d};
}

// The segment moved square to itself onto the parallel line through p.
Segment moved_onto(const Segment& s, const Vec2& p) {
  const Vec2 n(-s.dir().y(), s.dir().x());
  const Vec2 shift = n * n.dot(p - s.a);
  return {s.a + shift, s.b + shift};
}

// Offset of the line through p along the normal of direction d.
double offset(const Vec2& d, const Vec2& p) { return cross2(d, p); }

// Parallel walls: directions within kParallelDeg gather (longest first) and
// take their length-weighted mean.
std::vector<Segment> parallel_walls(std::vector<Segment> s) {
  std::vector<size_t> order(s.size());
  for (size_t i = 0; i < s.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](size_t i, size_t j) { return s[i].length() > s[j].length(); });
  std::vector<int> group(s.size(), -1);
  std::vector<std::pair<double, double>> seed;  // per group: direction of its longest, sum of 2-angle vectors
  std::vector<Vec2> sum;
  for (size_t i : order) {
    const double a = angle_of(s[i].dir());
    for (size_t g = 0; g < seed.size() && group[i] < 0; ++g)
      if (angle_between(a, seed[g].first) < kParallelDeg * kDeg) group[i] = int(g);
    if (group[i] < 0) {
      group[i] = int(seed.size());
      seed.push_back({a, 0});
      sum.push_back(Vec2::Zero());
    }
    sum[size_t(group[i])] += s[i].length() * Vec2(std::cos(2 * a), std::sin(2 * a));
  }
  for (size_t i = 0; i < s.size(); ++i) {
    const Vec2& v = sum[size_t(group[i])];
    s[i] = turned(s[i], 0.5 * std::atan2(v.y(), v.x()));
  }
  return s;
}

// Preferred corners: walls near the building's axes (every 45 degrees) on them.
std::vector<Segment> on_axes(std::vector<Segment> s, double axis) {
  for (auto& seg : s) {
    const double a = angle_of(seg.dir());
    const double k = std::round((a - axis) / (kPi / 4));
    const double snapped = axis + k * kPi / 4;
    if (angle_between(a, snapped) < kCornerDeg * kDeg) seg = turned(seg, snapped);
  }
  return s;
}

// Parallel and facing the same way (two sides of a narrow part never merge).
bool same_direction(const Segment& a, const Segment& b) {
  return a.dir().dot(b.dir()) > 0 && angle_between(angle_of(a.dir()), angle_of(b.dir())) < kSameDirectionDeg * kDeg;
}

// Whether the two segments' extents along a's direction overlap (within `reach`).
bool overlapping(const Segment& a, const Segment& b, double reach) {
  const Vec2 d = a.dir();
  const double a0 = 0, a1 = d.dot(a.b - a.a);
  const double b0 = d.dot(b.a - a.a), b1 = d.dot(b.b - a.a);
  return std::max(b0, b1) >= a0 - reach && std::min(b0, b1) <= a1 + reach;
}

// Inter-layer alignment: each wall near a parallel wall of the layer below
// goes onto that wall's line (the nearest such).
std::vector<Segment> aligned_below(std::vector<Segment> s, const std::vector<Segment>& below, double reach) {
  for (auto& seg : s) {
    double best = reach;
    const Segment* to = nullptr;
    for (const auto& b : below) {
      if (!same_direction(seg, b) || !overlapping(seg, b, reach)) continue;
      const double gap = std::fabs(offset(b.dir(), seg.a) - offset(b.dir(), b.a));
      if (gap < best) best = gap, to = &b;
    }
    if (to) seg = moved_onto(turned(seg, angle_of(to->dir())), to->a);
  }
  return s;
}

// Intra-layer alignment: non-adjacent parallel walls whose lines lie within
// `reach` go onto their length-weighted mean line.
std::vector<Segment> aligned_within(std::vector<Segment> s, double reach) {
  const size_t n = s.size();
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 2; j < n; ++j) {
      if ((j + 1) % n == i || !same_direction(s[i], s[j])) continue;
      const Vec2 d = s[i].dir();
      const double oi = offset(d, s[i].a), oj = offset(d, s[j].a);
      if (std::fabs(oi - oj) >= reach) continue;
      const double li = s[i].length(), lj = s[j].length(), o = (li * oi + lj * oj) / (li + lj);
      const Vec2 p = Vec2(-d.y(), d.x()) * o;  // the point of the line at offset o nearest the origin
      s[i] = moved_onto(s[i], p);
      s[j] = moved_onto(turned(s[j], angle_of(d)), p);
    }
  return s;
}

std::vector<Segment> without_short_jogs(const std::vector<Segment>& s, double min_edge) {
  Ring2 ring;
  for (const auto& seg : s) ring.push_back(seg.a);
  return segments_of(regularize_polygon({ring, {}}, min_edge).outer);
}

}  // namespace

std::vector<Segment> segments_of(const Ring2& ring) {
  std::vector<Segment> out;
  for (size_t i = 0; i < ring.size(); ++i) out.push_back({ring[i], ring[(i + 1) % ring.size()]});
  return out;
}

Ring2 ring_through(const std::vector<Segment>& lines) {
  const size_t n = lines.size();
  Ring2 out;
  for (size_t i = 0; i < n && n >= 3; ++i) {
    const Segment &prev = lines[(i + n - 1) % n], &cur = lines[i];
    const Vec2 dp = prev.dir(), dc = cur.dir(), shared = 0.5 * (prev.b + cur.a);
    const double reach = std::max(prev.length(), cur.length());
    if (std::fabs(cross2(dp, dc)) > kMeetSin) {
      const auto v = intersect_lines(prev.a, dp, cur.a, dc);
      if (v && (*v - shared).norm() <= reach) {
        out.push_back(*v);
        continue;
      }
    }
    if (std::fabs(offset(dp, cur.a) - offset(dp, prev.a)) < kCollinearM && dp.dot(dc) > 0) continue;
    const Vec2 across(-dp.y(), dp.x());  // a square connector through the shared point
    const auto p = intersect_lines(prev.a, dp, shared, across), q = intersect_lines(shared, across, cur.a, dc);
    if (!p || !q) return {};
    out.push_back(*p);
    if ((*q - *p).norm() > kCollinearM) out.push_back(*q);
  }
  if (out.size() < 3 || signed_area(out) <= 0 || !poly::is_valid({{out, {}}})) return {};
  return out;
}

Regularised regularise(const RegulariseInput& in) {
  Regularised r;
  r.outline = {in.outline.outer, {}};
  r.iou_found = r.iou = in.iou(r.outline);
  const double level = std::max(kMinIou, r.iou_found - kMaxIouLoss);
  using Step = std::pair<const char*, std::function<std::vector<Segment>(const std::vector<Segment>&)>>;
  const std::vector<Step> steps{
      {"parallel walls", [](const auto& s) { return parallel_walls(s); }},
      {"corner angles", [&](const auto& s) { return on_axes(s, in.axis); }},
      {"aligned with the layer below", [&](const auto& s) { return aligned_below(s, in.below, in.align_m); }},
      {"aligned within the layer", [&](const auto& s) { return aligned_within(s, in.align_m); }},
      {"short jogs removed", [&](const auto& s) { return without_short_jogs(s, in.min_edge_m); }},
  };
  for (const auto& [name, step] : steps) {
    const Ring2 ring = ring_through(step(segments_of(r.outline.outer)));
    if (ring.empty()) continue;
    const Polygon2 candidate{ring, {}};
    const double iou = in.iou(candidate);
    if (iou < level) continue;
    r.outline = candidate;
    r.iou = iou;
    r.steps.push_back(name);
  }
  return r;
}

}  // namespace c3d::lod13
