#include "core/reconstruct/reconstruct.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <map>
#include <mutex>
#include <set>



#include "core/reconstruct/envelope/envelope.h"
#include "core/evaluate/evaluate.h"
#include "core/geometry/geometry.h"
#include "core/log.h"
#include "core/reconstruct/measure/measure.h"
#include "core/optimizer/optimizer.h"
#include "core/reconstruct/ownership/ownership.h"
#include "core/reconstruct/outline/outline.h"
#include "core/geometry/polygon_ops.h"
#include "core/check/polygon_rules.h"
#include "core/reconstruct/roof/roof.h"
#include "core/reconstruct/segment/segmentation.h"
#include "core/check/solid_check.h"

namespace c3d {
namespace {

class StageClock {
 public:
  explicit StageClock(std::vector<Timing>& out) : out_(out) {}
  void lap(const std::string& stage) {
    auto now = std::chrono::steady_clock::now();
    double s = std::chrono::duration<double>(now - last_).count();
    for (auto& t : out_)
      if (t.stage == stage) {
        t.seconds += s;
        last_ = now;
        return;
      }
    out_.push_back({stage, s});
    last_ = now;
  }

 private:
  std::vector<Timing>& out_;
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

Vec2 plan(const Vec3& p) { return p.head<2>(); }

// Groups roof outlines that meet along an edge (roof levels of one building).
// Roofs of separate buildings can come within half a metre at a corner or along
// a short stretch (a shed against a house, a wall top bridging two roofs);
// levels of one building share a boundary of metres. The contact is measured
// as the overlap of the outlines grown by 0.25 m: 1 m^2 is about 2 m of edge.
constexpr double kMinContact = 1.0;  // m^2
std::vector<std::vector<int>> group_touching(const std::vector<Polygon2>& outlines) {
  size_t n = outlines.size();
  std::vector<int> group(n);
  std::iota(group.begin(), group.end(), 0);
  std::function<int(int)> find = [&](int i) { return group[i] == i ? i : group[i] = find(group[i]); };
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 1; j < n; ++j) {
      auto a = poly::buffer({outlines[i]}, 0.25), b = poly::buffer({outlines[j]}, 0.25);
      if (area(poly::intersect(a, b)) > kMinContact) group[find(int(i))] = find(int(j));
    }
  std::map<int, std::vector<int>> by_root;
  for (size_t i = 0; i < n; ++i) by_root[find(int(i))].push_back(int(i));
  std::vector<std::vector<int>> out;
  for (auto& [r, members] : by_root) out.push_back(members);
  return out;
}

struct BuildingPlan {
  Polygon2 outline;
  std::vector<int> components;
  MultiPolygon2 room;  // where the outline may grow to a wall seen outside it
};

// A building's wall stands on its own parcel; this much beyond the boundary
// is registration error between the scans and the parcel layer.
constexpr double kWallRoomM = 0.3;

constexpr double kNeedleAngle = 0.0175;  // rad (1 degree): sharper than any building's corner

std::vector<BuildingPlan> plan_buildings(const ParcelScene& s, const Segmentation& seg,
                                         const MultiPolygon2& cut, double loose_reach, bool turn_axes) {
  std::map<int, std::vector<int>> comps_of_roof;
  for (size_t c = 0; c < seg.components.size(); ++c)
    if (!seg.components[c].points.empty()) comps_of_roof[seg.components[c].roof].push_back(int(c));
  std::vector<Polygon2> outlines;
  std::vector<std::vector<int>> roof_comps;
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
    if (o.outer.size() < 3 || area(o) < 4.0) continue;
    outlines.push_back(o);
    roof_comps.push_back(comps);
  }
  std::vector<BuildingPlan> plans;
  for (const auto& group : group_touching(outlines)) {
    std::vector<int> comps;
    MultiPolygon2 u;
    for (int i : group) {
      u = poly::unite(u, {outlines[i]});
      comps.insert(comps.end(), roof_comps[i].begin(), roof_comps[i].end());
    }
    u = poly::buffer(poly::buffer(u, 0.25), -0.25);  // close gaps between roof levels
    if (!cut.empty()) u = poly::subtract(u, cut);
    // The cut may leave several buildings, and needles where it grazes a corner.
    for (Polygon2& part : poly::drop_needles(poly::simplify(u, 0.02), kNeedleAngle)) {
      part.holes.clear();
      if (part.outer.size() >= 3 && area(part) >= 4.0) plans.push_back({part, comps, {}});
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

// Why a building's faces would fail validation ("" when they pass): the ring
// and polygon rules `validate` applies, with its tolerances, to the faces as
// computed and as the CityJSON export writes them (a thin triangle can tilt there).
std::string face_defect(const Building& b) {
  const PolygonRules rules;  // validate's defaults
  for (const auto& e : b.elements)
    for (const auto& face : e.faces)
      for (const Face& f : {face, on_export_grid(face)}) {
        VertexSnap snap(rules.snap_tol);
        std::vector<std::vector<int>> rings;
        std::vector<PolygonIssue> issues;
        if (!check_polygon(f, rules, snap, rings, issues))
          return std::string("a ") + to_string(e.type) + " face" + issues.front().where + ": " +
                 issues.front().message;
      }
  return "";
}

// Why a refined building is unusable ("" when it is fine): faces as above,
// the shell still closed, manifold, outward and free of self-intersections.
std::string refinement_defect(const Building& b) {
  const std::string faces = face_defect(b);
  if (!faces.empty()) return faces;
  const SolidCheck check = check_solid(b.solid);
  return check.ok ? "" : check.summary();
}

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
    const MultiPolygon2 rim = poly::intersect(poly::buffer({part}, apart.overhang + 0.1), whole);
    houses.push_back(poly::subtract(rim, taken));
    taken = poly::unite(taken, rim);
  }
  for (const Polygon2& piece : poly::subtract(whole, taken)) {
    const MultiPolygon2 edge = poly::buffer({piece}, 0.05);
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
    const MultiPolygon2 closed = poly::buffer(poly::buffer(h, 0.01), -0.01);
    Polygon2 part = poly::largest(poly::drop_needles(poly::simplify(closed, 0.02), kNeedleAngle));
    part.holes.clear();
    if (area(part) >= kMinFootprintPart) out.push_back(part);
  }
  return out;
}

Building model_building(const ParcelScene& s, const Segmentation& seg, const BuildingPlan& bp,
                        const ReconstructionParams& p, const std::string& id, StageClock& clock,
                        FootprintApart* apart = nullptr) {
  RoofPartitionInput rp;
  rp.outline = bp.outline;  // add_points_by_height keeps the points inside it
  rp.components = bp.components;
  std::set<int> roofs;
  for (int c : bp.components) {  // one a neighbour's cut left in two buildings serves both, with one plane
    rp.planes.push_back(seg.components[c].fit.plane);
    roofs.insert(seg.components[c].roof);
    for (int i : seg.components[c].points) {
      rp.points.push_back(plan(s.roof_points[i]));
      rp.labels.push_back(c);
    }
  }
  std::vector<Vec3> untaken;  // this building's roof points no plane took
  for (size_t i = 0; i < s.roof_points.size(); ++i)
    if (seg.label[i] < 0 && roofs.count(seg.roof_of[i])) untaken.push_back(s.roof_points[i]);
  add_points_by_height(rp, untaken);
  rp.cell = p.partition_cell_m > 0 ? p.partition_cell_m : std::max(0.1, std::min(0.25, 1.5 * seg.spacing));
  EnvelopeInput ei;
  ei.building_id = id;
  clock.lap("roof partition input");
  auto partition = [&](const Polygon2& outline) {
    rp.outline = ei.outline = split_where_neighbour_roof_ends(outline, s, seg.label);
    ei.roof = partition_roof(rp);
    ei.fits.clear();
    for (const auto& r : ei.roof) ei.fits.push_back(seg.components[r.component].fit);
    ei.party_edge = find_party_edges(ei.outline, s, seg.label);
    clock.lap("roof partition");
  };
  partition(grow_under_neighbour_eaves(bp.outline, s, seg, bp.components, bp.room));
  ei.wall_points = s.wall_points;
  ei.terrain = s.terrain;
  ei.default_overhang = p.default_overhang_m;
  ei.storey_height = p.storey_height_m;
  ei.spacing = seg.spacing;
  GrownOutline grown = grow_to_walls_outside(ei, bp.room);
  if (!grown.walls.empty()) {  // a wall seen outside: the floor and the roof reach it
    partition(poly::largest(poly::drop_needles({grown.outline}, kNeedleAngle)));
    ei.walls_on_outline = std::move(grown.walls);
  }
  Building b = build_building(ei, apart);
  clock.lap("envelope");
  if (p.optimize) {
    std::vector<Vec3> own;
    for (int c : bp.components)
      for (int i : seg.components[c].points) own.push_back(s.roof_points[i]);
    OptimizerOptions o;
    o.device = parse_compute_device(p.optimize_device);
    Building refined = b;
    OptimizeReport rep = optimize_building(refined, own, o);
    static std::once_flag logged;
    std::call_once(logged, [&] { log::info("optimizer: " + rep.device); });
    const std::string why = refinement_defect(refined);
    if (why.empty())
      b = std::move(refined);
    else  // a refinement must never cost a valid solid: keep the reconstruction
      log::warn("optimizer: " + id + " kept unrefined (" + why + ")");
  }
  measure_building(b, p.storey_height_m);
  clock.lap("measure");
  return b;
}

// A building whose solid or faces fail is modelled again from outlines on the
// hull's own axes: turning the axes moves edges by millimetres, and where four
// planes meet that can make the difference between one clean vertex and a
// sliver. The second model is kept only if it passes.
void remodel_defective(const ParcelScene& s, const Segmentation& seg, const MultiPolygon2& cut,
                       const std::vector<BuildingPlan>& plans, const ReconstructionParams& p,
                       std::vector<Building>& buildings, StageClock& clock) {
  std::vector<BuildingPlan> fallback;
  for (size_t k = 0; k < buildings.size(); ++k) {
    Building& b = buildings[k];
    if (b.solid_valid && face_defect(b).empty()) continue;
    if (fallback.empty()) fallback = plan_buildings(s, seg, cut, p.loose_point_reach_m, false);
    for (const auto& bp : fallback) {
      const double common = area(poly::intersect({bp.outline}, {plans[k].outline}));
      if (bp.components != plans[k].components ||  // a roof cut in parts: the part here
          common < 0.5 * area(plans[k].outline) || common < 0.5 * area(bp.outline))
        continue;
      Building again = model_building(s, seg, bp, p, b.id, clock);
      if (again.solid_valid && face_defect(again).empty()) b = std::move(again);
      break;
    }
    const std::string faces = face_defect(b);
    if (b.solid_valid && !faces.empty()) {  // closed, but `validate` would reject it: say so
      b.solid_valid = false;
      b.solid_problem = faces;
    }
  }
}

}  // namespace

ParcelResult reconstruct_parcel(const ParcelScene& s, const ReconstructionParams& p) {
  ParcelResult r;
  r.parcel_index = s.parcel_index;
  r.parcel_id = s.parcel_id;
  r.roof_points = long(s.roof_points.size());
  r.wall_points = long(s.wall_points.size());
  StageClock clock(r.timings);
  try {
    if (s.roof_points.size() < size_t(p.min_component_points)) {
      r.status = ParcelStatus::Empty;
      r.reason = s.roof_points.empty() ? "no roof points in the parcel"
                                       : "too few roof points for a building (" +
                                             std::to_string(s.roof_points.size()) + ")";
      return r;
    }
    Segmentation seg = segment_roofs(s.roof_points, p);
    clock.lap("segment");
    const std::set<int> split_with = apply_ownership(s, seg, p);
    for (auto& c : seg.components)
      if (int(c.points.size()) < p.min_component_points) {
        for (int i : c.points) seg.label[i] = -1;
        c.points.clear();
      } else {
        c.fit = fit_plane_robust(s.roof_points, c.points, p.plane_inlier_m);
      }
    clock.lap("ownership");
    const MultiPolygon2 cut = split_cut(s, split_with);
    auto plans = plan_buildings(s, seg, cut, p.loose_point_reach_m, true);
    clock.lap("boundary");
    for (size_t k = 0; k < plans.size();) {
      std::string id = s.parcel_id + "_b" + std::to_string(k + 1);
      FootprintApart apart;
      Building b = model_building(s, seg, plans[k], p, id, clock, &apart);
      const auto pieces = apart.parts.size() > 1 ? cut_at_narrows(plans[k].outline, apart)
                                                 : std::vector<Polygon2>{};
      if (pieces.size() > 1) {  // one building per house, modelled next
        std::vector<BuildingPlan> houses;
        for (const Polygon2& piece : pieces)  // each house may grow on its parent's room, not on its siblings
          houses.push_back({piece, plans[k].components,
                            poly::subtract(plans[k].room, poly::subtract({plans[k].outline}, {piece}))});
        plans.erase(plans.begin() + long(k));
        plans.insert(plans.begin() + long(k), houses.begin(), houses.end());
        continue;
      }
      if (apart.parts.size() > 1) {  // no cut found: say what the model leaves out
        double all = 0;
        for (const auto& part : apart.parts) all += area(part);
        char note[160];
        std::snprintf(note, sizeof note, "the footprint comes apart under the roof; only its largest part "
                      "(%.1f of %.1f m^2) has walls and a floor", area(apart.parts.front()), all);
        r.reason += (r.reason.empty() ? "" : "; ") + id + ": " + note;
      }
      r.buildings.push_back(std::move(b));
      ++k;
    }
    remodel_defective(s, seg, cut, plans, p, r.buildings, clock);
    if (r.buildings.empty()) {
      r.status = ParcelStatus::Empty;
      r.reason = "roof points form no roof plane large enough for a building";
      return r;
    }
    std::vector<Vec3> inside_roof;
    for (const auto& q : s.roof_points)
      if (poly::covers(s.parcel, plan(q))) inside_roof.push_back(q);
    std::vector<Vec3> near_wall;  // by distance: a mitred buffer reaches further at corners
    for (const auto& q : s.wall_points)
      if (poly::distance(s.parcel, plan(q)) <= kWallPointReachM) near_wall.push_back(q);
    evaluate_buildings(r.buildings, inside_roof, near_wall);
    clock.lap("evaluate");
    r.status = ParcelStatus::Ok;
    for (const auto& b : r.buildings)
      if (!b.solid_valid) {
        r.reason += (r.reason.empty() ? "" : "; ") + b.id + ": solid not valid (" +
                    b.solid_problem + ")";
      }
  } catch (const std::exception& e) {
    r.status = ParcelStatus::Failed;
    r.reason = e.what();
    r.buildings.clear();
  }
  return r;
}

}  // namespace c3d
