// Questions about a building's outline where it meets the parcel boundary,
// answered from the Ownership alone: each reads only the points of the strip
// along one edge, from the Ownership's point index.
#include <algorithm>
#include <cmath>

#include "core/geometry/geometry.h"
#include "core/geometry/polygon_ops.h"
#include "core/reconstruct/envelope/envelope.h"
#include "core/reconstruct/ownership/ownership.h"
#include "core/reconstruct/ownership/ownership_constants.h"

namespace c3d {
using namespace ownership;
namespace {

Vec2 plan(const Vec3& p) { return p.head<2>(); }

// The q-quantile of v (0 <= q <= 1), v non-empty; v is reordered.
double quantile(std::vector<double>& v, double q) {
  auto k = v.begin() + long(q * double(v.size() - 1));
  std::nth_element(v.begin(), k, v.end());
  return *k;
}

// The indices, ascending (the scene's order), of the points of `grid` that may
// lie in the strip t in [t0, t1], off in [o0, o1] of the edge from `a` along
// `d` (`n` its outward normal): all of those in it, and some beside it.
std::vector<int> near_edge(const PointGrid& grid, const Vec2& a, const Vec2& d, const Vec2& n, double t0, double t1,
                           double o0, double o1) {
  Vec2 lo = a + t0 * d + o0 * n, hi = lo;
  for (const Vec2& c : {Vec2(a + t1 * d + o0 * n), Vec2(a + t0 * d + o1 * n), Vec2(a + t1 * d + o1 * n)})
    lo = lo.cwiseMin(c), hi = hi.cwiseMax(c);
  const Vec2 pad(kBoxPadM, kBoxPadM);
  return points_in_box(grid, lo - pad, hi + pad);
}

// The wall points fit_wall may use for edge a -> b, in the scene's order.
std::vector<Vec3> walls_near(const Ownership& own, const Vec2& a, const Vec2& b) {
  const double len = (b - a).norm();
  const Vec2 d = (b - a) / len, n(d.y(), -d.x());
  std::vector<Vec3> walls;
  for (int i : near_edge(own.wall_grid, a, d, n, 0, len, -kWallFitReachM, kWallFitReachM))
    walls.push_back(own.wall_points[size_t(i)]);
  return walls;
}

// Whether the handheld scanner saw this edge's wall (under the edge or just
// outside it, below the roof there): a wall shared with the neighbour's house
// is covered by it, so a wall seen from outside stands free, on an alley or a
// yard, whatever roof-class points lie across the line (05794: its facade
// seen 0.9 m inside its eave, a screen classed roof hanging at the line). Not
// on a short edge (kMinSeenPartyEdgeM): a few wall points there are as likely
// the end of a facade running on past the corner (two row houses' party jogs
// of 1.1 and 1.5 m on the sample towns lost their party walls to 26-28 such points).
bool wall_seen_under(const Ownership& own, const Vec2& a, const Vec2& b, std::vector<double>& own_z) {
  if ((b - a).norm() < kMinSeenPartyEdgeM || own_z.size() < kMinEdgeRoofPoints) return false;
  return fit_wall(walls_near(own, a, b), a, b, kAnyHeight, quantile(own_z, kLowQuantile), false).found;
}

// Whether m lies on the parcel boundary, n the outward normal of the edge
// through it: the parcel just inside, not just outside.
bool on_parcel_line(const Ownership& own, const Vec2& m, const Vec2& n) {
  return poly::covers(own.parcel, m - kLineProbeM * n) && !poly::covers(own.parcel, m + kLineProbeM * n);
}

// Where along edge a -> b (outward normal n) the neighbour's roof lies right
// across it: per bin of kPartyBinM, on the parcel line and with roof points
// no component here keeps 0.5-1 m beyond it; and the t of those points.
struct AcrossProfile {
  std::vector<bool> covered;
  std::vector<double> first_t, last_t;
};

AcrossProfile profile_across(const Vec2& a, const Vec2& b, const Ownership& own) {
  const double len = (b - a).norm();
  const Vec2 d = (b - a) / len, n(d.y(), -d.x());
  const size_t bins = size_t(std::ceil(len / kPartyBinM));
  AcrossProfile p{std::vector<bool>(bins, false), std::vector<double>(bins, len), std::vector<double>(bins, 0)};
  std::vector<bool> on_line(bins);
  for (size_t i = 0; i < bins; ++i) {
    on_line[i] = on_parcel_line(own, a + std::min(len, (double(i) + 0.5) * kPartyBinM) * d, n);
  }
  if (std::none_of(on_line.begin(), on_line.end(), [](bool b) { return b; })) return p;
  std::vector<int> count(bins, 0);
  for (int k : near_edge(own.roof_grid, a, d, n, 0, len, kAcrossNearM, kAcrossFarM)) {
    if (own.label[size_t(k)] >= 0) continue;
    const Vec2 q = plan(own.roof_points[size_t(k)]) - a;
    const double t = d.dot(q), off = n.dot(q);
    if (t < 0 || t >= len || off <= kAcrossNearM || off >= kAcrossFarM) continue;
    const size_t i = std::min(bins - 1, size_t(t / kPartyBinM));
    ++count[i];
    p.first_t[i] = std::min(p.first_t[i], t), p.last_t[i] = std::max(p.last_t[i], t);
  }
  for (size_t i = 0; i < bins; ++i) p.covered[i] = on_line[i] && count[i] >= kMinPointsInBin;
  return p;
}

// The longest run of covered bins, bridging gaps of up to kMaxGapBins: [first, last].
std::pair<size_t, size_t> longest_run(const std::vector<bool>& covered) {
  std::pair<size_t, size_t> best{1, 0};
  size_t start = 0, last = 0, gap = 0;
  bool open = false;
  for (size_t i = 0; i <= covered.size(); ++i) {
    const bool c = i < covered.size() && covered[i];
    if (c) {
      if (!open) start = i, open = true;
      last = i, gap = 0;
    } else if (open && (++gap > kMaxGapBins || i == covered.size())) {
      if (best.first > best.second || last - start > best.second - best.first) best = {start, last};
      open = false;
    }
  }
  return best;
}

// Whether bins [from, to) hold a house across: a free stretch has next to none.
bool free_stretch(const std::vector<bool>& covered, size_t from, size_t to) {
  if (double(to - from) * kPartyBinM < kMinStretchM) return false;
  return double(std::count(covered.begin() + long(from), covered.begin() + long(to), true)) <=
         kMaxFreeShare * double(to - from);
}

// Whether edge a -> b lies on the parcel line with the neighbour's roof right
// across it and no wall of this house seen under it.
bool party_edge(const Vec2& a, const Vec2& b, const Ownership& own) {
  const double len = (b - a).norm();
  if (len < kMinPartyEdgeM) return false;
  const Vec2 d = (b - a) / len, n(d.y(), -d.x()), m = 0.5 * (a + b);
  if (!on_parcel_line(own, m, n)) return false;
  int across = 0, further = 0;
  std::vector<double> own_z;  // this parcel's roof just inside the edge
  for (int k : near_edge(own.roof_grid, a, d, n, kEdgeFrom * len, kEdgeTo * len, -kOwnStripM, kAcrossFarM)) {
    const Vec2 q = plan(own.roof_points[size_t(k)]) - a;
    const double t = d.dot(q), off = n.dot(q);
    if (t <= kEdgeFrom * len || t >= kEdgeTo * len) continue;
    const int label = own.label[size_t(k)];
    if (label >= 0 && off > -kOwnStripM && off <= 0) own_z.push_back(own.roof_points[size_t(k)].z());
    if (label < 0 && off > 0.0 && off < kAcrossFarM) ++across, further += off > kAcrossNearM;
  }
  // The neighbour's house meeting this one gives roof all the way across the
  // metre; a gutter, a screen or an eave tip reaching over the line only in
  // its first half (05803's side facing open land: a 0.3-0.5 m strip).
  return across >= std::max(kMinAcrossPoints, kAcrossPointsPerM * len) &&
         further >= std::max(kMinFurtherPoints, kFurtherPointsPerM * len) && !wall_seen_under(own, a, b, own_z);
}

// A short jog on the parcel line (left where the outline snaps to the
// building's axes but the boundary runs a little askew) continues the party
// wall beside it; as an exterior wall it would take the overhang and pull the
// party wall inward.
std::vector<bool> jogs_beside_party_edges(const Ring2& r, const std::vector<bool>& party, const Ownership& own) {
  const size_t n = r.size();
  std::vector<bool> jog(n, false);
  for (size_t i = 0; i < n; ++i) {
    Vec2 a = r[i], b = r[(i + 1) % n];
    if (party[i] || (b - a).norm() >= kMinPartyEdgeM) continue;
    Vec2 m = 0.5 * (a + b);
    const bool off_line = poly::covers(own.parcel_core, m) || poly::distance(own.parcel, m) > kBoundaryStripM;
    if (off_line) continue;
    Vec2 d = (b - a).normalized();
    for (size_t k : {(i + n - 1) % n, (i + 1) % n}) {
      Vec2 e = (r[(k + 1) % n] - r[k]).normalized();
      if (party[k] && d.dot(e) > std::cos(kMaxJogTurnDeg * M_PI / 180)) jog[i] = true;
    }
  }
  return jog;
}

// The gap from edge a -> b (along d, outward n) to the parcel boundary,
// measured across the edge at five places: its least and its most.
std::pair<double, double> gap_to_boundary(const Ownership& own, const Vec2& a, double len, const Vec2& d,
                                          const Vec2& n) {
  double gmin = 1e9, gmax = -1e9;
  for (double f : {0.1, 0.3, 0.5, 0.7, 0.9}) {
    const Vec2 m = a + f * len * d;
    double g = 0;
    while (g <= kMaxHiddenGapM + kGapStepM && poly::covers(own.parcel, m + (g + kGapStepM) * n)) g += kGapStepM;
    gmin = std::min(gmin, g), gmax = std::max(gmax, g);
  }
  return {gmin, gmax};
}

// Whether edge a -> b, `gmin` to `gmax` short of the boundary, lies under a
// neighbour's higher eave (see grow_under_neighbour_eaves); `roofs` are this
// building's.
bool under_neighbour_eave(const Ownership& own, const std::set<int>& roofs, const Vec2& a, const Vec2& b,
                          double gmin, double gmax) {
  const double len = (b - a).norm();
  const Vec2 d = (b - a) / len, n(d.y(), -d.x());
  std::vector<double> own_z, over_z;
  std::vector<bool> covered(size_t(len / kCoverBinM) + 1, false);
  int walls_in_gap = 0;
  for (int k : near_edge(own.roof_grid, a, d, n, kEdgeFrom * len, kEdgeTo * len, -kOwnStripM, gmax + kGapMarginM)) {
    const Vec3& p = own.roof_points[size_t(k)];
    const Vec2 q = plan(p) - a;
    const double t = d.dot(q), off = n.dot(q);
    if (t < kEdgeFrom * len || t > kEdgeTo * len) continue;
    const bool ours = roofs.count(own.roof_of[size_t(k)]) > 0;
    if (ours && off > -kOwnStripM && off <= 0) own_z.push_back(p.z());
    if (!ours && off > 0 && off < gmax + kGapMarginM) {
      over_z.push_back(p.z());
      covered[size_t(t / kCoverBinM)] = true;
    }
  }
  for (int k : near_edge(own.wall_grid, a, d, n, kEdgeFrom * len, kEdgeTo * len, kGapMarginM, gmin - kGapMarginM)) {
    const Vec2 q = plan(own.wall_points[size_t(k)]) - a;
    const double t = d.dot(q), off = n.dot(q);
    walls_in_gap += t > kEdgeFrom * len && t < kEdgeTo * len && off > kGapMarginM && off < gmin - kGapMarginM;
  }
  const size_t spans = size_t(kEdgeMiddle * len / kCoverBinM);
  if (own_z.size() < kMinEdgeRoofPoints || over_z.size() < kMinOverPoints || walls_in_gap >= kMinWallPointsInGap)
    return false;
  if (size_t(std::count(covered.begin(), covered.end(), true)) < size_t(kMinOverCoverage * double(spans))) return false;
  const double own_top = quantile(own_z, kHighQuantile), over_bottom = quantile(over_z, kLowQuantile);
  if (over_bottom < own_top + kHigherEaveM) return false;  // this roof's own edge, or a roof at its height
  return !fit_wall(walls_near(own, a, b), a, b, kAnyHeight, own_top, false).found;  // its wall seen: it stands free
}

}  // namespace

// A long edge on the parcel line that meets the neighbour's house along one
// stretch and faces a yard or an alley along the rest (9's south-west side:
// 9 m against 05803's roof, then 5 m over open land) gets a vertex
// where the neighbour's roof ends, so each stretch is decided on its own:
// a party wall along the house, a free wall with its eave beyond it.
Polygon2 split_where_neighbour_roof_ends(const Polygon2& outline, const Ownership& own) {
  const Ring2& r = outline.outer;
  Ring2 out;
  for (size_t i = 0; i < r.size(); ++i) {
    const Vec2 a = r[i], b = r[(i + 1) % r.size()];
    out.push_back(a);
    const double len = (b - a).norm();
    if (len < 2 * kMinStretchM) continue;
    const AcrossProfile p = profile_across(a, b, own);
    const auto [first, last] = longest_run(p.covered);
    if (first > last || double(last - first + 1) * kPartyBinM < kMinStretchM) continue;
    const Vec2 d = (b - a) / len;
    if (free_stretch(p.covered, 0, first)) out.push_back(a + p.first_t[first] * d);
    if (free_stretch(p.covered, last + 1, p.covered.size())) out.push_back(a + p.last_t[last] * d);
  }
  if (out.size() == r.size()) return outline;
  return Polygon2{out, outline.holes};
}

// Outline edges on the parcel boundary with the neighbour's roof right across.
std::vector<bool> find_party_edges(const Polygon2& outline, const Ownership& own) {
  const Ring2& r = outline.outer;
  std::vector<bool> party(r.size(), false);
  for (size_t i = 0; i < r.size(); ++i) party[i] = party_edge(r[i], r[(i + 1) % r.size()], own);
  const std::vector<bool> jog = jogs_beside_party_edges(r, party, own);
  for (size_t i = 0; i < r.size(); ++i) party[i] = party[i] || jog[i];
  return party;
}

// A neighbour's eave hides the edge of this roof: an outline edge that stops
// short of the parcel boundary (by up to kMaxHiddenGapM, evenly along it)
// where a roof not this building's stands over the whole gap, clearly higher
// than this roof at the edge, and a neighbour's parcel lies beyond. The scan
// cannot see under the eave, so this roof ends where the neighbour's begins;
// it runs on under it to the boundary and meets the neighbour there (a party
// wall), rather than standing free with an overhang of its own (9 under
// 05801's eave: an exterior wall 0.8 m inside the boundary with an outer
// ceiling, where 05801 sees a party wall). A wall seen under the edge or in
// the gap says the house stands free (an alley under the eave): the edge stays.
Polygon2 grow_under_neighbour_eaves(const Polygon2& outline, const Ownership& own, const std::set<int>& roofs,
                                    const MultiPolygon2& room) {
  const Ring2& r = outline.outer;
  const MultiPolygon2 land = poly::intersect(own.parcel, room);
  MultiPolygon2 grown{outline};
  bool changed = false;
  for (size_t i = 0; i < r.size(); ++i) {
    const Vec2 a = r[i], b = r[(i + 1) % r.size()];
    const double len = (b - a).norm();
    if (len < kMinHiddenEdgeM) continue;
    const Vec2 d = (b - a) / len, n(d.y(), -d.x());  // outward (CCW ring)
    const auto [gmin, gmax] = gap_to_boundary(own, a, len, d, n);
    // On the boundary already, too far from it, or askew to it.
    if (gmin < kMinHiddenGapM || gmax > kMaxHiddenGapM || gmax - gmin > kMaxGapSpreadM) continue;
    const Vec2 across = a + 0.5 * len * d + (gmax + kAcrossProbeM) * n;
    if (std::none_of(own.neighbours.begin(), own.neighbours.end(),
                     [&](const MultiPolygon2& nb) { return poly::covers(nb, across); }))
      continue;  // no neighbour's land beyond: nobody to meet there
    if (!under_neighbour_eave(own, roofs, a, b, gmin, gmax)) continue;
    const Vec2 o = (gmax + kPastBoundaryM) * n;  // past the boundary, then cut back to it
    grown = poly::unite(grown, poly::intersect({Polygon2{{a, b, b + o, a + o}, {}}}, land));
    changed = true;
  }
  if (!changed) return outline;
  Polygon2 best = poly::largest(poly::simplify(grown, kGrownSimplifyM));
  best.holes.clear();
  return best;
}

}  // namespace c3d
