#include "core/reconstruct/envelope/wall_evidence.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "core/geometry/geometry.h"
#include "core/geometry/polygon_ops.h"
#include "core/log.h"
#include "core/reconstruct/envelope/arc_walls.h"
#include "core/reconstruct/outline/arcs.h"
#include "core/reconstruct/envelope/common.h"

namespace c3d::envelope {

// Wall points further inside a roof edge than this belong to another wall
// (an inner facade, a neighbour): hanging roofs reach about 1.5 m.
constexpr double kMaxOverhang = 1.8;
// A measured overhang this much larger than the building's typical one, and
// than its facade's (facade_overhang), is taken as a misread (another wall
// behind the edge) and replaced by the facade's. A wall
// found closer to the edge is believed: gable ends and walls under a lower
// roof often have little or no overhang.
constexpr double kOverhangOutlier = 0.6;
// A wall seen up to this far outside the roof outline is the wall under that
// edge, flush with the eave: the outline (a hull of roof points) stops short of
// the true eave where the eave's points are missing. Farther out stands
// something else (a fence, a neighbour across a gap).
constexpr double kMaxOutside = 0.6;
// Wall points more than this above the roof along an edge belong to a taller
// neighbour's wall behind it (a parapet rises less).
constexpr double kAboveRoof = 0.5;
// The building's typical overhang pools the seen walls within this of their
// weighted median (typical_overhang): flush jogs and step walls stay out.
constexpr double kOverhangInlier = 0.1;  // m
// A facade (walls parallel to each other, facade_overhang): within 20 degrees,
// at least kMinFacade of seen wall (a porch's flush sides are no facade), its
// own overhang where it differs from the building's by more than a
// measurement's scatter.
constexpr double kParallelCos = 0.94;
constexpr double kMinFacade = 3.0;      // m of seen wall
constexpr double kFacadeDiffers = 0.3;  // m
// A short edge continues a step between roof levels (continues_step) where
// the roof on either side of its line differs by more than kStepHeight; a
// longer edge than kStepJog is a wall of its own. The roof is read at
// kStepProbesAlong past each end, kStepProbeAcross to either side of the line.
constexpr double kStepHeight = 0.5;  // m between the levels beside the line
constexpr double kStepJog = 2.0;     // m, longest edge taken for a continuation
constexpr double kStepProbesAlong[] = {0.3, 0.6, 1.0};  // m: a step's line runs on for a metre at least
constexpr double kStepProbeAcross = 0.1;                // m: clear of the line, still on the step's two sides
// The roof over an edge's wall band (wall_top) is read near its ends and
// middle, just inside the edge and at the deepest overhang.
constexpr double kTopProbesAlong[] = {0.05, 0.5, 0.95};  // fractions of the edge
constexpr double kTopProbeNear = 0.2;                    // m inside the edge
// Wall points lower than this above the terrain are cars, hedges and garden
// walls standing before the facade, not the facade.
constexpr double kWallFootClearance = 0.3;  // m
// An edge lies on a wall the outline was grown onto when it runs along its
// line: parallel to within 2.6 degrees, its middle within a centimetre.
constexpr double kOnWallCos = 0.999;
constexpr double kOnWallDist = 0.01;  // m
// How well each kind of wall position is known (sigma, m).
constexpr double kPartySigma = 0.01;      // a party edge: on the parcel boundary; held there to 1.1 cm rms (sample towns)
constexpr double kContinuedSigma = 0.05;  // floor of a facade seen only on the neighbours
constexpr double kStepSigma = 0.05;       // an unseen wall carried on under a roof step
// Floor of the seen overhangs' scatter where fewer than kMinScatterWalls
// walls show it: two alike overhangs say little of how a third differs. From
// more, their scatter about the facade's overhang (their roof edges' noise
// included) is the unseen walls' error (area_sigma.cpp).
constexpr double kMinSpread = 0.05;
constexpr size_t kMinScatterWalls = 3;
constexpr double kMadToSigma = 1.4826;    // median absolute deviation -> sigma of a normal distribution
// fit_wall: a wall is a peak of the wall points' offsets from the edge.
constexpr double kMinWallEdge = 0.8;   // m: a shorter edge holds too few points to show a wall
constexpr double kOffsetBin = 0.04;    // m: offset histogram bin, a wall's points scatter a few cm
constexpr double kFitFrom = 0.1;       // fraction of the edge: its ends hold the crossing walls' points
constexpr double kFitTo = 0.9;
constexpr int kMinWallPoints = 25;     // fewer points are a pole, a gate or noise, not a wall
constexpr double kWallHalfWidth = 0.08;  // m: points this close to a peak's offset are that wall
constexpr double kCoverageCell = 0.5;  // m: cells along the edge counted for coverage
constexpr double kMinCoverage = 0.3;   // fraction of cells with wall points: less is a patch, not a wall
// A wall this little outside the outline is within the outline's own error
// (a hull edge is placed to about a centimetre, a wall fit to millimetres).
constexpr double kMinOutside = 0.05;
// A strip of land to grow onto, and a grown outline's gain, smaller than
// this is no growth (numerical slivers along the edge).
constexpr double kMinGrowth = 0.05;        // m^2
constexpr double kGrowSimplify = 0.005;    // m: vertex tolerance of the grown outline
// sparse_wall: an airborne scanner grazes the facades, and its building class
// holds those few points with the roof's. Points lower than the eave above
// them by kBelowEave (a gutter or fascia hangs less) lie on a wall; three of
// them at one offset (two fit any line) within kSparseWindow (an airborne
// point's scatter across a facade) show the wall, where they are most of the
// edge's low points (kMinSparseShare), not clutter beside a few. Pooled over a
// building, whose edges' directions are known, two agreeing points show its
// overhang (kMinPooledPoints).
constexpr double kBelowEave = 0.5;      // m
constexpr int kMinSparsePoints = 3;
constexpr int kMinPooledPoints = 2;
constexpr double kMinWallSpan = 0.5;    // m of height the window's points span
// A hanging roof is a margin of the roof: an overhang assumed where no wall
// is seen takes at most this share of the roof's plan (a garden shed's
// eaves are a hand wide, not the configured house's half metre).
constexpr double kMaxUnseenOverhangShare = 0.3;
constexpr double kSparseWindow = 0.3;   // m, full width
constexpr double kMinSparseShare = 0.5;

namespace {

// Roof height at p from the region over it (NaN where no region is).
double roof_z(const std::vector<RoofRegion>& roof, const Vec2& p) {
  for (const auto& r : roof)
    if (poly::covers(r.plan, p)) return r.plane.z_at(p.x(), p.y());
  return kNaN;
}

// Highest point of the roof over the band where this edge's wall may stand
// (+inf where no roof region covers it): wall points above it plus kAboveRoof
// are not this edge's wall.
double wall_top(const OutlineEdge& e, const std::vector<RoofRegion>& roof) {
  const Vec2 in = -outward((e.b - e.a).normalized());
  double top = -INFINITY;
  for (double t : kTopProbesAlong)
    for (double depth : {kTopProbeNear, kMaxOverhang}) {
      const double z = roof_z(roof, e.a + t * (e.b - e.a) + depth * in);
      if (std::isfinite(z)) top = std::max(top, z);
    }
  return std::isfinite(top) ? top + kAboveRoof : INFINITY;
}

Vec2 direction(const OutlineEdge& e) { return (e.b - e.a).normalized(); }

// The wall under edge e: a wall the outline was grown onto, where e lies on
// its line (flush: offset 0), else the one fit_edge_wall finds. Fitting again
// after growing could pick another peak of a thick wall's points.
WallFit wall_on_outline(const EnvelopeInput& in, const OutlineEdge& e) {
  const Vec2 mid = 0.5 * (e.a + e.b);
  for (const auto& w : in.walls_on_outline) {
    const Vec2 d = (w.b - w.a).normalized();
    const double t = d.dot(mid - w.a);
    if (std::abs(d.dot(direction(e))) > kOnWallCos && std::abs(outward(d).dot(mid - w.a)) < kOnWallDist && t > 0 &&
        t < (w.b - w.a).norm()) {
      WallFit flush = w.fit;
      flush.offset = 0;
      return flush;
    }
  }
  return fit_edge_wall(in, e);
}

// The wall at offset `centre` (points within kWallHalfWidth of it), or found=false
// when too few points show it or they cover too little of the edge.
WallFit wall_at(const std::vector<std::pair<double, double>>& st, double centre, double len,
                bool beyond_ends) {
  WallFit fit;
  double sum = 0, sum2 = 0;
  int count = 0;
  std::vector<bool> covered(size_t(len / kCoverageCell) + 1, false);
  for (auto& [s, t] : st)
    if (std::abs(s - centre) < kWallHalfWidth) {
      sum += s;
      ++count;
      if (!beyond_ends) covered[size_t(t / kCoverageCell)] = true;
    }
  if (count < kMinWallPoints) return fit;
  double mean = sum / count;
  for (auto& [s, t] : st)
    if (std::abs(s - centre) < kWallHalfWidth) sum2 += (s - mean) * (s - mean);
  double coverage = double(std::count(covered.begin(), covered.end(), true)) / covered.size();
  if (!beyond_ends && coverage < kMinCoverage) return fit;
  fit.found = true;
  fit.offset = mean;
  fit.support = count;
  fit.rms = std::sqrt(sum2 / count);
  return fit;
}

// Distance in plan from p to segment a -> b.
double to_segment(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 d = b - a;
  const double t = std::clamp(d.dot(p - a) / std::max(d.squaredNorm(), 1e-12), 0.0, 1.0);
  return (p - (a + t * d)).norm();
}

// The outline edge nearest to p in plan: a facade point shows that edge's
// wall, not the opposite one a narrow building holds within kMaxOverhang.
size_t nearest_edge(const std::vector<OutlineEdge>& edges, const Vec2& p) {
  size_t best = 0;
  double dmin = INFINITY;
  for (size_t i = 0; i < edges.size(); ++i)
    if (const double dist = to_segment(p, edges[i].a, edges[i].b); dist < dmin) dmin = dist, best = i;
  return best;
}

// The wall the facade points `s` show: the fullest kSparseWindow of their
// offsets, its median; found=false where too few points, too small a share
// of them, or too low a span of heights (a porch roof, a car: one height;
// a wall: from the eave down) show one.
WallFit wall_in_offsets(std::vector<FacadePoint> s, int min_points) {
  std::sort(s.begin(), s.end(), [](const FacadePoint& a, const FacadePoint& b) { return a.offset < b.offset; });
  size_t first = 0, count = 0;
  for (size_t i = 0, j = 0; i < s.size(); ++i) {
    while (s[i].offset - s[j].offset > kSparseWindow) ++j;
    if (i + 1 - j > count) first = j, count = i + 1 - j;
  }
  if (count < size_t(min_points) || count < kMinSparseShare * s.size()) return {};
  double lo = INFINITY, hi = -INFINITY;
  for (size_t i = first; i < first + count; ++i) lo = std::min(lo, s[i].z), hi = std::max(hi, s[i].z);
  if (hi - lo < kMinWallSpan) return {};
  const double median = 0.5 * (s[first + (count - 1) / 2].offset + s[first + count / 2].offset);
  double sum2 = 0;
  for (size_t i = first; i < first + count; ++i) sum2 += (s[i].offset - median) * (s[i].offset - median);
  return {true, median, int(count), std::sqrt(sum2 / count)};
}

}  // namespace

std::vector<FacadePoints> facade_offsets(const EnvelopeInput& in, const std::vector<OutlineEdge>& edges,
                                         const std::vector<Vec3>& points) {
  std::vector<FacadePoints> offsets(edges.size());
  if (edges.empty()) return offsets;
  // A point farther than any wall may stand from the outline's box is
  // farther from every edge: skip the scene's other buildings at once.
  Vec2 lo = edges.front().a, hi = lo;
  for (const auto& e : edges) lo = lo.cwiseMin(e.a), hi = hi.cwiseMax(e.a);
  lo.array() -= kMaxOverhang, hi.array() += kMaxOverhang;
  for (const auto& p : points) {
    if ((p.head<2>().array() < lo.array()).any() || (p.head<2>().array() > hi.array()).any()) continue;
    const size_t i = nearest_edge(edges, p.head<2>());
    const OutlineEdge& e = edges[i];
    const Vec2 d = direction(e), n = outward(d), q = p.head<2>() - e.a;
    const double len = (e.b - e.a).norm(), t = d.dot(q), s = n.dot(q);
    if (e.party || len < kMinWallEdge || t < kFitFrom * len || t > kFitTo * len || s < -kMaxOverhang ||
        s > kMaxOutside)
      continue;
    const double eave = roof_z(in.roof, e.a + t * d - kTopProbeNear * n);
    const double ground = in.terrain(p.x(), p.y());
    if (!(p.z() < eave - kBelowEave) || p.z() < ground + kWallFootClearance) continue;  // NaN passes neither way
    offsets[i].push_back({s, p.z()});
  }
  return offsets;
}

WallFit sparse_wall(const FacadePoints& offsets) { return wall_in_offsets(offsets, kMinSparsePoints); }

WallFit pooled_sparse_wall(const std::vector<FacadePoints>& offsets) {
  FacadePoints all;
  for (const auto& s : offsets) all.insert(all.end(), s.begin(), s.end());
  return wall_in_offsets(std::move(all), kMinPooledPoints);
}

double weighted_median(std::vector<Weighted> v) {
  std::sort(v.begin(), v.end(), [](const Weighted& a, const Weighted& b) { return a.value < b.value; });
  double total = 0, run = 0;
  for (const auto& w : v) total += w.weight;
  for (const auto& w : v)
    if ((run += w.weight) >= 0.5 * total) return w.value;
  return v.back().value;
}

// The building's overhang from its seen walls: the length-weighted mean of
// those within kOverhangInlier of the weighted median. An edge's position is
// known to within σ² ∝ 1/length, so weighting by length is the least-variance
// estimate (the median alone throws a third of that information away); the
// median's window keeps flush jogs and step walls (overhang 0) out of it.
double typical_overhang(const std::vector<Weighted>& measured) {
  double median = weighted_median(measured), sum = 0, weight = 0;
  for (const auto& m : measured)
    if (std::abs(m.value - median) <= kOverhangInlier) sum += m.value * m.weight, weight += m.weight;
  return sum / weight;  // the median itself is always within the window
}

// Facades parallel to each other overhang alike: on a pitched roof the eaves
// along the ridge share an overhang, and so do the verges across it, but the
// two often differ (a gable wall flush with the verge, a deep eave over the
// street). Where the seen walls parallel to a wall, a facade's length of them
// (a porch's flush sides are no facade), show an overhang clearly apart from
// the building's (more than a measurement's scatter), an unseen wall takes
// that facade's overhang, and a seen one is no misread for matching it
// (kParallelCos, kMinFacade, kFacadeDiffers).
double facade_overhang(const std::vector<SeenWall>& seen, const Vec2& dir, double building) {
  std::vector<Weighted> parallel;
  double length = 0;
  for (const auto& w : seen)
    if (std::abs(w.dir.dot(dir)) >= kParallelCos) parallel.push_back(w.overhang), length += w.overhang.weight;
  if (length < kMinFacade) return building;
  const double facade = typical_overhang(parallel);
  return std::abs(facade - building) > kFacadeDiffers ? facade : building;
}

// Whether a short edge's line runs on into the roof as a step between levels
// (the gable of a higher part beside a lower annex). The step wall stands
// right under the step, so an unseen wall under such an edge is that same wall
// carried on: no overhang, where the building's typical one would cut a notch
// of that depth into the footprint. A longer edge is a wall of its own
// (kStepJog); the levels differ by more than kStepHeight.
bool continues_step(const OutlineEdge& e, const std::vector<RoofRegion>& roof) {
  if ((e.b - e.a).norm() > kStepJog) return false;
  const Vec2 d = (e.b - e.a).normalized(), n = outward(d);
  for (const auto& [end, sign] : {std::pair{e.a, -1.0}, std::pair{e.b, 1.0}})
    for (double t : kStepProbesAlong) {
      const Vec2 p = end + sign * t * d;
      const double z1 = roof_z(roof, p - kStepProbeAcross * n), z2 = roof_z(roof, p + kStepProbeAcross * n);
      if (std::abs(z1 - z2) > kStepHeight) return true;  // false while either is NaN
    }
  return false;
}

// The wall seen under edge e, between kWallFootClearance above the terrain and wall_top.
WallFit fit_edge_wall(const EnvelopeInput& in, const OutlineEdge& e, bool beyond_ends) {
  const Vec2 mid = 0.5 * (e.a + e.b);
  const double tz = in.terrain(mid.x(), mid.y());
  return fit_wall(in.wall_points, e.a, e.b, std::isnan(tz) ? -1e9 : tz + kWallFootClearance, wall_top(e, in.roof),
                  beyond_ends);
}

namespace {

// The outline's edges; party edges (on the parcel boundary, shared with the
// neighbour) marked, with the boundary's sigma.
std::vector<OutlineEdge> outline_edges(const EnvelopeInput& in) {
  const Ring2& ring = in.outline.outer;
  const std::vector<int> arc = arcs_in_ring(ring).of_edge;
  std::vector<OutlineEdge> edges(ring.size());
  for (size_t i = 0; i < ring.size(); ++i) {
    OutlineEdge& e = edges[i];
    e.a = ring[i];
    e.b = ring[(i + 1) % ring.size()];
    e.arc = arc[i];
    e.party = i < in.party_edge.size() && in.party_edge[i];
    if (e.party) e.evidence = WallEvidence::ParcelBoundary, e.sigma = kPartySigma, e.sigma_shared = 0;
  }
  return edges;
}

// Each edge's own wall where the wall points, or failing them the roof
// class's facade points (`low`, per edge), show one: measured.
std::vector<SeenWall> measure_own_walls(const EnvelopeInput& in, std::vector<OutlineEdge>& edges,
                                        const std::vector<FacadePoints>& low) {
  std::vector<SeenWall> seen;
  for (size_t i = 0; i < edges.size(); ++i) {
    OutlineEdge& e = edges[i];
    if (e.party) continue;
    WallFit fit = wall_on_outline(in, e);
    if (!fit.found) fit = sparse_wall(low[i]);
    if (!fit.found || -fit.offset >= kMaxOverhang) continue;
    e.overhang = std::max(0.0, -fit.offset);
    e.evidence = WallEvidence::Measured;
    e.support = fit.support;
    e.rms = fit.rms;
    e.outside = std::max(0.0, fit.offset);
    // A wall seen outside the outline stays under the roof at the outline:
    // its distance to the points it stands for is part of its error; the
    // footprint built on it keeps its vertices to kGrowSimplify (uniform).
    e.sigma = std::hypot(fit.rms / std::sqrt(double(fit.support)), kGrowSimplify / std::sqrt(3.0)) +
              std::max(0.0, fit.offset);
    e.sigma_shared = 0;
    seen.push_back({i, direction(e), {e.overhang, (e.b - e.a).norm()}});
  }
  return seen;
}

// The overhang assumed where no wall is seen: the configured default, at
// most what leaves kMaxUnseenOverhangShare of the roof's plan to the
// overhangs along the edges that have one (area lost ~ perimeter x overhang).
double unseen_overhang(const EnvelopeInput& in, const std::vector<OutlineEdge>& edges) {
  double perimeter = 0;
  for (const auto& e : edges)
    if (!e.party) perimeter += (e.b - e.a).norm();
  if (perimeter <= 0) return in.default_overhang;
  return std::min(in.default_overhang, kMaxUnseenOverhangShare * area(in.outline) / perimeter);
}

// No wall of this building seen (a row house between its neighbours): the
// facade line may continue on the neighbours just past the edge's ends.
void continue_neighbours_facades(const EnvelopeInput& in, std::vector<OutlineEdge>& edges) {
  for (auto& e : edges) {
    if (e.party) continue;
    const WallFit fit = fit_edge_wall(in, e, true);
    if (!fit.found) continue;
    e.overhang = std::max(0.0, -fit.offset);
    e.evidence = WallEvidence::Propagated;
    e.support = fit.support;
    e.rms = fit.rms;
    e.sigma = kContinuedSigma + fit.rms / std::sqrt(double(fit.support));
    e.sigma_shared = 0;
  }
}

}  // namespace

std::vector<OutlineEdge> measure_edges(const EnvelopeInput& in) {
  std::vector<OutlineEdge> edges = outline_edges(in);
  // The few wall points where too few show a wall for fit_wall (a classified
  // airborne scan's facades); where the scene has no wall class, the roof
  // class's low points (an airborne building class holds the facades). With
  // wall points, the roof class's low points are porches and clutter.
  const std::vector<FacadePoints> low =
      facade_offsets(in, edges, in.wall_points.empty() ? in.roof_points : in.wall_points);
  const std::vector<SeenWall> seen = measure_own_walls(in, edges, low);
  pool_arcs(edges, kGrowSimplify);
  if (seen.empty()) continue_neighbours_facades(in, edges);
  double spread = kUnseenSpread;
  double typical = unseen_overhang(in, edges);
  WallEvidence fill = WallEvidence::Default;
  if (seen.empty()) {
    // No edge shows its own wall, but together they may (a shed's few facade
    // points): the building's overhang, each edge's wall within its scatter.
    const WallFit pooled = pooled_sparse_wall(low);
    if (pooled.found && -pooled.offset < kMaxOverhang) {
      typical = std::max(0.0, -pooled.offset);
      spread = std::max(kMinSpread, pooled.rms);
      fill = WallEvidence::Propagated;
    }
  }
  std::vector<double> facade(edges.size(), typical);
  if (!seen.empty()) {
    std::vector<Weighted> measured;
    for (const auto& w : seen) measured.push_back(w.overhang);
    typical = typical_overhang(measured);
    for (size_t i = 0; i < edges.size(); ++i) facade[i] = facade_overhang(seen, direction(edges[i]), typical);
    for (size_t i = 0; i < edges.size(); ++i) {
      OutlineEdge& e = edges[i];
      if (e.evidence == WallEvidence::Measured && e.overhang - std::max(typical, facade[i]) > kOverhangOutlier) {
        e.evidence = WallEvidence::Default;  // re-filled below as propagated
        e.support = 0;
        e.rms = 0;
      }
    }
    std::vector<Weighted> dev;
    for (const auto& w : seen) dev.push_back({std::abs(w.overhang.value - facade[w.edge]), w.overhang.weight});
    spread = kMadToSigma * weighted_median(dev);
    if (seen.size() < kMinScatterWalls) spread = std::max(kMinSpread, spread);
    fill = WallEvidence::Propagated;
  }
  for (size_t i = 0; i < edges.size(); ++i) {
    OutlineEdge& e = edges[i];
    if (!e.party && e.evidence != WallEvidence::Measured && e.support == 0) {
      const bool step = continues_step(e, in.roof);
      e.overhang = step ? 0.0 : facade[i];
      e.evidence = step ? WallEvidence::Propagated : fill;
      // Taken from the seen walls, each unseen wall errs on its own; the one
      // default or pooled overhang errs for all of them together.
      const bool own = step || (fill == WallEvidence::Propagated && !seen.empty());
      e.sigma = step ? kStepSigma : own ? spread : 0.0;
      e.sigma_shared = own ? 0.0 : spread;
    }
  }
  if (log::enabled(log::Level::Debug))
    for (auto& e : edges)
      log::debug(log::format("%s edge len %.2f ev %s overhang %.3f support %d", in.building_id.c_str(),
                             (e.b - e.a).norm(), to_string(e.evidence), e.overhang, e.support));
  return edges;
}

}  // namespace c3d::envelope

namespace c3d {

using namespace envelope;

WallFit fit_wall(const std::vector<Vec3>& pts, const Vec2& a, const Vec2& b, double min_z, double max_z,
                 bool beyond_ends) {
  Vec2 d = b - a;
  double len = d.norm();
  if (len < kMinWallEdge) return {};
  d /= len;
  Vec2 n = outward(d);
  const double lo = -kMaxOverhang, hi = kMaxOutside, bin = kOffsetBin;
  std::vector<int> hist(int((hi - lo) / bin) + 1, 0);
  std::vector<std::pair<double, double>> st;  // (s, t)
  for (const auto& p : pts) {
    if (p.z() < min_z || p.z() > max_z) continue;
    Vec2 q = p.head<2>() - a;
    double t = d.dot(q), s = n.dot(q);
    bool along = beyond_ends ? ((t < 0 && t > -kMaxOverhang) || (t > len && t < len + kMaxOverhang))
                             : (t >= kFitFrom * len && t <= kFitTo * len);
    if (!along || s < lo || s > hi) continue;
    ++hist[int((s - lo) / bin)];
    st.emplace_back(s, t);
  }
  if (st.size() < size_t(kMinWallPoints)) return {};
  // Peaks of the offset histogram (3 bins wide), most points first: a short
  // bright patch (a pole, a gate) must not hide the wall behind it.
  const size_t bins = hist.size();
  std::vector<int> smooth(bins);
  for (size_t i = 0; i < bins; ++i)
    smooth[i] = hist[i] + (i > 0 ? hist[i - 1] : 0) + (i + 1 < bins ? hist[i + 1] : 0);
  std::vector<std::pair<int, int>> peaks;  // (count, bin)
  for (size_t i = 0; i < bins; ++i)
    if ((i == 0 || smooth[i] > smooth[i - 1]) && (i + 1 == bins || smooth[i] >= smooth[i + 1]))
      peaks.emplace_back(smooth[i], int(i));
  std::sort(peaks.rbegin(), peaks.rend());
  for (const auto& [count, i] : peaks) {
    const WallFit fit = wall_at(st, lo + (i + 0.5) * bin, len, beyond_ends);
    if (fit.found) return fit;
  }
  return {};
}

GrownOutline grow_to_walls_outside(const EnvelopeInput& in, const MultiPolygon2& room) {
  const Ring2& ring = in.outline.outer;
  const size_t n = ring.size();
  std::vector<WallFit> fits(n);  // the walls standing outside their edges
  for (size_t i = 0; i < n; ++i) {
    if (i < in.party_edge.size() && in.party_edge[i]) continue;
    OutlineEdge e;
    e.a = ring[i], e.b = ring[(i + 1) % n];
    fits[i] = fit_edge_wall(in, e);
  }
  const RingArcs arcs = arcs_in_ring(ring);
  pool_arc_fits(ring, arcs.of_edge, fits);
  for (WallFit& fit : fits)
    if (!(fit.found && fit.offset > kMinOutside)) fit = WallFit{};
  auto out = [&](size_t i) { return fits[i % n].found ? fits[i % n].offset : 0.0; };
  GrownOutline g{in.outline, {}};
  MultiPolygon2 grown{in.outline};
  for (size_t i = 0; i < n; ++i) {
    if (!fits[i].found) continue;
    const Vec2 a = ring[i], b = ring[(i + 1) % n], d = (b - a).normalized(), o = outward(d) * out(i);
    // Run on past each end by the next edge's growth, so that two grown edges
    // meet in a corner rather than leave a notch (at a reflex corner the run
    // on lies inside the outline already). An arc's chords grow away from
    // its centre, onto the concentric circle.
    Vec2 a0 = a - d * out(i + n - 1), b0 = b + d * out(i + 1), a1 = a0 + o, b1 = b0 + o;
    if (const int k = arcs.of_edge[i]; k >= 0) {
      const Vec2 c = arcs.arcs[size_t(k)].centre;
      a0 = a, b0 = b, a1 = a + (a - c).normalized() * out(i), b1 = b + (b - c).normalized() * out(i);
    }
    const MultiPolygon2 strip = poly::intersect({Polygon2{{a0, b0, b1, a1}, {}}}, room);
    if (area(strip) < kMinGrowth) continue;  // no land to grow on
    grown = poly::unite(grown, strip);
    g.walls.push_back({a1, b1, fits[i]});
  }
  Polygon2 best = poly::largest(poly::simplify(grown, kGrowSimplify));
  best.holes.clear();
  if (area(best) > area(in.outline) + kMinGrowth)
    g.outline = best;
  else
    g.walls.clear();
  return g;
}

}  // namespace c3d
