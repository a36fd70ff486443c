// The sample town: parcels in blocks along streets, a terrain, one truth
// building group per parcel (or a row of attached houses over 2-3 parcels)
// placed on it, and the point cloud (sample_scan.cpp). sample_detail.h lists
// the other files.
#include "core/synthetic/sample_town.h"

#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <stdexcept>

#include "core/geometry/geometry.h"
#include "core/synthetic/sample_detail.h"

namespace c3d {

const char* to_string(SampleLayout l) {
  switch (l) {
    case SampleLayout::Gable: return "gable";
    case SampleLayout::Hip: return "hip";
    case SampleLayout::CrossGable: return "cross_gable";
    case SampleLayout::Shed: return "shed";
    case SampleLayout::Flat: return "flat";
    case SampleLayout::TwoLevel: return "two_level";
    case SampleLayout::RowHouse: return "row_gable";
    case SampleLayout::Empty: return "empty";
    case SampleLayout::Vault: return "vault";
    case SampleLayout::GroundVault: return "ground_vault";
    case SampleLayout::Dome: return "dome";
    case SampleLayout::ShallowDome: return "shallow_dome";
    case SampleLayout::Cone: return "cone";
    case SampleLayout::OnionDome: return "onion";
    case SampleLayout::DomeOnFlat: return "dome_on_flat";
    case SampleLayout::Saddle: return "saddle";
    case SampleLayout::Wave: return "wave";
    case SampleLayout::RoundTower: return "round_tower";
    case SampleLayout::ApsedHall: return "apsed_hall";
  }
  return "?";
}

using namespace sample_detail;

// ---- The town ----

namespace {

constexpr int kPerRow = 5;          // parcels along a block side
constexpr double kBlockWidth = 100; // m, along the street
constexpr double kStreet = 10;      // m
constexpr double kMaxDepth = 32;    // m, parcel depth upper bound

// Terrain: gentle slope plus two undulations; local xy -> world z.
struct Terrain {
  double z0, gx, gy, a1, l1, l2, ph1, ph2, a2, l3, ph3;
  explicit Terrain(Rng& r)
      : z0(r.uniform(700, 760)), gx(r.uniform(-0.02, 0.02)), gy(r.uniform(-0.02, 0.02)),
        a1(r.uniform(0.5, 1.5)), l1(r.uniform(150, 400)), l2(r.uniform(150, 400)),
        ph1(r.uniform(0, 2 * kPi)), ph2(r.uniform(0, 2 * kPi)), a2(r.uniform(0.2, 0.6)),
        l3(r.uniform(60, 120)), ph3(r.uniform(0, 2 * kPi)) {}
  double operator()(double x, double y) const {
    return z0 + gx * x + gy * y + a1 * std::sin(2 * kPi * x / l1 + ph1) * std::cos(2 * kPi * y / l2 + ph2) +
           a2 * std::sin(2 * kPi * (x + y) / l3 + ph3);
  }
};

// Parcel rectangles in the town frame, layer order: block by block, south row
// west to east, then north row.
std::vector<TownParcel> lay_out_parcels(int n, Rng& rng) {
  std::vector<TownParcel> out;
  int blocks = (n + 2 * kPerRow - 1) / (2 * kPerRow);
  int cols = std::max(1, int(std::ceil(std::sqrt(double(blocks)))));
  for (int b = 0; b < blocks; ++b) {
    double s0 = (b % cols) * (kBlockWidth + kStreet), t0 = (b / cols) * (2 * kMaxDepth + kStreet);
    double depth[2] = {rng.uniform(26, kMaxDepth), rng.uniform(26, kMaxDepth)};
    for (int row = 0; row < 2; ++row) {
      double w[kPerRow], sum = 0;
      for (double& x : w) sum += (x = rng.uniform(0.85, 1.15));
      double s = s0;
      double ta = row == 0 ? t0 : t0 + depth[0], tb = ta + depth[row];
      for (int k = 0; k < kPerRow && int(out.size()) < n; ++k) {
        double ds = kBlockWidth * w[k] / sum;
        out.push_back({{s, s + ds, ta, tb}, row == 1});
        s += ds;
      }
    }
  }
  return out;
}

// Which layout each parcel gets; a row of attached houses spans 2-3 parcels of one
// block side. Every layout appears within the first 10 parcels. A curved town
// cycles through the curved layouts and a gable house, the planar control; a
// town of curved plans through a round tower, an apsed hall and a gable.
std::vector<std::pair<SampleLayout, int>> assign_layouts(int n, const SampleOptions& opt) {
  static const SampleLayout planar[] = {SampleLayout::Gable,    SampleLayout::Hip,
                                        SampleLayout::CrossGable, SampleLayout::Shed,
                                        SampleLayout::Flat,     SampleLayout::TwoLevel,
                                        SampleLayout::RowHouse, SampleLayout::Empty};
  static const SampleLayout round[] = {SampleLayout::Vault,       SampleLayout::Dome,
                                       SampleLayout::GroundVault, SampleLayout::Cone,
                                       SampleLayout::DomeOnFlat,  SampleLayout::ShallowDome,
                                       SampleLayout::OnionDome,   SampleLayout::Gable,
                                       SampleLayout::Saddle,      SampleLayout::Wave};
  static const SampleLayout plans[] = {SampleLayout::RoundTower, SampleLayout::ApsedHall, SampleLayout::Gable};
  const SampleLayout* cycle = opt.curved_plans ? plans : opt.curved ? round : planar;
  const int kinds = opt.curved_plans ? int(std::size(plans))
                    : opt.curved     ? int(std::size(round))
                                     : int(std::size(planar));
  std::vector<std::pair<SampleLayout, int>> out;  // (layout, houses in the row starting here)
  int slot = 0, rows = 0;
  for (int i = 0; i < n;) {
    SampleLayout l = cycle[slot % kinds];
    int left_in_side = std::min(kPerRow - i % kPerRow, n - i);
    if (l == SampleLayout::RowHouse) {
      int m = rows % 2 == 0 ? 3 : 2;
      if (left_in_side < m) m = 2;
      if (left_in_side < m) {  // no room on this block side: a gable now, the row later
        out.push_back({SampleLayout::Gable, 1});
        ++i;
        continue;
      }
      for (int k = 0; k < m; ++k) out.push_back({l, k == 0 ? m : 0});
      i += m;
      ++rows;
    } else {
      out.push_back({l, 1});
      ++i;
    }
    ++slot;
  }
  return out;
}

// Sizes of the curved layouts (no overhang: the roof meets the walls).
void curved_params(BuildingParams& p, Rng& r) {
  p.overhang = 0;
  p.eave_height = r.uniform(3.5, 6.5);
  const double d = r.uniform(8, 12);  // round ones: the drum's diameter
  switch (p.layout) {
    case SampleLayout::Vault:
      p.length = r.uniform(12, 18), p.width = r.uniform(8, 11), p.rise = p.width * r.uniform(0.2, 0.5);
      break;
    case SampleLayout::GroundVault:
      p.length = r.uniform(14, 20), p.width = r.uniform(9, 12), p.eave_height = 0, p.rise = p.width / 2;
      break;
    case SampleLayout::Dome: p.length = p.width = d, p.rise = d / 2 * r.uniform(0.7, 1.0); break;
    case SampleLayout::ShallowDome:
      p.length = p.width = d + 2, p.rise = (d + 2) / 2 * r.uniform(0.2, 0.35);
      break;
    case SampleLayout::Cone: p.length = p.width = d - 2, p.rise = (d - 2) / 2 * r.uniform(0.7, 1.5); break;
    case SampleLayout::OnionDome: p.length = p.width = d - 2, p.rise = (d - 2) * r.uniform(1.0, 1.4); break;
    case SampleLayout::DomeOnFlat:
      p.length = p.width = r.uniform(12, 16), p.dome_radius = p.length * r.uniform(0.25, 0.35);
      p.rise = p.dome_radius * r.uniform(0.7, 1.0);
      break;
    case SampleLayout::Saddle:
      p.length = r.uniform(12, 18), p.width = r.uniform(9, 13), p.rise = r.uniform(2, 4);
      break;
    case SampleLayout::Wave:
      p.length = r.uniform(14, 20), p.width = r.uniform(9, 12), p.rise = r.uniform(1.5, 3);
      break;
    case SampleLayout::RoundTower: p.length = p.width = d, p.eave_height = r.uniform(6, 12); break;
    case SampleLayout::ApsedHall: p.length = r.uniform(14, 20), p.width = r.uniform(8, 12); break;
    default: break;
  }
}

BuildingParams random_params(SampleLayout l, Rng& r) {
  BuildingParams p;
  p.layout = l;
  p.overhang = r.uniform(0.3, 0.8);
  p.pitch_deg = r.uniform(22, 40);
  p.eave_height = r.chance(0.5) ? r.uniform(3.0, 3.4) : r.uniform(6.0, 6.6);
  p.length = r.uniform(10, 15);
  p.width = r.uniform(7, 9.5);
  switch (l) {
    case SampleLayout::Shed:
      p.length = r.uniform(8, 12), p.width = r.uniform(6, 8), p.pitch_deg = r.uniform(8, 15);
      p.eave_height = r.uniform(3.0, 3.5);
      break;
    case SampleLayout::Flat: p.eave_height = r.uniform(3.0, 7.0); break;
    case SampleLayout::CrossGable:
      p.length = r.uniform(12, 16), p.width = r.uniform(6.5, 8.5), p.wing_length = r.uniform(3.5, 6);
      break;
    case SampleLayout::TwoLevel:
      p.length = r.uniform(9, 12), p.width = r.uniform(7, 9), p.eave_height = r.uniform(5.8, 6.5);
      p.annex_length = r.uniform(3, 5), p.annex_inset = r.uniform(0.5, 1.5);
      p.annex_height = r.uniform(2.8, 3.4);
      p.annex_pitch_deg = r.chance(0.5) ? 0.0 : r.uniform(5, 10);
      break;
    default: break;
  }
  if (is_curved(l)) curved_params(p, r);
  return p;
}

void scale_lengths(BuildingParams& p, double s) {
  for (double* x : {&p.length, &p.width, &p.wing_length, &p.annex_length, &p.annex_inset, &p.rise, &p.dome_radius})
    *x *= s;
}


Rect bbox(const Group& g, bool regions) {
  Rect b{1e300, -1e300, 1e300, -1e300};
  for (const auto& B : g.blocks) {
    const Rect& r = regions ? B.region : B.footprint;
    b = {std::min(b.u0, r.u0), std::max(b.u1, r.u1), std::min(b.v0, r.v0), std::max(b.v1, r.v1)};
  }
  return b;
}

// The footprint's (regions: the roof's) box in the building frame.
Rect plan_box(const BuildingParams& p, bool regions) {
  if (is_curved(p.layout)) {
    const Ring2 f = make_curved_building(p).footprint;
    Rect b{1e300, -1e300, 1e300, -1e300};
    for (const Vec2& q : f) b = {std::min(b.u0, q.x()), std::max(b.u1, q.x()), std::min(b.v0, q.y()), std::max(b.v1, q.y())};
    if (regions && p.layout == SampleLayout::OnionDome) {  // the bulge reaches past the drum
      const double grow = 0.1 * (b.u1 - b.u0);
      b = {b.u0 - grow, b.u1 + grow, b.v0 - grow, b.v1 + grow};
    }
    return b;
  }
  return bbox(build_group(p), regions);
}

// A detached building: arbitrary rotation, shrunk until it fits its parcel with
// a 1 m margin, placed off-centre by chance. town_angle rotates town -> local.
Placement place_detached(BuildingParams& p, const Rect& parcel, double town_angle, Rng& r) {
  double th = r.uniform(0, kPi);
  double c = std::abs(std::cos(th)), s = std::abs(std::sin(th));
  Rect f = plan_box(p, false);
  double du = f.u1 - f.u0, dv = f.v1 - f.v0, oo = 2 * p.overhang * (c + s);
  double aw = parcel.u1 - parcel.u0 - 2, ad = parcel.v1 - parcel.v0 - 2;
  double k = std::min({1.0, (aw - oo) / (du * c + dv * s), (ad - oo) / (du * s + dv * c)});
  if (k < 1) scale_lengths(p, k * 0.999);
  Rect rg = plan_box(p, true);
  double ru = rg.u1 - rg.u0, rv = rg.v1 - rg.v0;
  double ex = ru * c + rv * s, ey = ru * s + rv * c;
  Vec2 mid((parcel.u0 + parcel.u1) / 2, (parcel.v0 + parcel.v1) / 2);
  mid += Vec2(r.uniform(-0.5, 0.5) * std::max(0.0, aw - ex), r.uniform(-0.5, 0.5) * std::max(0.0, ad - ey));
  Vec2 rc((rg.u0 + rg.u1) / 2, (rg.v0 + rg.v1) / 2);
  Placement town{mid, th};
  Vec2 origin_town = mid - (town.to_local(rc) - mid);  // group origin in the town frame
  Placement toloc{Vec2::Zero(), town_angle};
  return {toloc.to_local(origin_town), th + town_angle};
}

// Attached houses on parcels [first, first+m): party walls on the parcel lines.
Placement place_row(BuildingParams& p, const std::vector<TownParcel>& tp, int first, int m,
                    double town_angle, Rng& r) {
  p.layout = SampleLayout::RowHouse;
  p.width = r.uniform(8, 10);
  double margin = p.overhang + r.uniform(0.6, 1.5);
  double s_start = tp[first].rect.u0 + margin, s_end = tp[first + m - 1].rect.u1 - margin;
  p.house_widths.clear();
  for (int k = 0; k < m; ++k) {
    double a = k == 0 ? s_start : tp[first + k].rect.u0;
    double b = k == m - 1 ? s_end : tp[first + k].rect.u1;
    p.house_widths.push_back(b - a);
  }
  p.length = s_end - s_start;
  const Rect& pr = tp[first].rect;
  double setback = r.uniform(2.5, 5);
  double v0 = tp[first].north_row ? pr.v1 - setback - p.width : pr.v0 + setback;
  Placement toloc{Vec2::Zero(), town_angle};
  return {toloc.to_local(Vec2(s_start, v0)), town_angle};
}

// Moves the ground floor (every vertex at z = 0, group frame) to z = dz:
// ground faces and wall feet follow, the roof stays. Element areas are
// measured afterwards by transform().
void move_floor(TruthBuilding& tb, double dz) {
  if (dz == 0) return;
  auto shift = [&](Face& f) {
    for (auto& p : f.ring)
      if (p.z() == 0) p.z() = dz;
  };
  Building& m = tb.model;
  for (auto& e : m.elements)
    for (auto& f : e.faces) shift(f);
  for (auto& f : m.solid) shift(f);
  m.eave_height -= dz;
  m.ridge_height -= dz;
  tb.wall_top_height -= dz;
  m.volume = shell_volume(m.solid);
}

Vec3 place3(const Placement& pl, const Vec3& q, double dz) {
  Vec2 xy = pl.to_local(q.head<2>());
  return {xy.x(), xy.y(), q.z() + dz};
}

void transform(TruthBuilding& tb, const Placement& pl, double dz) {
  auto tf = [&](Face& f) {
    for (auto& p : f.ring) p = place3(pl, p, dz);
  };
  for (auto& e : tb.model.elements) {
    for (auto& f : e.faces) tf(f);
    const double exact_area = e.area, exact_plan = e.plan_area;
    measure(e);
    if (tb.exact_areas) e.area = exact_area, e.plan_area = exact_plan;
  }
  for (auto& f : tb.model.solid) tf(f);
  for (auto& p : tb.footprint) p = pl.to_local(p);
  tb.model.terrain_z = dz;
}

Dtm make_dtm(const std::vector<Parcel>& parcels, const LocalFrame& frame, const Terrain& terrain,
             const std::string& wkt) {
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (const auto& p : parcels)
    for (const auto& v : p.shape.front().outer)
      x0 = std::min(x0, v.x()), x1 = std::max(x1, v.x()), y0 = std::min(y0, v.y()), y1 = std::max(y1, v.y());
  const double margin = 15;
  double wx0 = std::floor(x0 - margin), wx1 = std::ceil(x1 + margin);
  double wy0 = std::floor(y0 - margin), wy1 = std::ceil(y1 + margin);
  Dtm d;
  d.crs_wkt = wkt;
  d.source = "sample";
  d.nx = int(wx1 - wx0), d.ny = int(wy1 - wy0);
  d.x0 = wx0 + 0.5, d.y0 = wy1 - 0.5, d.dx = 1, d.dy = -1;
  d.z.resize(size_t(d.nx) * d.ny);
  for (int j = 0; j < d.ny; ++j)
    for (int i = 0; i < d.nx; ++i) {
      Vec2 l = frame.to_local(Vec2(d.x0 + i, d.y0 - j));
      d.z[size_t(j) * d.nx + i] = float(terrain(l.x(), l.y()));
    }
  return d;
}

// Mean DTM value over the cells whose centres fall inside (building frame),
// world z; marks those cells NoData. `corners` bound the footprint; with no
// cell inside, the height at the first corner.
template <class Inside>
double ground_level_in(const std::vector<Vec2>& corners, Inside inside, const Placement& pl, const LocalFrame& frame,
                       const Dtm& d, std::vector<std::uint8_t>& nodata) {
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (const auto& q : corners) {
    Vec2 w = frame.to_world(pl.to_local(q));
    x0 = std::min(x0, w.x()), x1 = std::max(x1, w.x()), y0 = std::min(y0, w.y()), y1 = std::max(y1, w.y());
  }
  int i0 = std::max(0, int(std::floor(x0 - d.x0))), i1 = std::min(d.nx - 1, int(std::ceil(x1 - d.x0)));
  int j0 = std::max(0, int(std::floor(d.y0 - y1))), j1 = std::min(d.ny - 1, int(std::ceil(d.y0 - y0)));
  double sum = 0;
  long n = 0;
  for (int j = j0; j <= j1; ++j)
    for (int i = i0; i <= i1; ++i) {
      if (!inside(pl.to_group(frame.to_local(Vec2(d.x0 + i, d.y0 - j))))) continue;
      size_t idx = size_t(j) * d.nx + i;
      sum += d.z[idx];
      ++n;
      nodata[idx] = 1;
    }
  if (n > 0) return sum / n;
  Vec2 c = frame.to_world(pl.to_local(corners.front()));
  return d.height_at(c.x(), c.y());
}

// The same over the footprints of the group's blocks owned by `owner` (-1: all blocks).
double ground_level(const Group& g, const Placement& pl, const LocalFrame& frame, const Dtm& d,
                    std::vector<std::uint8_t>& nodata, int owner = -1) {
  std::vector<Vec2> corners;
  for (const auto& B : g.blocks)
    for (const auto& q : B.footprint.ring()) corners.push_back(q);
  auto inside = [&](const Vec2& q) {
    for (const auto& B : g.blocks)
      if ((owner < 0 || B.owner == owner) && B.footprint.contains(q)) return true;
    return false;
  };
  return ground_level_in(corners, inside, pl, frame, d, nodata);
}

// The same under a convex counter-clockwise footprint.
double ground_level(const Ring2& footprint, const Placement& pl, const LocalFrame& frame, const Dtm& d,
                    std::vector<std::uint8_t>& nodata) {
  auto inside = [&](const Vec2& q) {
    for (size_t i = 0, n = footprint.size(); i < n; ++i) {
      const Vec2 a = footprint[i], e = footprint[(i + 1) % n] - a;
      if (e.x() * (q - a).y() - e.y() * (q - a).x() < 0) return false;
    }
    return true;
  };
  return ground_level_in(footprint, inside, pl, frame, d, nodata);
}

std::string nib(int k) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "102805030%05d", k + 1);
  return buf;
}

std::string wkt_of(int epsg) {
  OGRSpatialReference srs;
  if (srs.importFromEPSG(epsg) != OGRERR_NONE)
    throw std::runtime_error("sample: unknown EPSG code " + std::to_string(epsg));
  char* w = nullptr;
  srs.exportToWkt(&w);
  std::string s = w ? w : "";
  CPLFree(w);
  return s;
}

}  // namespace

SampleTown make_sample_town(const SampleOptions& opt) {
  if (opt.parcels < 1) throw std::invalid_argument("sample: --parcels must be at least 1");
  SampleTown town;
  town.seed = opt.seed;
  town.epsg = opt.epsg;
  town.crs_wkt = wkt_of(opt.epsg);
  Rng rng(opt.seed);
  const Terrain terrain(rng);
  const double town_angle = rng.uniform(-25, 25) * kPi / 180;
  town.frame.origin = Vec3(opt.origin_easting, opt.origin_northing, std::round(terrain.z0));
  const auto tp = lay_out_parcels(opt.parcels, rng);
  const auto layouts = assign_layouts(opt.parcels, opt);
  Placement toloc{Vec2::Zero(), town_angle};
  for (size_t i = 0; i < tp.size(); ++i) {
    Parcel p;
    p.index = int(i);
    p.id = nib(int(i));
    p.right_type = rng.chance(0.7) ? "Hak Milik" : "Hak Guna Bangunan";
    Polygon2 poly;
    for (const auto& q : tp[i].rect.ring()) poly.outer.push_back(town.frame.to_world(toloc.to_local(q)));
    p.shape = {poly};
    // Certificates carry a rounded, slightly different area (older survey).
    p.official_area = std::round(area(p.shape) * (1 + 0.01 * rng.normal()));
    town.parcels.push_back(std::move(p));
    town.layouts.push_back(layouts[i].first);
  }
  town.dtm = make_dtm(town.parcels, town.frame, terrain, town.crs_wkt);
  town.dtm_nodata.assign(town.dtm.z.size(), 0);
  town.truth.resize(tp.size());
  for (size_t i = 0; i < tp.size(); ++i) {
    auto [layout, houses] = layouts[i];
    if (layout == SampleLayout::Empty || houses == 0) continue;
    BuildingParams bp = random_params(layout, rng);
    Placement pl = layout == SampleLayout::RowHouse
                       ? place_row(bp, tp, int(i), houses, town_angle, rng)
                       : place_detached(bp, tp[i].rect, town_angle, rng);
    if (is_curved(layout)) {
      TruthBuilding tb = make_curved_building(bp);
      const double level = ground_level(tb.footprint, pl, town.frame, town.dtm, town.dtm_nodata);
      tb.ground_level = level;
      transform(tb, pl, level - town.frame.origin.z());
      tb.model.id = nib(int(i)) + "_b0";
      town.truth[i].push_back(std::move(tb));
      continue;
    }
    Group g = build_group(bp);
    double level = ground_level(g, pl, town.frame, town.dtm, town.dtm_nodata);
    auto buildings = assemble(g);
    for (size_t k = 0; k < buildings.size(); ++k) {
      TruthBuilding& tb = buildings[k];
      tb.params = bp;
      // Attached houses share one roof but each floor follows its own terrain.
      double own = buildings.size() > 1
                       ? ground_level(g, pl, town.frame, town.dtm, town.dtm_nodata, int(k))
                       : level;
      move_floor(tb, own - level);
      tb.ground_level = own;
      transform(tb, pl, level - town.frame.origin.z());
      tb.model.terrain_z = own - town.frame.origin.z();
      tb.model.id = nib(int(i + k)) + "_b0";
      for (auto& a : tb.attached_to) a = nib(int(i) + std::stoi(a.substr(1))) + "_b0";
      town.truth[i + k].push_back(std::move(tb));
    }
    if (opt.progress && (i % 100 == 99 || i + 1 == tp.size()))
      opt.progress("buildings", int(i + 1), int(tp.size()));
  }
  long cells = 0;
  for (auto v : town.dtm_nodata) cells += v;
  town.dtm.nodata_share = town.dtm.z.empty() ? 0 : double(cells) / town.dtm.z.size();
  town.cloud.source = "sample";
  town.cloud.crs_wkt = town.crs_wkt;
  if (opt.with_points) sample_points(town, opt, rng, tp, town_angle);
  if (opt.with_points && opt.trees_per_parcel > 0) sample_trees(town, opt, tp, town_angle);
  if (opt.with_points && opt.sheds_per_parcel > 0) sample_sheds(town, opt, tp, town_angle);
  return town;
}

}  // namespace c3d
