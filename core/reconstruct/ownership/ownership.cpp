#include "core/reconstruct/ownership/ownership.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <optional>
#include <unordered_map>

#include "core/reconstruct/envelope/envelope.h"
#include "core/geometry/geometry.h"
#include "core/geometry/polygon_ops.h"

namespace c3d {
namespace {

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

constexpr double kRoofCellM = 0.5;  // the ownership grid's cell

std::pair<long, long> roof_cell(const Vec2& q) {
  return {std::lround(std::floor(q.x() / kRoofCellM)), std::lround(std::floor(q.y() / kRoofCellM))};
}

// Roof found in a band of land: the cells of a fixed grid (the local frame's,
// the same in every scene) holding a share of the scan's typical count or
// more. Cells, not points, so that the answer does not hang on the scan's
// density, and a share of the typical count, not a fixed one, so that a
// sparse scan's cells count as a dense one's do.
class RoofCells {
 public:
  explicit RoofCells(int points_per_cell) : needed_(points_per_cell) {}
  void add(const Vec2& q) {
    if (++count_[roof_cell(q)] == needed_) ++covered_;
  }
  bool enough() const { return covered_ >= kMinCells; }

 private:
  static constexpr size_t kMinCells = 4;  // 1 m^2: a metre of roof along the boundary, a metre deep
  int needed_;
  std::map<std::pair<long, long>, int> count_;
  size_t covered_ = 0;
};

// What a cell must hold to count as roof: a fifth of the scan's typical
// count (3 of Cimahi's 15), so stray points in a cell do not make it roof.
int points_needed_per_cell(const ParcelScene& s) {
  const int typical = s.roof_points_per_cell > 0 ? s.roof_points_per_cell : typical_roof_points_per_cell(s.roof_points);
  return std::max(1, (typical + 4) / 5);
}

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
  const int needed = points_needed_per_cell(s);
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

}  // namespace

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


namespace {

// Whether the handheld scanner saw this edge's wall (under the edge or just
// outside it, below the roof there): a wall shared with the neighbour's house
// is covered by it, so a wall seen from outside stands free, on an alley or a
// yard, whatever roof-class points lie across the line (05794: its facade
// seen 0.9 m inside its eave, a screen classed roof hanging at the line). Not
// on a short edge: a few wall points there are as likely the end of a facade
// running on past the corner (two row houses' party jogs of 1.1 and 1.5 m on
// the sample towns lost their party walls to 26-28 such points).
constexpr double kMinSeenPartyEdgeM = 3.0;

bool wall_seen_under(const ParcelScene& s, const Vec2& a, const Vec2& b, std::vector<double>& own_z) {
  if ((b - a).norm() < kMinSeenPartyEdgeM || own_z.size() < 10) return false;
  return fit_wall(s.wall_points, a, b, -1e9, quantile(own_z, 0.1), false).found;
}

// Whether m lies on the parcel boundary, n the outward normal of the edge
// through it: the parcel just inside, not just outside.
bool on_parcel_line(const ParcelScene& s, const Vec2& m, const Vec2& n) {
  return poly::covers(s.parcel, m - 0.15 * n) && !poly::covers(s.parcel, m + 0.15 * n);
}

constexpr double kPartyBinM = 0.5;     // stretch of an edge counted at a time
constexpr double kMinStretchM = 2.0;   // shortest party or free stretch a split leaves
constexpr int kMinPointsInBin = 2;     // roof points 0.5-1 m across in a bin that say "a house"
constexpr size_t kMaxGapBins = 2;      // a gap of 1 m in those points (a skylight, a shadow) is no end

// Where along edge a -> b (outward normal n) the neighbour's roof lies right
// across it: per bin of kPartyBinM, on the parcel line and with roof points
// no component here keeps 0.5-1 m beyond it; and the t of those points.
struct AcrossProfile {
  std::vector<bool> covered;
  std::vector<double> first_t, last_t;
};

AcrossProfile profile_across(const Vec2& a, const Vec2& b, const ParcelScene& s, const std::vector<int>& label) {
  const double len = (b - a).norm();
  const Vec2 d = (b - a) / len, n(d.y(), -d.x());
  const size_t bins = size_t(std::ceil(len / kPartyBinM));
  AcrossProfile p{std::vector<bool>(bins, false), std::vector<double>(bins, len), std::vector<double>(bins, 0)};
  std::vector<bool> on_line(bins);
  for (size_t i = 0; i < bins; ++i) {
    on_line[i] = on_parcel_line(s, a + std::min(len, (double(i) + 0.5) * kPartyBinM) * d, n);
  }
  if (std::none_of(on_line.begin(), on_line.end(), [](bool b) { return b; })) return p;
  std::vector<int> count(bins, 0);
  for (size_t k = 0; k < s.roof_points.size(); ++k) {
    if (label[k] >= 0) continue;
    const Vec2 q = plan(s.roof_points[k]) - a;
    const double t = d.dot(q), off = n.dot(q);
    if (t < 0 || t >= len || off <= 0.5 || off >= 1.0) continue;
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
         0.1 * double(to - from);
}
}  // namespace

// A long edge on the parcel line that meets the neighbour's house along one
// stretch and faces a yard or an alley along the rest (9's south-west side:
// 9 m against 05803's roof, then 5 m over open land) gets a vertex
// where the neighbour's roof ends, so each stretch is decided on its own:
// a party wall along the house, a free wall with its eave beyond it.
Polygon2 split_where_neighbour_roof_ends(const Polygon2& outline, const ParcelScene& s,
                                         const std::vector<int>& label) {
  const Ring2& r = outline.outer;
  Ring2 out;
  for (size_t i = 0; i < r.size(); ++i) {
    const Vec2 a = r[i], b = r[(i + 1) % r.size()];
    out.push_back(a);
    const double len = (b - a).norm();
    if (len < 2 * kMinStretchM) continue;
    const AcrossProfile p = profile_across(a, b, s, label);
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
std::vector<bool> find_party_edges(const Polygon2& outline, const ParcelScene& s,
                                   const std::vector<int>& label) {
  const Ring2& r = outline.outer;
  std::vector<bool> party(r.size(), false);
  for (size_t i = 0; i < r.size(); ++i) {
    Vec2 a = r[i], b = r[(i + 1) % r.size()];
    double len = (b - a).norm();
    if (len < 1.0) continue;
    Vec2 d = (b - a) / len, n(d.y(), -d.x()), m = 0.5 * (a + b);
    if (!on_parcel_line(s, m, n)) continue;
    int across = 0, further = 0;
    std::vector<double> own_z;  // this parcel's roof just inside the edge
    for (size_t k = 0; k < s.roof_points.size(); ++k) {
      Vec2 q = plan(s.roof_points[k]) - a;
      double t = d.dot(q), off = n.dot(q);
      if (t <= 0.1 * len || t >= 0.9 * len) continue;
      if (label[k] >= 0 && off > -0.6 && off <= 0) own_z.push_back(s.roof_points[k].z());
      if (label[k] < 0 && off > 0.0 && off < 1.0) ++across, further += off > 0.5;
    }
    // The neighbour's house meeting this one gives roof all the way across the
    // metre; a gutter, a screen or an eave tip reaching over the line only in
    // its first half (05803's side facing open land: a 0.3-0.5 m strip).
    party[i] = across >= std::max(10.0, 2.0 * len) && further >= std::max(5.0, 0.5 * len) &&
               !wall_seen_under(s, a, b, own_z);
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

namespace {
constexpr double kMaxHiddenGapM = 0.8;
constexpr double kHigherEaveM = 1.0;  // a storey or a roof pitch higher, not a step of this roof
}  // namespace

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
Polygon2 grow_under_neighbour_eaves(const Polygon2& outline, const ParcelScene& s, const Segmentation& seg,
                                    const std::vector<int>& components, const MultiPolygon2& room) {
  std::set<int> roofs;
  for (int c : components) roofs.insert(seg.components[size_t(c)].roof);
  const Ring2& r = outline.outer;
  const MultiPolygon2 land = poly::intersect(s.parcel, room);
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

}  // namespace c3d
