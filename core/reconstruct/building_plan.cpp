#include "core/reconstruct/building_plan.h"

#include <functional>
#include <map>
#include <numeric>

#include "core/geometry/geometry.h"
#include "core/geometry/polygon_ops.h"
#include "core/reconstruct/outline/arcs.h"
#include "core/reconstruct/outline/outline.h"

namespace c3d {
namespace {

// Roofs of separate buildings can come within half a metre at a corner or along
// a short stretch (a shed against a house, a wall top bridging two roofs);
// levels of one building share a boundary of metres. The contact is measured
// as the overlap of the outlines grown by kContactGrowthM: 1 m^2 is about 2 m of edge.
constexpr double kMinContact = 1.0;        // m^2
constexpr double kContactGrowthM = 0.25;   // each outline grown by this to measure their contact
constexpr double kMinOutlineArea = 4.0;    // m^2: a smaller outline is clutter, not a building
constexpr double kCloseLevelsM = 0.25;     // gaps between a building's roof levels closed up to twice this
constexpr double kSimplifyM = 0.02;        // an outline's vertices within this of a line go
// A building's wall stands on its own parcel; this much beyond the boundary
// is registration error between the scans and the parcel layer.
constexpr double kWallRoomM = 0.3;
constexpr double kRimMarginM = 0.1;        // a house keeps the roof within its overhang and this much more
constexpr double kPieceContactM = 0.05;    // a leftover piece grown by this meets the houses beside it
constexpr double kCloseSeamsM = 0.01;      // seams left between a house's pieces closed

Vec2 plan(const Vec3& p) { return p.head<2>(); }

// Groups roof outlines that meet along an edge (roof levels of one building).
std::vector<std::vector<int>> group_touching(const std::vector<Polygon2>& outlines) {
  size_t n = outlines.size();
  std::vector<int> group(n);
  std::iota(group.begin(), group.end(), 0);
  std::function<int(int)> find = [&](int i) { return group[i] == i ? i : group[i] = find(group[i]); };
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 1; j < n; ++j) {
      auto a = poly::buffer({outlines[i]}, kContactGrowthM), b = poly::buffer({outlines[j]}, kContactGrowthM);
      if (area(poly::intersect(a, b)) > kMinContact) group[find(int(i))] = find(int(j));
    }
  std::map<int, std::vector<int>> by_root;
  for (size_t i = 0; i < n; ++i) by_root[find(int(i))].push_back(int(i));
  std::vector<std::vector<int>> out;
  for (auto& [r, members] : by_root) out.push_back(members);
  return out;
}

// Per roof with a component kept, its outline (its components' points and its
// loose points on this parcel) and its components; `roof_comps` in step.
std::vector<Polygon2> roof_outlines(const ParcelScene& s, const Segmentation& seg, double loose_reach,
                                    bool turn_axes, std::vector<std::vector<int>>& roof_comps) {
  std::map<int, std::vector<int>> comps_of_roof;
  for (size_t c = 0; c < seg.components.size(); ++c)
    if (!seg.components[c].points.empty()) comps_of_roof[seg.components[c].roof].push_back(int(c));
  std::vector<Polygon2> outlines;
  OutlineOptions opt;
  opt.spacing = seg.spacing;
  opt.refine_orientation = turn_axes;
  const auto loose = loose_roof_points(s.roof_points, seg, loose_reach);
  for (auto& [roof, comps] : comps_of_roof) {
    std::vector<Vec2> pts;
    for (int i : loose[size_t(roof)])  // on this parcel only: a neighbour's are theirs
      if (poly::covers(s.parcel, plan(s.roof_points[i]))) pts.push_back(plan(s.roof_points[i]));
    for (int c : comps)
      for (int i : seg.components[c].points) pts.push_back(plan(s.roof_points[i]));
    Polygon2 o = roof_outline(pts, opt);
    if (o.outer.size() < 3 || area(o) < kMinOutlineArea) continue;
    outlines.push_back(o);
    roof_comps.push_back(comps);
  }
  return outlines;
}

}  // namespace

std::vector<BuildingPlan> plan_buildings(const ParcelScene& s, const Segmentation& seg, const MultiPolygon2& cut,
                                         double loose_reach, bool turn_axes) {
  std::vector<std::vector<int>> roof_comps;
  const std::vector<Polygon2> outlines = roof_outlines(s, seg, loose_reach, turn_axes, roof_comps);
  std::vector<BuildingPlan> plans;
  for (const auto& group : group_touching(outlines)) {
    std::vector<int> comps;
    MultiPolygon2 u;
    for (int i : group) {
      u = poly::unite(u, {outlines[i]});
      comps.insert(comps.end(), roof_comps[i].begin(), roof_comps[i].end());
    }
    // Close gaps between roof levels, and straighten runs of vertices; but a
    // single roof ending on a circle (outline/arcs.h) is kept as drawn: both
    // would move its chords' vertices.
    const bool as_drawn = group.size() == 1 && !arcs_in_ring(outlines[size_t(group[0])].outer).arcs.empty();
    if (!as_drawn) u = poly::buffer(poly::buffer(u, kCloseLevelsM), -kCloseLevelsM);
    if (!cut.empty()) u = poly::subtract(u, cut);
    // The cut may leave several buildings, and needles where it grazes a corner.
    for (Polygon2& part : poly::drop_needles(as_drawn ? u : poly::simplify(u, kSimplifyM), kNeedleAngle)) {
      part.holes.clear();
      if (part.outer.size() >= 3 && area(part) >= kMinOutlineArea) plans.push_back({part, comps, {}});
    }
  }
  const MultiPolygon2 land = poly::subtract(poly::buffer(s.parcel, kWallRoomM), cut);
  for (auto& bp : plans) {
    bp.room = land;
    for (const auto& other : plans)
      if (&other != &bp) bp.room = poly::subtract(bp.room, {other.outline});
  }
  return plans;
}

namespace {

// Cuts a roof outline whose footprint came apart into one outline per footprint
// part, so each house under it gets a roof and walls of its own: each part
// keeps the outline within its overhang (the larger part where two such rims
// meet), and every piece left over (a walkway's roof between them) goes to
// the part it meets along most boundary.
std::vector<Polygon2> cut_at_narrows(const Polygon2& outline, const FootprintApart& apart) {
  const MultiPolygon2 whole{outline};
  std::vector<MultiPolygon2> houses;
  MultiPolygon2 taken;
  for (const Polygon2& part : apart.parts) {  // largest first
    const MultiPolygon2 rim = poly::intersect(poly::buffer({part}, apart.overhang + kRimMarginM), whole);
    houses.push_back(poly::subtract(rim, taken));
    taken = poly::unite(taken, rim);
  }
  for (const Polygon2& piece : poly::subtract(whole, taken)) {
    const MultiPolygon2 edge = poly::buffer({piece}, kPieceContactM);
    size_t best = 0;
    double most = 0;
    for (size_t h = 0; h < houses.size(); ++h) {
      const double contact = area(poly::intersect(edge, houses[h]));
      if (contact > most) most = contact, best = h;
    }
    if (most > 0) houses[best] = poly::unite(houses[best], {piece});
  }
  std::vector<Polygon2> out;
  for (const auto& h : houses) {
    const MultiPolygon2 closed = poly::buffer(poly::buffer(h, kCloseSeamsM), -kCloseSeamsM);
    Polygon2 part = poly::largest(poly::drop_needles(poly::simplify(closed, kSimplifyM), kNeedleAngle));
    part.holes.clear();
    if (area(part) >= kMinFootprintPart) out.push_back(part);
  }
  return out;
}

}  // namespace

std::vector<BuildingPlan> houses_under(const BuildingPlan& bp, const FootprintApart& apart) {
  if (apart.parts.size() <= 1) return {};
  const std::vector<Polygon2> pieces = cut_at_narrows(bp.outline, apart);
  if (pieces.size() <= 1) return {};
  std::vector<BuildingPlan> houses;
  for (const Polygon2& piece : pieces)  // each house may grow on its parent's room, not on its siblings
    houses.push_back({piece, bp.components, poly::subtract(bp.room, poly::subtract({bp.outline}, {piece}))});
  return houses;
}

}  // namespace c3d
