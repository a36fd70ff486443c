#include "core/reconstruct/ownership/ownership.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <optional>
#include <unordered_map>

#include "core/geometry/geometry.h"
#include "core/geometry/polygon_ops.h"
#include "core/reconstruct/ownership/ownership_constants.h"

namespace c3d {
using namespace ownership;
namespace {

Vec2 plan(const Vec3& p) { return p.head<2>(); }

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
      hull = poly::concave_hull(pts, std::max(kRunsHullMinAlphaM, kRunsHullSpacings * spacing));
    }
    if (runs_across(*hull, s.neighbours[n], s.parcel, p.min_component_area_m2) ||
        runs_across(*hull, s.parcel, s.neighbours[n], p.min_component_area_m2))
      split_with.insert(int(n));
  }
}

// What a roof cell must hold to count as roof: a fifth of the typical count
// where it lies (3 of Cimahi's 15), so stray points in a cell do not make it
// roof. Without the scan's density (a scene alone), the scene's own typical.
class CellNeed {
 public:
  explicit CellNeed(const ParcelScene& s) : s_(s) {}
  int operator()(const CellIndex& cell) const {
    int typical = s_.roof_density.at(cell);
    if (typical <= 0) {
      if (own_ < 0) own_ = typical_roof_points_per_cell(s_.roof_points);
      typical = own_;
    }
    return std::max(1, (typical + kTypicalShareOfCell - 1) / kTypicalShareOfCell);
  }

 private:
  const ParcelScene& s_;
  mutable int own_ = -1;
};

// Roof found in a band of land: the cells of a fixed grid (the local frame's,
// the same in every scene) holding a share of the scan's typical count or
// more. Cells, not points, so that the answer does not hang on the scan's
// density, and a share of the typical count, not a fixed one, so that a
// sparse scan's cells count as a dense one's do.
class RoofCells {
 public:
  explicit RoofCells(const CellNeed& need) : need_(need) {}
  void add(const Vec2& q) {
    const CellIndex cell = roof_cell(q);
    if (++count_[cell] == need_(cell)) ++covered_;
  }
  bool enough() const { return covered_ >= kMinRoofCells; }

 private:
  const CellNeed& need_;
  std::map<CellIndex, int> count_;
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
  const auto in_band = [&](double d) { return d > shared_depth && d <= s.context_m - kClipRoundingM; };
  const CellNeed needed(s);
  std::vector<RoofCells> there(s.neighbours.size(), RoofCells(needed));
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
    RoofCells here(needed);
    for (size_t k = 0; k < own.size() && !here.enough(); ++k)
      if (in_band(poly::distance(s.neighbours[n], own[k]))) here.add(own[k]);
    if (here.enough()) meeting.insert(int(n));
  }
  return meeting;
}

// Per component, the land each of its points stands on: -1 this parcel, a
// neighbour's index, or the neighbours' count for land outside the layer.
std::vector<std::vector<int>> lands_of_components(const ParcelScene& s, const Segmentation& seg) {
  const int outside = int(s.neighbours.size());  // land outside the layer
  auto land_of = [&](const Vec2& q) {            // -1: this parcel
    if (poly::covers(s.parcel, q)) return -1;
    for (size_t n = 0; n < s.neighbours.size(); ++n)
      if (poly::covers(s.neighbours[n], q)) return int(n);
    return outside;
  };
  std::vector<std::vector<int>> lands(seg.components.size());
  for (size_t c = 0; c < seg.components.size(); ++c)
    for (int i : seg.components[c].points) lands[c].push_back(land_of(plan(s.roof_points[i])));
  return lands;
}

// Gives away, in `seg`, component `ci` (standing on `where`) or its parts on
// the neighbours' parcels it is split against (see give_away).
void give_away_component(Segmentation& seg, size_t ci, const std::vector<int>& where, const std::set<int>& split_with,
                         size_t neighbours, bool roof_mostly_on_parcels) {
  const size_t outside = neighbours;
  auto& c = seg.components[ci];
  std::vector<long> held(neighbours + 1, 0);
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
  if (!outside_ours || roof_mostly_on_parcels) held[outside] = 0;
  if (own == 0 || own < *std::max_element(held.begin(), held.end())) {
    for (int i : c.points) seg.label[i] = seg.roof_of[i] = -1;  // another's
    c.points.clear();
    return;
  }
  if (!split) return;  // whole: ours, overhang included
  std::vector<int> kept;
  for (size_t k = 0; k < c.points.size(); ++k) {
    if (split_with.count(where[k]) || (!outside_ours && where[k] == int(outside)))
      seg.label[c.points[k]] = seg.roof_of[c.points[k]] = -1;
    else
      kept.push_back(c.points[k]);
  }
  c.points = kept;
}

// Ownership: a component goes whole to the land holding most of its points (an
// overhang reaches at most the overhang buffer across a boundary) and is
// modelled here only when that is this parcel. Where the buildings meet at a
// neighbour's boundary (meeting_neighbours) or a component runs across the
// neighbour's parcel (add_runs_across), every outline is cut there,
// and so every component crossing it is split there too, the parts on the
// neighbours' parcels being theirs: the neighbour decides the same from its
// side and cuts at the same line, so a part given away whole would be
// modelled by nobody, and a part kept whole would be modelled twice.
// Land outside every parcel of the layer (streets, parcels the layer leaves
// out) votes against a component only when the roof it belongs to stands
// mostly there: the corner of a building on a parcel the layer leaves out is
// nobody's here, while a porch of this parcel's house reaching over an alley
// stays with the house, and so does a slope of a neighbour's low roof that
// spans an alley and reaches onto this parcel. Land outside the layer is never
// split against: roofs here overhang streets and alleys by metres. Edits
// `seg` (a copy) and returns the neighbours split against.
std::set<int> give_away(const ParcelScene& s, Segmentation& seg, const ReconstructionParams& p) {
  const int outside = int(s.neighbours.size());
  const std::vector<std::vector<int>> lands = lands_of_components(s, seg);
  std::vector<long> roof_on_parcels(size_t(seg.roof_count), 0), roof_outside(size_t(seg.roof_count), 0);
  for (size_t c = 0; c < seg.components.size(); ++c)
    for (int land : lands[c]) {
      roof_on_parcels[size_t(seg.components[c].roof)] += land != outside;
      roof_outside[size_t(seg.components[c].roof)] += land == outside;
    }
  std::set<int> split_with = meeting_neighbours(s, p);
  for (size_t c = 0; c < seg.components.size(); ++c) add_runs_across(s, seg.components[c], lands[c], seg.spacing, p, split_with);
  for (size_t ci = 0; ci < seg.components.size(); ++ci) {
    const size_t roof = size_t(seg.components[ci].roof);
    give_away_component(seg, ci, lands[ci], split_with, s.neighbours.size(),
                        roof_on_parcels[roof] >= roof_outside[roof]);
  }
  return split_with;
}

// A part left here with too few points for a plane (the component's own
// minimum where it has one) joins the roof's loose points: no component, its
// roof kept.
void drop_remnants(Segmentation& seg, int min_points) {
  for (auto& c : seg.components)
    if (int(c.points.size()) < (c.min_points > 0 ? c.min_points : min_points)) {
      for (int i : c.points) seg.label[i] = -1;
      c.points.clear();
    }
}

// A roof split with a neighbour ends at their boundary, and beyond their
// shared corner (over a street, or over a third parcel whose land their eaves
// reach) where the land is nearer to the neighbour: each keeps its side, so
// no eave there is modelled twice.
MultiPolygon2 split_cut(const ParcelScene& s, const std::set<int>& split_with) {
  MultiPolygon2 cut;
  for (int n : split_with)
    cut = poly::unite_all(
        {cut, s.neighbours[n], poly::nearer_to(s.neighbours[n], s.parcel, s.context_m, kNearerStepM)});
  return cut;
}

}  // namespace

std::pair<long, long> roof_cell(const Vec2& q) {
  return {std::lround(std::floor(q.x() / kRoofCellM)), std::lround(std::floor(q.y() / kRoofCellM))};
}

CellIndex density_block(const CellIndex& world_cell) {
  const long cells = std::lround(kDensityBlockM / kRoofCellM);  // whole cells: a block's edge is a cell's
  const auto floor_div = [cells](long v) { return v >= 0 ? v / cells : -((-v + cells - 1) / cells); };
  return {floor_div(world_cell.first), floor_div(world_cell.second)};
}

int RoofDensity::at(const CellIndex& local_cell) const {
  if (typical.empty()) return 0;
  const auto it = typical.find(density_block({local_cell.first + offset.first, local_cell.second + offset.second}));
  return it == typical.end() ? 0 : it->second;
}

int typical_roof_points_per_cell(const std::map<int, size_t>& cells_by_count) {
  size_t cells = 0;
  for (const auto& [count, n] : cells_by_count) cells += n;
  size_t seen = 0;  // the count of rank cells / 2, as nth_element picks it below
  for (const auto& [count, n] : cells_by_count)
    if ((seen += n) > cells / 2) return count;
  return 0;
}

int typical_roof_points_per_cell(const std::vector<Vec3>& roof_points) {
  std::unordered_map<uint64_t, int> count;  // hashed, not sorted: 0.25 s, not 0.9 s, on 6 M points
  count.reserve(roof_points.size() / 4);
  for (const auto& q : roof_points) {
    const auto [ix, iy] = roof_cell(plan(q));
    ++count[uint64_t(uint32_t(ix)) << 32 | uint32_t(iy)];
  }
  if (count.empty()) return 0;
  std::vector<int> counts;
  counts.reserve(count.size());
  for (const auto& [cell, n] : count) counts.push_back(n);
  auto mid = counts.begin() + long(counts.size() / 2);
  std::nth_element(counts.begin(), mid, counts.end());
  return *mid;
}

Ownership decide_ownership(const ParcelScene& s, const Segmentation& seg, const ReconstructionParams& p) {
  Segmentation kept = seg;
  Ownership own;
  own.split_with = give_away(s, kept, p);
  drop_remnants(kept, p.min_component_points);
  own.label = std::move(kept.label);
  own.roof_of = std::move(kept.roof_of);
  for (auto& c : kept.components) own.component_points.push_back(std::move(c.points));
  own.cut = split_cut(s, own.split_with);
  own.parcel = s.parcel;
  own.parcel_core = poly::buffer(s.parcel, -kBoundaryStripM);
  own.neighbours = s.neighbours;
  own.roof_points = s.roof_points;
  own.wall_points = s.wall_points;
  own.roof_grid = index_points(own.roof_points, kGridCellM);
  own.wall_grid = index_points(own.wall_points, kGridCellM);
  return own;
}

Segmentation kept_segmentation(const Segmentation& seg, const Ownership& own) {
  Segmentation kept = seg;
  kept.label = own.label;
  kept.roof_of = own.roof_of;
  for (size_t c = 0; c < kept.components.size(); ++c) kept.components[c].points = own.component_points[c];
  return kept;
}

}  // namespace c3d
