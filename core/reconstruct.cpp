#include "core/reconstruct.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <optional>
#include <map>
#include <mutex>
#include <set>
#include <cstdio>
#include <cstdlib>

#include "core/envelope.h"
#include "core/evaluate.h"
#include "core/geometry.h"
#include "core/measure.h"
#include "core/optimizer.h"
#include "core/outline.h"
#include "core/polygon_ops.h"
#include "core/polygon_rules.h"
#include "core/roof.h"
#include "core/segmentation.h"
#include "core/solid_check.h"

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

// The q-quantile of v (0 <= q <= 1), v non-empty; v is reordered.
double quantile(std::vector<double>& v, double q) {
  auto k = v.begin() + long(q * double(v.size() - 1));
  std::nth_element(v.begin(), k, v.end());
  return *k;
}

constexpr size_t kMinPointsAcross = 10;  // fewer points on a neighbour's land say nothing about it

// Whether a component (its `hull`) runs over parcel `over` from parcel `from`
// back onto it: the hull, `over` taken out, leaves roof on `from` on two
// sides. A row roof over a parcel narrower than twice an overhang, with the
// other on both sides, lies nowhere deep in it, yet is shared.
bool runs_across(const MultiPolygon2& hull, const MultiPolygon2& over, const MultiPolygon2& from,
                 double min_side_area) {
  int sides = 0;
  for (const Polygon2& side : poly::subtract(hull, over))
    sides += area(poly::intersect({side}, from)) >= min_side_area;
  return sides >= 2;
}

// Adds to `split_with` the neighbours a component shares its roof with:
// running across their parcel from this one back onto it, or across this one
// from theirs, it is a roof of attached houses (both parcels see it so).
void add_runs_across(const ParcelScene& s, const RoofComponent& c, const std::vector<int>& land, double spacing,
                     const ReconstructionParams& p, std::set<int>& split_with) {
  std::vector<long> held(s.neighbours.size(), 0);
  for (int l : land)
    if (l >= 0 && l < int(s.neighbours.size())) ++held[size_t(l)];
  std::optional<MultiPolygon2> hull;  // the component's plan hull, once a neighbour needs it
  for (size_t n = 0; n < held.size(); ++n) {
    if (held[n] < long(kMinPointsAcross) || split_with.count(int(n))) continue;
    if (!hull) {
      std::vector<Vec2> pts;
      for (int i : c.points) pts.push_back(plan(s.roof_points[i]));
      hull = poly::concave_hull(pts, std::max(1.0, 5.0 * spacing));
    }
    if (runs_across(*hull, s.neighbours[n], s.parcel, p.min_component_area_m2) ||
        runs_across(*hull, s.parcel, s.neighbours[n], p.min_component_area_m2))
      split_with.insert(int(n));
  }
}

// Roof found in a band of land: the cells of a fixed grid (the local frame's,
// the same in every scene) holding a few roof points or more. Cells, not
// points, so that the answer does not hang on the scan's density.
class RoofCells {
 public:
  void add(const Vec2& q) {
    if (++count_[{std::lround(std::floor(q.x() / kCell)), std::lround(std::floor(q.y() / kCell))}] == kPointsPerCell)
      ++covered_;
  }
  bool enough() const { return covered_ >= kMinCells; }

 private:
  static constexpr double kCell = 0.5;       // m
  static constexpr int kPointsPerCell = 3;
  static constexpr size_t kMinCells = 4;     // 1 m^2: a metre of roof along the boundary, a metre deep
  std::map<std::pair<long, long>, int> count_;
  size_t covered_ = 0;
};

// Neighbours whose buildings meet this parcel's at their boundary: roof
// deeper into their parcel than an overhang reaches (the overhang buffer plus
// a margin), and as deep into this one from theirs. The scene's raw roof
// points are counted, and only in the band both parcels' scenes hold (up to
// the context width, less the clip buffer's rounding at corners), so the
// neighbour, looking from its side, comes to the same answer: a roof standing
// deep in one parcel and hanging over the other is an eave for both.
std::set<int> meeting_neighbours(const ParcelScene& s, const ReconstructionParams& p) {
  const double shared_depth = s.overhang_buffer_m + p.shared_roof_depth_m;
  const auto in_band = [&](double d) { return d > shared_depth && d <= s.context_m - 0.05; };
  std::vector<RoofCells> there(s.neighbours.size());
  std::vector<Vec2> own;
  for (const auto& point : s.roof_points) {
    const Vec2 q = plan(point);
    const double d = poly::distance(s.parcel, q);  // 0 on the parcel
    if (d == 0) {
      own.push_back(q);
    } else if (in_band(d)) {
      for (size_t n = 0; n < s.neighbours.size(); ++n)
        if (poly::covers(s.neighbours[n], q)) {
          there[n].add(q);
          break;
        }
    }
  }
  std::set<int> meeting;
  for (size_t n = 0; n < there.size(); ++n) {
    if (!there[n].enough()) continue;
    RoofCells here;
    for (size_t k = 0; k < own.size() && !here.enough(); ++k)
      if (in_band(poly::distance(s.neighbours[n], own[k]))) here.add(own[k]);
    if (here.enough()) meeting.insert(int(n));
  }
  return meeting;
}

// Ownership: a component goes whole to the land holding most of its points (an
// overhang reaches at most the overhang buffer across a boundary) and is
// modelled here only when that is this parcel. Where the buildings meet at a
// neighbour's boundary (meeting_neighbours) or a component runs across the
// neighbour's parcel (add_runs_across), every outline is cut there,
// and so every component crossing it is split there too, the parts on the
// neighbours' parcels being theirs: the neighbour decides the same from its
// side and cuts at the same line, so a part given away whole would be
// modelled by nobody, and a part kept whole would be modelled twice. A part
// left here with too few points for a plane joins the roof's loose points.
// Land outside every parcel of the layer (streets, parcels the layer leaves
// out) votes against a component only when the roof it belongs to stands
// mostly there: the corner of a building on a parcel the layer leaves out is
// nobody's here, while a porch of this parcel's house reaching over an alley
// stays with the house, and so does a slope of a neighbour's low roof that
// spans an alley and reaches onto this parcel. Land outside the layer is never
// split against: roofs here overhang streets and alleys by metres. Returns the
// neighbours split against.
std::set<int> apply_ownership(const ParcelScene& s, Segmentation& seg, const ReconstructionParams& p) {
  const int outside = int(s.neighbours.size());  // land outside the layer
  auto land_of = [&](const Vec2& q) {            // -1: this parcel
    if (poly::covers(s.parcel, q)) return -1;
    for (size_t n = 0; n < s.neighbours.size(); ++n)
      if (poly::covers(s.neighbours[n], q)) return int(n);
    return outside;
  };
  std::vector<std::vector<int>> lands(seg.components.size());
  std::vector<long> roof_on_parcels(size_t(seg.roof_count), 0), roof_outside(size_t(seg.roof_count), 0);
  for (size_t c = 0; c < seg.components.size(); ++c)
    for (int i : seg.components[c].points) {
      const int land = land_of(plan(s.roof_points[i]));
      lands[c].push_back(land);
      roof_on_parcels[size_t(seg.components[c].roof)] += land != outside;
      roof_outside[size_t(seg.components[c].roof)] += land == outside;
    }
  std::set<int> split_with = meeting_neighbours(s, p);
  for (size_t c = 0; c < seg.components.size(); ++c) add_runs_across(s, seg.components[c], lands[c], seg.spacing, p, split_with);
  for (size_t ci = 0; ci < seg.components.size(); ++ci) {
    auto& c = seg.components[ci];
    const auto& where = lands[ci];
    std::vector<long> held(s.neighbours.size() + 1, 0);
    long own = 0;
    for (int land : where) ++(land < 0 ? own : held[size_t(land)]);
    bool split = false;  // crossing a boundary split against
    for (int n : split_with) split = split || held[size_t(n)] >= long(kMinPointsAcross);
    // Split with a few stray points here only (fewer than say anything about
    // this parcel), the part over land outside the layer goes with the
    // neighbour holding more of it: that neighbour models it.
    bool outside_ours = true;
    if (split)  // the parts on the neighbours' parcels it is split against are theirs
      for (int n : split_with) {
        outside_ours = outside_ours && (own >= long(kMinPointsAcross) || own >= held[size_t(n)]);
        held[size_t(n)] = 0;
      }
    if (!outside_ours || roof_on_parcels[size_t(c.roof)] >= roof_outside[size_t(c.roof)])
      held[size_t(outside)] = 0;
    if (own == 0 || own < *std::max_element(held.begin(), held.end())) {
      for (int i : c.points) seg.label[i] = seg.roof_of[i] = -1;  // another's
      c.points.clear();
      continue;
    }
    if (!split) continue;  // whole: ours, overhang included
    std::vector<int> kept;
    for (size_t k = 0; k < c.points.size(); ++k) {
      if (split_with.count(where[k]) || (!outside_ours && where[k] == outside))
        seg.label[c.points[k]] = seg.roof_of[c.points[k]] = -1;
      else
        kept.push_back(c.points[k]);
    }
    c.points = kept;
  }
  return split_with;
}

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

// Outline edges on the parcel boundary with the neighbour's roof right across.
std::vector<bool> find_party_edges(const Polygon2& outline, const ParcelScene& s,
                                   const std::vector<int>& label) {
  const Ring2& r = outline.outer;
  std::vector<bool> party(r.size(), false);
  for (size_t i = 0; i < r.size(); ++i) {
    Vec2 a = r[i], b = r[(i + 1) % r.size()];
    double len = (b - a).norm();
    if (len < 1.0) continue;
    Vec2 d = (b - a) / len, n(d.y(), -d.x()), m = 0.5 * (a + b);
    if (!poly::covers(s.parcel, m - 0.15 * n) || poly::covers(s.parcel, m + 0.15 * n)) continue;
    int across = 0;
    for (size_t k = 0; k < s.roof_points.size(); ++k) {
      if (label[k] >= 0) continue;
      Vec2 q = plan(s.roof_points[k]) - a;
      double t = d.dot(q), off = n.dot(q);
      if (t > 0.1 * len && t < 0.9 * len && off > 0.0 && off < 1.0) ++across;
    }
    party[i] = across >= std::max(10.0, 2.0 * len);
  }
  // A short jog on the parcel line (left where the outline snaps to the
  // building's axes but the boundary runs a little askew) continues the party
  // wall beside it; as an exterior wall it would take the overhang and pull the
  // party wall inward.
  const size_t n = r.size();
  const MultiPolygon2 core = poly::buffer(s.parcel, -0.3);  // parcel minus its boundary strip
  std::vector<bool> jog(n, false);
  for (size_t i = 0; i < n; ++i) {
    Vec2 a = r[i], b = r[(i + 1) % n];
    if (party[i] || (b - a).norm() >= 1.0) continue;
    Vec2 m = 0.5 * (a + b);
    if (poly::covers(core, m) || poly::distance(s.parcel, m) > 0.3) continue;  // off the parcel line
    Vec2 d = (b - a).normalized();
    for (size_t k : {(i + n - 1) % n, (i + 1) % n}) {
      Vec2 e = (r[(k + 1) % n] - r[k]).normalized();
      if (party[k] && d.dot(e) > std::cos(20.0 * M_PI / 180)) jog[i] = true;
    }
  }
  for (size_t i = 0; i < n; ++i) party[i] = party[i] || jog[i];
  return party;
}

struct BuildingPlan {
  Polygon2 outline;
  std::vector<int> components;
  MultiPolygon2 room;  // where the outline may grow to a wall seen outside it
};

// A building's wall stands on its own parcel; this much beyond the boundary
// is registration error between the scans and the parcel layer.
constexpr double kWallRoomM = 0.3;

// A neighbour's eave hides the edge of this roof: an outline edge that stops
// short of the parcel boundary (by up to kMaxHiddenGapM, evenly along it)
// where a roof not this building's stands over the whole gap, clearly higher
// than this roof at the edge, and a neighbour's parcel lies beyond. The scan cannot see under the eave, so this roof
// ends where the neighbour's begins; it runs on under it to the boundary and
// meets the neighbour there (a party wall), rather than standing free with an
// overhang of its own (9 under 05801's eave: an exterior wall 0.8 m inside the
// boundary with an outer ceiling, where 05801 sees a party wall). A wall seen
// under the edge or in the gap says the house stands free (an alley under the
// eave): the edge stays.
constexpr double kMaxHiddenGapM = 0.8;
constexpr double kHigherEaveM = 1.0;  // a storey or a roof pitch higher, not a step of this roof

Polygon2 grow_under_neighbour_eaves(const Polygon2& outline, const ParcelScene& s, const Segmentation& seg,
                                    const BuildingPlan& bp) {
  std::set<int> roofs;
  for (int c : bp.components) roofs.insert(seg.components[size_t(c)].roof);
  const Ring2& r = outline.outer;
  const MultiPolygon2 land = poly::intersect(s.parcel, bp.room);
  MultiPolygon2 grown{outline};
  bool changed = false;
  for (size_t i = 0; i < r.size(); ++i) {
    const Vec2 a = r[i], b = r[(i + 1) % r.size()];
    const double len = (b - a).norm();
    if (len < 2.0) continue;
    const Vec2 d = (b - a) / len, n(d.y(), -d.x());  // outward (CCW ring)
    // The gap to the boundary, measured across the edge at five places.
    double gmin = 1e9, gmax = -1e9;
    for (double f : {0.1, 0.3, 0.5, 0.7, 0.9}) {
      const Vec2 m = a + f * len * d;
      double g = 0;
      while (g <= kMaxHiddenGapM + 0.02 && poly::covers(s.parcel, m + (g + 0.02) * n)) g += 0.02;
      gmin = std::min(gmin, g), gmax = std::max(gmax, g);
    }
    if (gmin < 0.1 || gmax > kMaxHiddenGapM || gmax - gmin > 0.2) continue;  // on it, too far, or askew
    const Vec2 across = a + 0.5 * len * d + (gmax + 0.2) * n;
    if (std::none_of(s.neighbours.begin(), s.neighbours.end(),
                     [&](const MultiPolygon2& nb) { return poly::covers(nb, across); }))
      continue;  // no neighbour's land beyond: nobody to meet there
    std::vector<double> own_z, over_z;
    std::vector<bool> covered(size_t(len / 0.5) + 1, false);
    int walls_in_gap = 0;
    for (size_t k = 0; k < s.roof_points.size(); ++k) {
      const Vec2 q = plan(s.roof_points[k]) - a;
      const double t = d.dot(q), off = n.dot(q);
      if (t < 0.1 * len || t > 0.9 * len) continue;
      const bool ours = roofs.count(seg.roof_of[k]) > 0;
      if (ours && off > -0.6 && off <= 0) own_z.push_back(s.roof_points[k].z());
      if (!ours && off > 0 && off < gmax + 0.05) {
        over_z.push_back(s.roof_points[k].z());
        covered[size_t(t / 0.5)] = true;
      }
    }
    for (const auto& w : s.wall_points) {
      const Vec2 q = plan(w) - a;
      const double t = d.dot(q), off = n.dot(q);
      walls_in_gap += t > 0.1 * len && t < 0.9 * len && off > 0.05 && off < gmin - 0.05;
    }
    const size_t spans = size_t(0.8 * len / 0.5);
    if (own_z.size() < 10 || over_z.size() < 10 || walls_in_gap >= 10) continue;
    if (size_t(std::count(covered.begin(), covered.end(), true)) < size_t(0.7 * double(spans))) continue;
    const double own_top = quantile(own_z, 0.9), over_bottom = quantile(over_z, 0.1);
    if (over_bottom < own_top + kHigherEaveM) continue;  // this roof's own edge, or a roof at its height
    if (fit_wall(s.wall_points, a, b, -1e9, own_top, false).found) continue;  // its wall is seen: it stands free
    const Vec2 o = (gmax + 0.3) * n;  // past the boundary, then cut back to it
    grown = poly::unite(grown, poly::intersect({Polygon2{{a, b, b + o, a + o}, {}}}, land));
    changed = true;
  }
  if (!changed) return outline;
  Polygon2 best = poly::largest(poly::simplify(grown, 0.005));
  best.holes.clear();
  return best;
}

// A roof split with a neighbour ends at their boundary, and beyond their
// shared corner (over a street, or over a third parcel whose land their eaves
// reach) where the land is nearer to the neighbour: each keeps its side, so
// no eave there is modelled twice.
MultiPolygon2 split_cut(const ParcelScene& s, const std::set<int>& split_with) {
  MultiPolygon2 cut;
  for (int n : split_with)
    cut = poly::unite_all({cut, s.neighbours[n], poly::nearer_to(s.neighbours[n], s.parcel, s.context_m, 0.25)});
  return cut;
}

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
    rp.outline = ei.outline = outline;
    ei.roof = partition_roof(rp);
    ei.fits.clear();
    for (const auto& r : ei.roof) ei.fits.push_back(seg.components[r.component].fit);
    ei.party_edge = find_party_edges(outline, s, seg.label);
    clock.lap("roof partition");
  };
  partition(grow_under_neighbour_eaves(bp.outline, s, seg, bp));
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
    std::call_once(logged, [&] { std::fprintf(stderr, "optimizer: %s\n", rep.device.c_str()); });
    const std::string why = refinement_defect(refined);
    if (why.empty())
      b = std::move(refined);
    else  // a refinement must never cost a valid solid: keep the reconstruction
      std::fprintf(stderr, "optimizer: %s kept unrefined (%s)\n", id.c_str(), why.c_str());
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
