// 3DBAG-style building attributes and lower LoDs (issue 36): the roof type of
// known planes, the attributes of reconstructed gable, flat and two-level
// houses (known percentiles, density, RMSE), their LoD 1.2 and 1.3 shells
// closed and valid (check_solid; val3dity where ../shared has it), the data
// quality rule, and the store round trip of both (an older store opens).
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <tuple>

#include "cadastre/store/store.h"
#include "core/check/solid_check.h"
#include "core/config/config.h"
#include "core/geometry/geometry.h"
#include "core/reconstruct/lower_lods.h"
#include "core/reconstruct/reconstruct.h"
#include "tests/export_fixtures.h"
#include "tests/reconstruct_fixtures.h"
#include "tests/test_support.h"
#include "valuation/valuation.h"

using namespace c3d;
using namespace c3d::test;
namespace fx = c3d::fixture;

namespace {

PlaneFit fit_of(const Vec3& at, const Vec3& normal) {
  PlaneFit f;
  f.plane = plane_through(at, normal);
  f.centroid = at;
  f.inliers = 100;
  return f;
}

// The parcel's one building, modelled at LoD 2.2.
Building only_building(const ParcelScene& s) {
  const ParcelResult r = reconstruct_parcel(s, params());
  EXPECT_EQ(r.status, ParcelStatus::Ok) << r.reason;
  EXPECT_EQ(r.buildings.size(), 1u);
  if (r.buildings.empty()) return {};
  EXPECT_EQ(r.buildings[0].lod, Lod::Lod22) << r.buildings[0].lod_note;
  return r.buildings[0];
}

const LodShell* shell_at(const Building& b, Lod lod) {
  for (const auto& s : b.lower_lods)
    if (s.lod == lod) return &s;
  return nullptr;
}

// Each lower LoD closed and valid, one type per face, a roof, walls and a
// ground among them, its volume the closed volume of its faces.
void expect_valid_shells(const Building& b) {
  for (const auto& s : b.lower_lods) {
    const SolidCheck check = check_solid(s.faces);
    EXPECT_TRUE(check.ok) << b.id << " LoD " << to_string(s.lod) << ": " << check.summary();
    ASSERT_EQ(s.face_types.size(), s.faces.size());
    std::map<ElementType, int> n;
    for (ElementType t : s.face_types) ++n[t];
    EXPECT_GE(n[ElementType::Roof], 1);
    EXPECT_GE(n[ElementType::Wall] + n[ElementType::PartyWall], 4);
    EXPECT_EQ(n[ElementType::Ground], 1);
    for (size_t i = 0; i < s.faces.size(); ++i) {
      const double nz = unit_normal(s.faces[i]).z();
      if (s.face_types[i] == ElementType::Roof) EXPECT_GT(nz, 0.99);
      if (s.face_types[i] == ElementType::Ground) EXPECT_LT(nz, -0.99);
      if (s.face_types[i] == ElementType::Wall) EXPECT_LT(std::abs(nz), 0.01);
    }
    EXPECT_NEAR(s.volume, check.volume, 1e-6 * check.volume);
  }
}

// A flat roof at height z over [x0,x1] x [y0,y1], `density` points per m2.
std::vector<Vec3> flat(double z, double x0, double x1, double y0, double y1, double density, unsigned seed) {
  std::mt19937_64 rng(seed);
  return sample_plane(plane_through({0, 0, z}, {0, 0, 1}), x0, x1, y0, y1, density, 0.02, rng);
}

}  // namespace

TEST(LowerLods, RoofTypeFollows3dbag) {
  const PlaneFit low = fit_of({0, 0, 3}, {0, 0, 1}), also_low = fit_of({5, 0, 3.2}, {0.02, 0, 1}),
                 high = fit_of({0, 5, 6}, {0, 0, 1}), pitched = fit_of({0, 0, 5}, {0, 0.75, 1}),
                 drained = fit_of({0, 0, 3}, {0, std::tan(4.0 * M_PI / 180), 1});
  EXPECT_EQ(roof_type_of({low}, 100), "horizontal");
  EXPECT_EQ(roof_type_of({low, also_low, drained}, 100), "horizontal");  // one level, split, drained at 4 deg
  EXPECT_EQ(roof_type_of({low, high}, 100), "multiple horizontal");
  EXPECT_EQ(roof_type_of({low, high, pitched}, 100), "slanted");
  EXPECT_EQ(roof_type_of({}, 100), "could not detect");
  EXPECT_EQ(roof_type_of({}, 0), "no points");
}

TEST(LowerLods, DataQualitySaysWhyNotGood) {
  Building b;
  BuildingAttributes a;
  a.roof_points = 400;
  a.point_density = 8;
  EXPECT_EQ(min_good_density(2.0), 5.0);  // 10 points on the smallest plane kept, 2 m^2
  EXPECT_EQ(data_quality_of(b, a, 5.0), "good");
  a.point_density = 3.25;
  EXPECT_EQ(data_quality_of(b, a, 5.0), "insufficient points (3.2 per m2, LoD 2.2 needs 5.0)");
  b.lod = Lod::Lod13;
  EXPECT_EQ(data_quality_of(b, a, 5.0), "insufficient points (3.2 per m2, LoD 2.2 needs 5.0); lod fallback (1.3)");
  a.roof_points = 0;
  EXPECT_EQ(data_quality_of(b, a, 5.0), "no roof points; lod fallback (1.3)");
}

// The gable house of the fixtures: roof 11 x 9 m (0.5 m overhang) at 40 points
// per m2, ridge 106 m along y = 10, on terrain at 100 m; no wall points, so
// its walls stand the default 0.5 m inside: a 10 x 8 m ground. The points
// over it (and a little beyond: its edge points) have heights uniform between
// their min and max: the percentiles are known, and so is the RMSE of the
// points about the prism's flat top at the 70th.
TEST(LowerLods, GableHouseIsSlantedWithKnownHeightsAndShells) {
  std::mt19937_64 rng(31);
  ParcelScene s = square_parcel_scene();
  s.roof_points = gable_points(rng);
  const Building b = only_building(s);
  const BuildingAttributes& a = b.attributes;
  EXPECT_EQ(a.roof_type, "slanted");
  EXPECT_EQ(a.data_quality, "good");
  EXPECT_GE(a.roof_points, long(78 * 40 * 0.95));                  // over the 10 x 8 m ground...
  EXPECT_LE(a.roof_points, long(0.95 * double(s.roof_points.size())));  // ...not the whole overhang
  EXPECT_GE(a.roof_z_min, 102.625);   // the eave's points
  EXPECT_LE(a.roof_z_min, 103.0 + 0.05);  // the wall line's
  EXPECT_NEAR(a.roof_z_max, 106, 0.08);
  const double lo = a.roof_z_min, span = a.roof_z_max - a.roof_z_min;
  EXPECT_NEAR(a.roof_z_50p, lo + 0.5 * span, 0.05);
  EXPECT_NEAR(a.roof_z_70p, lo + 0.7 * span, 0.05);
  EXPECT_NEAR(a.point_density, 40, 3);
  EXPECT_LT(a.roof_rmse, 0.1);  // the LoD 2.2 planes fit the points to their noise

  ASSERT_EQ(b.lower_lods.size(), 2u);
  EXPECT_EQ(b.lower_lods[0].lod, Lod::Lod12);
  EXPECT_EQ(b.lower_lods[1].lod, Lod::Lod13);
  expect_valid_shells(b);
  const LodShell& prism = b.lower_lods[0];
  // RMSE of a uniform height about its 70th percentile: span * sqrt(1/12 + 0.2^2).
  EXPECT_NEAR(prism.roof_rmse, span * std::sqrt(1.0 / 12 + 0.04), 0.05);
  EXPECT_NEAR(totals(b).ground, 80, 2);
  const double on_ground = totals(b).ground * (a.roof_z_70p - 100);  // the prism stands on the LoD 2.2 ground
  EXPECT_NEAR(prism.volume, on_ground, 1e-6 * on_ground);
  EXPECT_LE(b.lower_lods[1].roof_rmse, prism.roof_rmse + 1e-9);  // layers fit no worse than one prism

  const std::string path = test::temp_dir("lower_lods_gable") + "/shells.city.json";
  std::vector<NamedSolid> shells;
  for (const auto& s : b.lower_lods) shells.push_back({b.id + "_lod" + to_string(s.lod), to_string(s.lod), s.faces});
  write_solids_cityjson(shells, path);
  const auto invalid = test::val3dity_invalid(path);
  C3D_NEED(invalid, "../shared/tools/val3dity not found");
  EXPECT_TRUE(invalid->empty()) << invalid->front();
}

TEST(LowerLods, FlatRoofIsHorizontal) {
  ParcelScene s = square_parcel_scene();
  s.roof_points = flat(103, 3, 17, 2, 10, 40, 32);
  const Building b = only_building(s);
  EXPECT_EQ(b.attributes.roof_type, "horizontal");
  EXPECT_NEAR(b.attributes.roof_z_50p, 103, 0.01);
  EXPECT_NEAR(b.attributes.roof_z_70p, 103, 0.02);
  EXPECT_EQ(b.attributes.data_quality, "good");
  ASSERT_NE(shell_at(b, Lod::Lod12), nullptr);
  ASSERT_NE(shell_at(b, Lod::Lod13), nullptr);
  EXPECT_LT(shell_at(b, Lod::Lod12)->roof_rmse, 0.05);
  expect_valid_shells(b);
}

// A flat roof at 106 m over x 5..11 beside one at 103 m over x 11..17 (y 4..12):
// two levels of one building; its LoD 1.3 has both, its prism one top.
TEST(LowerLods, TwoFlatLevelsAreMultipleHorizontalWithTwoLayers) {
  ParcelScene s = square_parcel_scene();
  s.roof_points = flat(106, 5, 11, 4, 12, 40, 33);
  const auto low = flat(103, 11, 17, 4, 12, 40, 34);
  s.roof_points.insert(s.roof_points.end(), low.begin(), low.end());
  const Building b = only_building(s);
  EXPECT_EQ(b.attributes.roof_type, "multiple horizontal");
  EXPECT_NEAR(b.attributes.roof_z_min, 103, 0.1);
  EXPECT_NEAR(b.attributes.roof_z_max, 106, 0.1);
  const LodShell* layers = shell_at(b, Lod::Lod13);
  ASSERT_NE(layers, nullptr);
  ASSERT_NE(shell_at(b, Lod::Lod12), nullptr);
  int roofs = 0;
  for (ElementType t : layers->face_types) roofs += t == ElementType::Roof;
  EXPECT_EQ(roofs, 2);
  EXPECT_LT(layers->roof_rmse, 0.1);                      // each level on its layer
  EXPECT_GT(shell_at(b, Lod::Lod12)->roof_rmse, 1.0);          // one top between them
  // On the LoD 2.2 ground (x0..x1, y0..y1), the step at x = 11.
  double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
  for (const auto& e : b.elements)
    if (e.type == ElementType::Ground)
      for (const auto& v : e.faces.front().ring)
        x0 = std::min(x0, v.x()), x1 = std::max(x1, v.x()), y0 = std::min(y0, v.y()), y1 = std::max(y1, v.y());
  const double want = (11 - x0) * (y1 - y0) * 6 + (x1 - 11) * (y1 - y0) * 3;
  EXPECT_NEAR(layers->volume, want, 0.05 * want);
  expect_valid_shells(b);
}

TEST(LowerLods, SparseRoofIsFlaggedInsufficient) {
  ParcelScene s = square_parcel_scene();
  s.roof_points = flat(103, 3, 17, 2, 10, 3, 35);  // 3 points per m2 (5 needed)
  const ParcelResult r = reconstruct_parcel(s, params());
  ASSERT_EQ(r.status, ParcelStatus::Ok) << r.reason;
  ASSERT_EQ(r.buildings.size(), 1u);
  const BuildingAttributes& a = r.buildings[0].attributes;
  EXPECT_NEAR(a.point_density, 3, 0.6);
  EXPECT_EQ(a.data_quality.rfind("insufficient points (", 0), 0u) << a.data_quality;
}

// Two 8 x 8 m houses under one flat roof plane (joined by a 2 x 1 m walkway
// roof, their footprint comes apart under it): each house's attributes count
// the points over its own footprint, not its sibling's on the shared plane.
TEST(LowerLods, HousesSharingARoofPlaneCountTheirOwnPoints) {
  std::mt19937_64 rng(37);
  const Plane roof = plane_through({0, 0, 103}, {0, 0.02, 1});
  ParcelScene s = square_parcel_scene();
  s.roof_points = sample_plane(roof, 1, 9, 6, 14, 40, 0.02, rng);
  for (auto part : {sample_plane(roof, 11, 19, 6, 14, 40, 0.02, rng), sample_plane(roof, 9, 11, 9.5, 10.5, 40, 0.02, rng)})
    s.roof_points.insert(s.roof_points.end(), part.begin(), part.end());
  const ParcelResult r = reconstruct_parcel(s, params());
  ASSERT_EQ(r.status, ParcelStatus::Ok) << r.reason;
  ASSERT_EQ(r.buildings.size(), 2u);
  for (const auto& b : r.buildings) {
    EXPECT_LE(double(b.attributes.roof_points), 1.1 * 64 * 40) << b.id;  // not its sibling's too
    EXPECT_NEAR(b.attributes.point_density, 40, 4) << b.id;
    EXPECT_EQ(b.attributes.roof_type, "horizontal");
    ASSERT_NE(shell_at(b, Lod::Lod12), nullptr);
    const double want = totals(b).ground * (b.attributes.roof_z_70p - 100);  // on the LoD 2.2 ground
    EXPECT_NEAR(shell_at(b, Lod::Lod12)->volume, want, 1e-6 * want) << b.id;
  }
}

namespace {

// The export fixtures' batch with the gable house's attributes and shells on
// its first building.
BatchModel batch_with_lods(Building& modelled) {
  std::mt19937_64 rng(36);
  ParcelScene s = square_parcel_scene();
  s.roof_points = gable_points(rng);
  modelled = only_building(s);
  BatchModel m = fx::sample_batch();
  Building& b = m.results.front().buildings.front();
  b.attributes = modelled.attributes;
  b.lower_lods = modelled.lower_lods;
  return m;
}

}  // namespace

TEST(LowerLods, StoreKeepsAttributesAndShellsAndAnOlderStoreOpens) {
  Building modelled;
  const BatchModel m = batch_with_lods(modelled);
  ASSERT_EQ(modelled.lower_lods.size(), 2u);
  const std::string path = write_store(test::temp_dir("lower_lods_store") + "/cadastre.gpkg", m);
  BatchModel back = load_batch_model(path);
  const Building& b = back.results.front().buildings.front();
  const BuildingAttributes &a = b.attributes, &want = modelled.attributes;
  EXPECT_EQ(a.roof_type, want.roof_type);
  EXPECT_EQ(a.data_quality, want.data_quality);
  EXPECT_EQ(a.roof_points, want.roof_points);
  for (auto [got, wanted] : {std::pair{a.roof_z_min, want.roof_z_min}, {a.roof_z_50p, want.roof_z_50p},
                             {a.roof_z_70p, want.roof_z_70p}, {a.roof_z_max, want.roof_z_max},
                             {a.point_density, want.point_density}, {a.roof_rmse, want.roof_rmse}})
    EXPECT_NEAR(got, wanted, 1e-6);
  ASSERT_EQ(b.lower_lods.size(), 2u);
  for (size_t k = 0; k < 2; ++k) {
    const LodShell &s = b.lower_lods[k], &w = modelled.lower_lods[k];
    EXPECT_EQ(s.lod, w.lod);
    EXPECT_EQ(s.face_types, w.face_types);
    ASSERT_EQ(s.faces.size(), w.faces.size());
    for (size_t f = 0; f < s.faces.size(); ++f)
      for (size_t v = 0; v < s.faces[f].ring.size(); ++v) EXPECT_LT((s.faces[f].ring[v] - w.faces[f].ring[v]).norm(), 1e-6);
    EXPECT_NEAR(s.volume, w.volume, 1e-9);
    EXPECT_NEAR(s.roof_rmse, w.roof_rmse, 1e-9);
    EXPECT_TRUE(check_solid(s.faces).ok);
  }
  // A building without them reads back without them.
  const Building& plain = back.results[1].buildings.front();
  EXPECT_EQ(plain.attributes.roof_type, "");
  EXPECT_TRUE(std::isnan(plain.attributes.roof_z_70p));
  EXPECT_TRUE(plain.lower_lods.empty());

  // A store written before they existed opens without them, and takes them
  // when a batch writes into it again.
  sql_exec(path,
      "DROP TABLE building_lod; ALTER TABLE building DROP COLUMN roof_type; "
      "ALTER TABLE building DROP COLUMN data_quality;");
  back = load_batch_model(path);
  EXPECT_EQ(back.results.front().buildings.front().attributes.roof_type, "");
  EXPECT_TRUE(back.results.front().buildings.front().lower_lods.empty());
  write_store(path, m);
  back = load_batch_model(path);
  EXPECT_EQ(back.results.front().buildings.front().attributes.roof_type, want.roof_type);
  EXPECT_EQ(back.results.front().buildings.front().lower_lods.size(), 2u);
}
