// Curved surfaces found in roof points: the curved sample town's vaults,
// domes and cones with their radii, and no curved surface on planar roofs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <random>
#include <nlohmann/json.hpp>

#include "core/geometry/geometry.h"
#include "core/primitives/curved_building.h"
#include "core/primitives/exact_shape.h"
#include "core/primitives/primitives.h"
#include "core/primitives/revolved_roof.h"
#include "core/reconstruct/measure/measure.h"
#include "core/synthetic/sample_town.h"
#include "tests/test_support.h"

using namespace c3d;

namespace {

// Each parcel's roof-class points over its parcel, local coordinates.
std::vector<std::vector<Vec3>> roof_points_by_parcel(const SampleTown& town) {
  std::vector<std::vector<Vec3>> out(town.parcels.size());
  for (size_t k = 0; k < town.cloud.points.size(); ++k) {
    if (town.cloud.classes[k] != 6) continue;
    const Vec3& w = town.cloud.points[k];
    for (size_t i = 0; i < town.parcels.size(); ++i)
      if (in_ring_plan(town.parcels[i].shape.front().outer, Vec2(w.head<2>()))) {
        out[i].push_back(w - town.frame.origin);
        break;
      }
  }
  return out;
}

SampleTown town(bool curved, double density, int parcels) {
  SampleOptions opt;
  opt.curved = curved;
  opt.parcels = parcels;
  opt.seed = 7;
  opt.roof_density = density;
  return make_sample_town(opt);
}

// The rim radius and rise of a truth building's curved roof (sample_town.h).
double sphere_radius(const BuildingParams& p) {
  const double r = p.layout == SampleLayout::DomeOnFlat ? p.dome_radius : std::min(p.length, p.width) / 2;
  return (r * r + p.rise * p.rise) / (2 * p.rise);
}

}  // namespace

TEST(Primitives, CurvedTownGivesEachRoofItsSurface) {
  for (double density : {40.0, 10.0}) {
    const SampleTown t = town(true, density, 8);
    const auto points = roof_points_by_parcel(t);
    for (size_t i = 0; i < t.parcels.size(); ++i) {
      if (t.truth[i].empty()) continue;
      const TruthBuilding& tb = t.truth[i].front();
      SCOPED_TRACE(tb.roof_type + " at " + std::to_string(int(density)) + " pts/m2");
      const PrimitiveFit fit = find_curved_surfaces(points[i], {});
      std::map<PrimitiveKind, int> n;
      for (const Primitive& p : fit.curved) ++n[p.kind];
      const BuildingParams& bp = tb.params;
      switch (bp.layout) {
        case SampleLayout::Vault:
        case SampleLayout::GroundVault: {
          ASSERT_EQ(fit.curved.size(), 1u);
          EXPECT_EQ(fit.curved[0].kind, PrimitiveKind::Cylinder);
          const double R = (bp.width * bp.width / 4 + bp.rise * bp.rise) / (2 * bp.rise);
          EXPECT_NEAR(fit.curved[0].radius / R, 1, 0.02);
          break;
        }
        case SampleLayout::Dome:
        case SampleLayout::ShallowDome:
        case SampleLayout::DomeOnFlat:
          ASSERT_EQ(fit.curved.size(), 1u);
          EXPECT_EQ(fit.curved[0].kind, PrimitiveKind::Sphere);
          EXPECT_NEAR(fit.curved[0].radius / sphere_radius(bp), 1, 0.02);
          break;
        case SampleLayout::Cone: {
          ASSERT_EQ(fit.curved.size(), 1u);
          EXPECT_EQ(fit.curved[0].kind, PrimitiveKind::Cone);
          const double half = std::atan2(std::min(bp.length, bp.width) / 2, bp.rise);
          EXPECT_NEAR(fit.curved[0].angle, half, 0.02);
          break;
        }
        case SampleLayout::Gable: EXPECT_TRUE(fit.curved.empty()) << fit.curved.front().describe(); break;
        default: break;  // the onion is free-form: no single primitive holds it
      }
      if (bp.layout != SampleLayout::OnionDome)
        for (const Primitive& p : fit.curved) EXPECT_LT(p.rmse, 1.5 * fit.noise) << p.describe();
    }
  }
}

TEST(Primitives, PlanarTownHasNoCurvedSurface) {
  const SampleTown t = town(false, 40, 24);
  const auto points = roof_points_by_parcel(t);
  for (size_t i = 0; i < points.size(); ++i) {
    const PrimitiveFit fit = find_curved_surfaces(points[i], {});
    EXPECT_TRUE(fit.curved.empty()) << t.parcels[i].id << ": " << fit.curved.front().describe();
  }
}

TEST(Primitives, NoiseEstimateFollowsTheScan) {
  for (double noise : {0.01, 0.03, 0.06}) {
    SampleOptions opt;
    opt.parcels = 4;
    opt.roof_noise = noise;
    opt.outlier_share = 0;
    opt.clutter_share = 0;
    const SampleTown t = make_sample_town(opt);
    const auto points = roof_points_by_parcel(t);
    EXPECT_NEAR(estimate_noise(points[0]) / noise, 1, 0.25) << noise;
  }
}

namespace {

// Points evenly over a plan region (a grid of `step`), lifted to z(x, y).
template <class Inside, class Height>
std::vector<Vec3> grid_points(double x0, double x1, double y0, double y1, double step, Inside inside, Height z) {
  std::vector<Vec3> out;
  for (double x = x0 + step / 2; x < x1; x += step)
    for (double y = y0 + step / 2; y < y1; y += step)
      if (inside(x, y)) out.push_back({x, y, z(x, y)});
  return out;
}

std::map<ElementType, double> areas(const Building& b) {
  std::map<ElementType, double> out;
  for (const Element& e : b.elements) out[e.type] += e.area;
  return out;
}

}  // namespace

// A sphere of radius 5 centred 4 m up, over a drum of radius 4: a cap of rise
// 2 (area 2 pi R h) on a wall 7 m high; and a half cylinder of radius 5 on
// the ground, 20 m long: a roof of 20 pi R, two half-disc end walls.
TEST(Primitives, CurvedBuildingsStandOnTheirSurfaces) {
  Primitive sphere;
  sphere.kind = PrimitiveKind::Sphere, sphere.point = Vec3(0, 0, 4), sphere.radius = 5;
  CurvedBuildingInput dome;
  dome.roof = sphere, dome.spacing = 0.1;
  dome.roof_points = grid_points(
      -4, 4, -4, 4, 0.1, [](double x, double y) { return x * x + y * y < 16; },
      [](double x, double y) { return 4 + std::sqrt(25 - x * x - y * y); });
  std::optional<Building> b = curved_building(dome);
  ASSERT_TRUE(b);
  measure_building(*b);
  EXPECT_TRUE(b->solid_valid) << b->solid_problem;
  auto a = areas(*b);
  EXPECT_NEAR(a[ElementType::Roof] / (2 * M_PI * 5 * 2), 1, 0.01);
  EXPECT_NEAR(a[ElementType::Wall] / (2 * M_PI * 4 * 7), 1, 0.01);
  EXPECT_NEAR(a[ElementType::Ground] / (M_PI * 16), 1, 0.01);
  EXPECT_NEAR(b->volume / (M_PI * 16 * 7 + M_PI * 4 * (15 - 2) / 3), 1, 0.01);
  for (const Element& e : b->elements) EXPECT_GT(e.sigma_area, 0) << to_string(e.type);

  // Roof points that stop short of the rim (a scan's gap) shrink the drum;
  // the drum's wall points put it back where the wall scan saw it.
  CurvedBuildingInput gap = dome;
  gap.roof_points.erase(std::remove_if(gap.roof_points.begin(), gap.roof_points.end(),
                                       [](const Vec3& q) { return q.head<2>().norm() > 3.6; }),
                        gap.roof_points.end());
  b = curved_building(gap);
  ASSERT_TRUE(b);
  EXPECT_LT(areas(*b)[ElementType::Ground], 0.9 * M_PI * 16);
  // Its drum stands under the rim, which says so: no wall point placed it.
  auto drum = [](const Building& m) {
    return *std::find_if(m.elements.begin(), m.elements.end(), [](const Element& e) { return e.type == ElementType::Wall; });
  };
  EXPECT_EQ(drum(*b).evidence, WallEvidence::Default);
  EXPECT_EQ(drum(*b).support_points, 0);
  for (int i = 0; i < 400; ++i)
    gap.wall_points.push_back({4 * std::cos(i * 0.0157), 4 * std::sin(i * 0.0157), 0.5 + 6.0 * (i % 20) / 20});
  b = curved_building(gap);
  ASSERT_TRUE(b);
  EXPECT_NEAR(areas(*b)[ElementType::Ground] / (M_PI * 16), 1, 0.01);
  EXPECT_EQ(drum(*b).evidence, WallEvidence::Measured);
  EXPECT_EQ(drum(*b).support_points, 400);
  // A wall scan whose points stop 2 m below where the dome meets the drum
  // (7 m) saw no such drum: something unseen stands between (an onion's
  // bulb), and no dome is built on it.
  for (Vec3& q : gap.wall_points) q.z() = 0.5 + 4.0 * (q.z() - 0.5) / 6.0;
  EXPECT_FALSE(curved_building(gap));

  Primitive cylinder;
  cylinder.kind = PrimitiveKind::Cylinder, cylinder.point = Vec3(0, 0, 0), cylinder.axis = Vec3::UnitX(),
  cylinder.radius = 5;
  CurvedBuildingInput hangar;
  hangar.roof = cylinder, hangar.spacing = 0.1;
  hangar.roof_points = grid_points(
      0, 20, -5, 5, 0.1, [](double, double) { return true; },
      [](double, double y) { return std::sqrt(std::max(0.0, 25 - y * y)); });
  b = curved_building(hangar);
  ASSERT_TRUE(b);
  measure_building(*b);
  EXPECT_TRUE(b->solid_valid) << b->solid_problem;
  a = areas(*b);
  EXPECT_NEAR(a[ElementType::Roof] / (20 * M_PI * 5), 1, 0.01);
  EXPECT_NEAR(a[ElementType::Wall] / (M_PI * 25), 1, 0.01);
  int walls = 0;
  for (const Element& e : b->elements) walls += e.type == ElementType::Wall;
  EXPECT_EQ(walls, 2);  // end walls only
  EXPECT_NEAR(b->volume / (20 * M_PI * 25 / 2), 1, 0.01);

  cylinder.axis = Vec3(1, 0, 0.2).normalized();  // a tilted axis is no vault
  hangar.roof = cylinder;
  for (Vec3& q : hangar.roof_points) q.z() += 0.2 * q.x();
  EXPECT_FALSE(curved_building(hangar));
}

// A 20 x 12 m hall, flat roof at 5 m, carrying a cap of a sphere of radius
// 5 centred at 2 m (it meets the roof on a circle of radius 4, rise 2) and a
// cone of half-angle 45 deg, apex at 9 m, on a 2 m drum of radius 2: the
// flat roof is the hall's plan less the two discs, the cap 2 pi R h, the
// cone pi r s; the drum's wall stands on the roof. A roof outline 0.5 m past
// the walls adds the overhang to the roof and makes the outer ceiling.
TEST(Primitives, DomesAndConesStandOnAFlatRoof) {
  Primitive sphere, cone;
  sphere.kind = PrimitiveKind::Sphere, sphere.point = Vec3(5, 6, 2), sphere.radius = 5;
  cone.kind = PrimitiveKind::Cone, cone.point = Vec3(15, 6, 9), cone.axis = -Vec3::UnitZ(), cone.angle = M_PI / 4;
  DomedRoofInput in;
  in.footprint = {{{0, 0}, {20, 0}, {20, 12}, {0, 12}}, {}};
  in.ground_z = 0, in.roof_z = 5, in.spacing = 0.1;
  in.caps = {sphere, cone};
  in.cap_points = {grid_points(
                       1, 9, 2, 10, 0.1, [](double x, double y) { return std::hypot(x - 5, y - 6) < 4; },
                       [](double x, double y) { return 2 + std::sqrt(25 - std::pow(x - 5, 2) - std::pow(y - 6, 2)); }),
                   grid_points(
                       13, 17, 4, 8, 0.05, [](double x, double y) { return std::hypot(x - 15, y - 6) < 2; },
                       [](double x, double y) { return 9 - std::hypot(x - 15, y - 6); })};
  std::optional<Building> b = domed_roof_building(in);
  ASSERT_TRUE(b);
  measure_building(*b);
  EXPECT_TRUE(b->solid_valid) << b->solid_problem;
  auto a = areas(*b);
  const double flat = 240 - M_PI * 16 - M_PI * 4, cap = 2 * M_PI * 5 * 2, cone_roof = M_PI * 2 * 2 * std::sqrt(2.0);
  EXPECT_NEAR(a[ElementType::Roof] / (flat + cap + cone_roof), 1, 0.005);
  EXPECT_NEAR(b->elements[1].area / cap, 1, 0.005);
  EXPECT_NEAR(b->elements[2].area / cone_roof, 1, 0.005);
  EXPECT_NEAR(a[ElementType::Wall] / (64 * 5 + 2 * M_PI * 2 * 2), 1, 0.005);
  EXPECT_NEAR(a[ElementType::Ground] / 240, 1, 1e-9);
  const double volume = 240 * 5 + M_PI * 4 * (15 - 2) / 3 + M_PI * 4 * 2 + M_PI * 4 * 2 / 3;
  EXPECT_NEAR(b->volume / volume, 1, 0.005);
  // Points exactly on the cap leave its fit no error; the cone's drum rim is
  // read from its points' quantile.
  EXPECT_GT(b->elements[2].sigma_area, 0);

  in.roof_outline = {{{-0.5, -0.5}, {20.5, -0.5}, {20.5, 12.5}, {-0.5, 12.5}}, {}};
  b = domed_roof_building(in);
  ASSERT_TRUE(b);
  measure_building(*b);
  EXPECT_TRUE(b->solid_valid) << b->solid_problem;
  EXPECT_NEAR(areas(*b)[ElementType::Roof] - a[ElementType::Roof], 21 * 13 - 240, 0.01);
  EXPECT_NEAR(areas(*b)[ElementType::OuterCeiling], 21 * 13 - 240, 0.01);
  EXPECT_NEAR(b->volume / volume, 1, 0.005);

  in.caps[1].point.x() = 18.5;  // a cone over the hall's edge stands on no roof
  for (Vec3& q : in.cap_points[1]) q.x() += 3.5;
  EXPECT_FALSE(domed_roof_building(in));
}

// An onion dome on a drum of radius 4 and height 6: profile rho(t) = r (1 -
// t)^1.5 (1 + 2.5 t), z = 6 + 10 t, widest (1.078 r) at t = 0.16. Seen from
// the air (points on the part above the widest ring, 3 cm noise), with the
// drum's wall points, the surface of revolution gives the roof (its unseen
// underside a straight band, its needle tip above the highest points) and
// the drum within 2 % of the exact figures.
TEST(Primitives, OnionDomeIsASurfaceOfRevolution) {
  const double r = 4, H = 6, h = 10;
  auto rho = [&](double t) { return r * std::pow(1 - t, 1.5) * (1 + 2.5 * t); };
  double roof = 0, volume = 0;  // exact by fine frusta
  for (int i = 0; i < 20000; ++i) {
    const double a = rho(i / 20000.0), b = rho((i + 1) / 20000.0), dz = h / 20000;
    roof += M_PI * (a + b) * std::hypot(a - b, dz);
    volume += M_PI * dz * (a * a + a * b + b * b) / 3;
  }
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0, 0.03);
  std::vector<Vec3> pts;
  for (double x = -4.4; x <= 4.4; x += 0.15)
    for (double y = -4.4; y <= 4.4; y += 0.15) {
      const double p = std::hypot(x, y);
      if (p > rho(0.16)) continue;
      double lo = 0.16, hi = 1;  // the visible part: rho falls from the widest ring to the tip
      for (int k = 0; k < 60; ++k) (rho((lo + hi) / 2) > p ? lo : hi) = (lo + hi) / 2;
      pts.push_back({x + 20, y + 30, H + h * lo + noise(rng)});
    }
  const std::optional<RevolvedRoof> fit = fit_revolved_roof(pts, Vec2(20.3, 29.8), 0.03);
  ASSERT_TRUE(fit);
  EXPECT_NEAR(fit->axis.x(), 20, 0.05);
  EXPECT_NEAR(fit->axis.y(), 30, 0.05);
  EXPECT_NEAR(fit->profile.front().x(), rho(0.16), 0.1);
  EXPECT_NEAR(fit->profile.back().y(), H + h, 0.5);  // a cusp: the highest points lie beside it
  EXPECT_LT(fit->rmse, 0.045);
  EXPECT_TRUE(fit->may_overhang());
  for (size_t k = 1; k < fit->profile.size(); ++k)  // a height over the plan, as seen from the air: no fold
    EXPECT_LE(fit->profile[k].x(), fit->profile[k - 1].x()) << k;
  RevolvedBuildingInput in;
  in.roof = *fit;
  in.spacing = 0.15;
  EXPECT_FALSE(drum_seen(in));
  std::uniform_real_distribution<double> up(0.3, H);  // a wall scan's points, spread up the drum
  for (int i = 0; i < 600; ++i)
    in.wall_points.push_back({20 + r * std::cos(i * 0.0105), 30 + r * std::sin(i * 0.0105), up(rng)});
  EXPECT_TRUE(drum_seen(in));
  std::optional<Building> b = revolved_roof_building(in);
  ASSERT_TRUE(b);
  measure_building(*b);
  EXPECT_TRUE(b->solid_valid) << b->solid_problem;
  auto a = areas(*b);
  EXPECT_NEAR(a[ElementType::Roof] / roof, 1, 0.02);
  EXPECT_NEAR(a[ElementType::Wall] / (2 * M_PI * r * H), 1, 0.02);
  EXPECT_NEAR(a[ElementType::Ground] / (M_PI * r * r), 1, 0.02);
  EXPECT_NEAR(b->volume / (M_PI * r * r * H + volume), 1, 0.02);
  // Its exact shape (the drum, the profile's B-spline turned about the axis)
  // is the solid its faces tessellate, to their chords.
  const double exact = exact_volume(b->exact);
  EXPECT_NEAR(exact / b->volume, 1, 0.005);
  EXPECT_NEAR(exact / (M_PI * r * r * H + volume), 1, 0.02);
}

// From the air an onion's bulb shows little plan about its widest ring: at
// 10 pts/m2 a bulb's lowest profile step could hold too few of its 300-odd
// points (here seed 11's second onion), the fit gave up, and in the batch
// (seed 5) a cone took the roof, `ok` with 49 % of its area. Wider steps fit.
TEST(Primitives, SparseOnionKeepsItsSurfaceOfRevolution) {
  for (unsigned seed : {5u, 7u, 11u}) {
    SampleOptions opt;
    opt.curved = true, opt.parcels = 24, opt.seed = seed, opt.roof_density = 10;
    const SampleTown t = make_sample_town(opt);
    const auto points = roof_points_by_parcel(t);
    for (size_t i = 0; i < t.parcels.size(); ++i) {
      if (t.truth[i].empty() || t.truth[i].front().params.layout != SampleLayout::OnionDome) continue;
      SCOPED_TRACE("seed " + std::to_string(seed) + ", parcel " + t.parcels[i].id);
      Vec2 centre = Vec2::Zero();
      for (const Vec3& q : points[i]) centre += q.head<2>() / double(points[i].size());
      const std::optional<RevolvedRoof> fit = fit_revolved_roof(points[i], centre + Vec2(0.2, -0.1), 0.03);
      ASSERT_TRUE(fit) << points[i].size() << " points";
      EXPECT_LT(fit->rmse, 0.045);
    }
  }
}

namespace {

// The optimizer ran on a curved building (on by default): the dense mesh of
// its points, snapped onto its exact surfaces, lies at least 50 % nearer them
// (Chamfer), and within the scan's noise (3 cm) of its points.
void expect_refined(const nlohmann::json& r, const std::string& layout) {
  ASSERT_TRUE(r.is_object()) << layout << ": not refined";
  EXPECT_GT(r["triangles"].get<int>(), 500) << layout;
  EXPECT_GT(r["snapped_share"].get<double>(), 0.8) << layout;
  const double before = r["chamfer_to_exact_shape_m"]["before"], after = r["chamfer_to_exact_shape_m"]["after"];
  EXPECT_LE(after, 0.5 * before) << layout << ": Chamfer " << before << " -> " << after;
  EXPECT_LT(r["cloud_to_mesh_m"]["after"].get<double>(), 0.035) << layout;
}

// The batch of `dir` rerun on one parcel alone: its buildings' figures are
// the same to the last bit.
void expect_alone_as_in_town(const std::string& dir, const std::string& parcel) {
  std::string log;
  ASSERT_EQ(test::run_cli("batch --quiet --formats cityjson --cloud " + dir + "/town/cloud.las --parcels " + dir +
                              "/town/parcels.gpkg --dtm " + dir + "/town/dtm.tif --out " + dir +
                              "/alone --where \"NIB IN ('" + parcel + "')\"",
                          &log),
            0)
      << log;
  auto buildings_of = [&](const std::string& out) {
    const auto summary = nlohmann::json::parse(std::ifstream(dir + "/" + out + "/summary.json"));
    for (const auto& p : summary["parcels"])
      if (p["parcel_id"] == parcel) return std::make_pair(p["status"].get<std::string>(), p["buildings"]);
    return std::make_pair(std::string("missing"), nlohmann::json());
  };
  const auto [status, alone] = buildings_of("alone");
  const auto [town_status, in_town] = buildings_of("out");
  EXPECT_EQ(status, town_status);
  ASSERT_EQ(alone.size(), in_town.size());
  for (size_t b = 0; b < alone.size(); ++b)
    for (const char* key : {"roof_area_m2", "wall_area_m2", "ground_area_m2", "volume_m3"})
      EXPECT_EQ(alone[b][key].get<double>(), in_town[b][key].get<double>()) << parcel << " " << key;
}

}  // namespace

// The batch on a curved town: a building whose roof is one vault, dome or
// cone is modelled on it, `ok`, within the figures of docs/curved.md; one
// where a flat roof carries it (a dome on a flat roof) is modelled as the
// flat roof with the dome on it, `ok`, within the same figures; an onion
// dome on its surface of revolution where the wall scan saw its drum, else
// `suspect` (its underside unknown); a saddle or a wave under its B-spline
// height field. Each curved building's mesh is refined.
// And a parcel modelled alone gets the figures it gets in its town: each is
// modelled in its own frame (its third vault was `suspect` in the whole town,
// `ok` alone, while the batch's frame followed the parcels it held).
TEST(Primitives, BatchModelsCurvedRoofsOnTheirSurfaces) {
  const std::string dir = test::temp_dir("primitives_batch");
  ASSERT_EQ(test::sample_and_batch(dir, "--curved --parcels 24 --seed 11"), "");
  expect_alone_as_in_town(dir, "10280503000021");
  const auto truth = nlohmann::json::parse(std::ifstream(dir + "/town/truth.json"));
  const auto summary = nlohmann::json::parse(std::ifstream(dir + "/out/summary.json"));
  ASSERT_EQ(truth["parcels"].size(), summary["parcels"].size());
  const std::map<std::string, std::string> surface = {
      {"vault", "cylinder"}, {"ground_vault", "cylinder"}, {"dome", "sphere"}, {"shallow_dome", "sphere"},
      {"dome_on_flat", "sphere"}, {"cone", "cone"}, {"onion", "surface of revolution"},
      {"saddle", "B-spline height field"}, {"wave", "B-spline height field"}};
  // What is reached at 40 pts/m2 (docs/curved.md); the targets are
  // 2 % (roof, ground, volume) and 3 % (walls): a near-hemisphere's roof is
  // tied to its rim (2.9 % on one dome).
  const double roof_tol = 0.035, wall_tol = 0.03, ground_tol = 0.02, volume_tol = 0.02;
  for (size_t i = 0; i < truth["parcels"].size(); ++i) {
    const std::string layout = truth["parcels"][i]["layout"], status = summary["parcels"][i]["status"];
    const std::string reason = summary["parcels"][i].value("reason", "");
    if (layout == "gable") {
      EXPECT_EQ(status, "ok") << reason;
      EXPECT_TRUE(summary["parcels"][i]["buildings"][0]["mesh_refinement"].is_null()) << "planes only";
    }
    if (layout == "onion" && status == "suspect") {
      EXPECT_NE(reason.find("no wall point shows the drum"), std::string::npos) << reason;
      continue;
    }
    if (!surface.count(layout)) continue;
    EXPECT_EQ(status, "ok") << layout << ": " << reason;
    const bool free_form = surface.at(layout) == "B-spline height field";
    const std::string how = layout == "dome_on_flat" ? "roof modelled as a flat roof carrying its "
                            : free_form              ? "roof modelled under its "
                                                     : "roof modelled on its ";
    EXPECT_NE(reason.find(how + surface.at(layout)), std::string::npos) << layout << ": " << reason;
    const auto& t = truth["parcels"][i]["buildings"][0];
    ASSERT_EQ(summary["parcels"][i]["buildings"].size(), 1u) << layout;
    const auto& m = summary["parcels"][i]["buildings"][0];
    EXPECT_TRUE(m["solid_valid"].get<bool>()) << layout;
    for (const auto& [key, tol] : std::vector<std::pair<std::string, double>>{
             {"roof_area_m2", roof_tol}, {"wall_area_m2", wall_tol}, {"ground_area_m2", ground_tol},
             {"volume_m3", volume_tol}})
      EXPECT_NEAR(m[key].get<double>() / t[key].get<double>(), 1, tol) << layout << " " << key;
    expect_refined(m["mesh_refinement"], layout);
  }
}

namespace {

// Each onion, saddle and wave of the town at `sample_args`: `ok` within the
// issue's targets (roof and ground 2 %, walls 3 %) or `suspect`, and the
// free-form halls always `ok`.
void expect_sparse_town_right(const std::string& sample_args) {
  SCOPED_TRACE(sample_args);
  const std::string dir = test::temp_dir("primitives_sparse");
  ASSERT_EQ(test::sample_and_batch(dir, sample_args), "");
  const auto truth = nlohmann::json::parse(std::ifstream(dir + "/town/truth.json"));
  const auto summary = nlohmann::json::parse(std::ifstream(dir + "/out/summary.json"));
  ASSERT_EQ(truth["parcels"].size(), summary["parcels"].size());
  std::map<std::string, int> seen;
  for (size_t i = 0; i < truth["parcels"].size(); ++i) {
    const std::string layout = truth["parcels"][i]["layout"];
    if (layout != "onion" && layout != "saddle" && layout != "wave") continue;
    ++seen[layout];
    const std::string status = summary["parcels"][i]["status"], reason = summary["parcels"][i].value("reason", "");
    SCOPED_TRACE(layout + " " + std::to_string(i) + ": " + reason);
    if (status == "suspect" && layout == "onion") continue;
    EXPECT_EQ(status, "ok");
    const auto &model = summary["parcels"][i]["buildings"][0], &exact = truth["parcels"][i]["buildings"][0];
    for (const auto& [figure, target] :
         {std::pair<const char*, double>{"roof_area_m2", 0.02}, {"ground_area_m2", 0.02}, {"wall_area_m2", 0.03}})
      EXPECT_NEAR(model[figure].get<double>() / exact[figure].get<double>(), 1, target) << figure;
  }
  EXPECT_EQ(seen, (std::map<std::string, int>{{"onion", 2}, {"saddle", 2}, {"wave", 2}}));
}

}  // namespace

// At 10 pts/m2 an onion's drum and underside are unseen without wall
// points, a cone may hold most of its roof, and the bulb's widest ring is
// thinly seen: each onion is then either modelled within the figures of
// docs/curved.md or `suspect`, never `ok` on a surface that leaves its
// points materially farther than its profile, nor with its drum standing
// through its bulb (with wall points, one was `ok` with half its roof).
// Saddles and waves stand on their whole roof's outline (the planar
// model's had notches: a saddle's walls were 5 % long).
TEST(Primitives, SparseTownIsOkOnlyWithinTheTargets) {
  for (const std::string walls : {" --wall-density 0", ""})
    expect_sparse_town_right("--curved --parcels 24 --seed 11 --density 10" + walls);
}

// The sigma of each curved element against the scatter of its errors: a dome
// on a drum and a vault springing from the ground (as above), each scanned
// 40 times at 20 points per m2 spread evenly over the plan (as from the air)
// with 3 cm of noise, from a search's surface a few cm off, on a ground level
// read 5 mm off at random (the DTM's error the sigma assumes). A calibrated
// sigma has rms(error / sigma) 1; moving the rim by half a point spacing, as
// before, gave the roofs 0.1-0.2 and the vault's end walls 5.
TEST(Primitives, CurvedSigmaMatchesTheScatterOfItsErrors) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0, 0.03), terrain(0, 0.005);
  std::uniform_real_distribution<double> u(0, 1);
  const double density = 20;
  std::map<std::string, std::vector<double>> z;
  auto record = [&](const std::string& kind, const Building& b, const std::map<ElementType, double>& truth) {
    for (const Element& e : b.elements) {
      ASSERT_GT(e.sigma_area, 0) << kind << " " << to_string(e.type);
      z[kind + " " + to_string(e.type)].push_back((e.area - truth.at(e.type)) / e.sigma_area);
    }
  };
  for (int trial = 0; trial < 40; ++trial) {
    CurvedBuildingInput dome;
    dome.roof.kind = PrimitiveKind::Sphere, dome.roof.point = Vec3(0.02, -0.01, 4.03), dome.roof.radius = 5.02;
    dome.spacing = 1 / std::sqrt(density), dome.ground_z = terrain(rng), dome.ground_sigma = 0.005;
    for (int i = 0; i < int(density * M_PI * 16); ++i) {
      const double r = 4 * std::sqrt(u(rng)), a = 2 * M_PI * u(rng);
      const Vec3 q(r * std::cos(a), r * std::sin(a), 4 + std::sqrt(25 - r * r));
      dome.roof_points.push_back(q + Vec3(noise(rng), noise(rng), noise(rng)));
    }
    std::optional<Building> b = curved_building(dome);
    ASSERT_TRUE(b);
    record("dome", *b, {{ElementType::Roof, 20 * M_PI}, {ElementType::Wall, 56 * M_PI}, {ElementType::Ground, 16 * M_PI}});

    CurvedBuildingInput hangar;
    hangar.roof.kind = PrimitiveKind::Cylinder, hangar.roof.point = Vec3(0, 0.02, -0.03);
    hangar.roof.axis = Vec3::UnitX(), hangar.roof.radius = 5.03;
    hangar.spacing = dome.spacing, hangar.ground_z = terrain(rng), hangar.ground_sigma = 0.005;
    for (int i = 0; i < int(density * 200); ++i) {
      const double x = 20 * u(rng), y = -5 + 10 * u(rng);
      hangar.roof_points.push_back(Vec3(x, y, std::sqrt(25 - y * y)) + Vec3(noise(rng), noise(rng), noise(rng)));
    }
    b = curved_building(hangar);
    ASSERT_TRUE(b);
    record("vault", *b, {{ElementType::Roof, 100 * M_PI}, {ElementType::Wall, 12.5 * M_PI}, {ElementType::Ground, 200}});
  }
  for (const auto& [what, v] : z) {
    double ss = 0;
    for (double x : v) ss += x * x;
    const double rms = std::sqrt(ss / double(v.size()));
    EXPECT_GT(rms, 0.6) << what << ": sigma too large";
    EXPECT_LT(rms, 1.5) << what << ": sigma too small";
  }
}
